#!/usr/bin/env bash
# Soak run (doc/hardening.md): a generated scene replayed in a loop for MINUTES (default 60)
# into short-term maps every 3 sensor seconds; prints RSS (slope after warm-up), file
# descriptors, threads, and whether every map file loads. Not run by CI.
#   scripts/soak.sh [MINUTES] [BUILD_DIR]        (BUILD_DIR default build, must exist)
set -euo pipefail
cd "$(dirname "$0")/.."
MINUTES="${1:-60}"
B="${2:-build}"
cmake --build "$B" -j"${JOBS:-2}" --target pndt_soak pndt-generate
SCENE=out/soak/scene/synth_small_cam_01.rawlog
[ -f "$SCENE" ] || "$B/bin/pndt-generate" -n 120 --formats rawlog -o out/soak/scene > /dev/null
"$B/bin/pndt_soak" "$SCENE" --minutes "$MINUTES" --period 3 --sample 10 -o out/soak/maps | tee out/soak/soak.log
