#!/usr/bin/env bash
# Soak run (doc/hardening.md): a generated scene replayed in a loop for MINUTES (default 60);
# prints RSS (slope after warm-up), file descriptors and threads.
#   MODE short-term (default): short-term maps every 3 sensor seconds; every map file must load.
#   MODE one-map: one map never replaced, a CMultiMetricMap from config/panoptic_ndt.ini (an
#     MRPT app embedding the plugin); also its voxels, instance records, frames-seen entries and
#     id counter; at the end the map is saved and must load back as saved.
# Not run by CI.
#   scripts/soak.sh [MINUTES] [BUILD_DIR] [MODE]        (BUILD_DIR default build, must exist)
set -euo pipefail
cd "$(dirname "$0")/.."
MINUTES="${1:-60}"
B="${2:-build}"
MODE="${3:-short-term}"
cmake --build "$B" -j"${JOBS:-2}" --target pndt_soak pndt-generate
SCENE=out/soak/scene/synth_small_cam_01.rawlog
[ -f "$SCENE" ] || "$B/bin/pndt-generate" -n 120 --formats rawlog -o out/soak/scene > /dev/null
case "$MODE" in
  short-term) EXTRA=() ;;
  one-map) EXTRA=(--one-map config/panoptic_ndt.ini) ;;
  *) echo "soak.sh: unknown MODE '$MODE' (short-term or one-map)" >&2; exit 2 ;;
esac
"$B/bin/pndt_soak" "$SCENE" --minutes "$MINUTES" --period 3 --sample 10 "${EXTRA[@]}" -o "out/soak/$MODE" \
  | tee "out/soak/soak-$MODE.log"
