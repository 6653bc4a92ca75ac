#!/usr/bin/env bash
# Soak of pndt-live (doc/hardening.md): the live pipeline as on a robot, for MINUTES (default
# 60) - the OpenNI2 virtual camera (libs/pndt_oni_virtual, loaded by the OpenNI2 runtime) at
# 640x480 and 30 frames/s, poses streamed over TCP by pndt-pose-send at the camera's pace,
# tests/seg's tiny panoptic network as the segmentation, short-term maps every 3 s.
# `pndt_soak --watch` samples pndt-live's RSS, file descriptors and threads every 10 s, prints
# the figures after warm-up and loads every map file written. Not run by CI.
#   scripts/soak_live.sh [MINUTES] [BUILD_DIR] [PNDT-LIVE ARGS...]   (BUILD_DIR default build, must exist)
# e.g. scripts/soak_live.sh 60 build --keep-maps 20   (the map files on disk bounded)
# MODEL=models/centernet_coco.json (scripts/get_models.sh) runs the real COCO detector instead;
# OUT=<folder> (default out/soak/live, emptied first) lets two soaks run side by side;
# WRAP="heaptrack -o <file>" (or another launcher) runs pndt-live under it (the watch follows
# pndt-live itself).
set -euo pipefail
cd "$(dirname "$0")/.."
MINUTES="${1:-60}"
B="$(cd "${2:-build}" && pwd)"
cmake --build "$B" -j"${JOBS:-2}" --target pndt-live pndt-pose-send pndt-virtual-camera pndt_soak \
  pndt_oni_virtual_driver pndt_seg_test_models
D="$(realpath -m "${OUT:-out/soak/live}")"
rm -rf "$D"
mkdir -p "$D"
RUN_SECONDS=$((MINUTES * 60))
cat > "$D/camera.cfg" <<CFG
width = 640
height = 480
fps = 30
loop_frames = 120
pose_seconds = $((RUN_SECONDS + 120))
CFG
"$B/bin/pndt-virtual-camera" --config "$D/camera.cfg" --write-poses "$D/poses.txt" > /dev/null
cat > "$D/model.json" <<JSON
{"format": "pndt-segmentation-model/1", "name": "tiny", "onnx": "$B/tests/seg/models/panoptic_tiny.onnx",
 "kind": "panoptic", "input_size": [16, 12],
 "inputs": [{"name": "rgb", "kind": "rgb", "scale": 0.003921568627451},
            {"name": "depth", "kind": "depth", "mean": [2], "std": [10]}],
 "outputs": {"semantic": "semantic", "center": "center", "offset": "offset"},
 "classes": ["void", "wall", "chair", "table"],
 "postprocess": {"center_threshold": 0.1, "nms_kernel": 3, "top_k": 8, "offset_order": "yx", "offset_scale": 2}}
JSON
MODEL="$(realpath "${MODEL:-$D/model.json}")"
PORT="${PORT:-$((20000 + RANDOM % 20000))}"
PNDT_VIRTUAL_CAMERA="$D/camera.cfg" LD_LIBRARY_PATH="$B/lib/openni2-virtual" \
  ${WRAP:-} "$B/bin/pndt-live" --pose-tcp "$PORT" --pose-format tum --model "$MODEL" --seconds "$RUN_SECONDS" \
  --period 3 -o "$D/maps" "${@:3}" > "$D/live.out" 2> "$D/live.err" &
LIVE=$!
WATCH="$LIVE"
if [ -n "${WRAP:-}" ]; then  # the launcher's child (or grandchild) named pndt-live
  for _ in $(seq 100); do
    WATCH="$(for p in $(pgrep -f -- "-o $D/maps" || true); do
      if [ "$(cat "/proc/$p/comm" 2> /dev/null)" = pndt-live ]; then echo "$p"; fi; done)"
    [ -n "$WATCH" ] && break
    sleep 0.1
  done
  [ -n "$WATCH" ] || { echo "no pndt-live under WRAP='$WRAP'"; exit 1; }
fi
"$B/bin/pndt-pose-send" "$D/poses.txt" --to "127.0.0.1:$PORT" --connect-timeout 120 > "$D/send.out" 2>&1 &
SEND=$!
STATUS=0
"$B/bin/pndt_soak" --watch "$WATCH" --maps "$D/maps" --sample 10 | tee "$D/soak.log" || STATUS=$?
LIVE_STATUS=0
wait "$LIVE" || LIVE_STATUS=$?
kill "$SEND" 2> /dev/null || true
wait "$SEND" 2> /dev/null || true
echo "pndt-live exit $LIVE_STATUS; its summary:"
cat "$D/live.out"
[ "$LIVE_STATUS" -eq 0 ] || { echo "pndt-live failed:"; tail -20 "$D/live.err"; exit 1; }
exit "$STATUS"
