#!/usr/bin/env bash
# README's main command: install + build (scripts/setup.sh), generate the bundled
# synthetic scene, and replay it with pndt-map into short-term panoptic maps.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
mkdir -p out
# The bundled scene: a furnished room, 60 RGB-D frames at 640x480 along a hand-held
# walk, with network-like (calibrated, noisy) panoptic labels and poses, as a rawlog.
./build/bin/pndt-generate --scene small --frames 60 --formats rawlog,gt --out out/scene
# The main job: replay it with the rawlog's poses into 4-second short-term maps.
./build/bin/pndt-map out/scene/synth_small_cam_01.rawlog -o out/map --period 4 \
    --screenshot out/map/3d_view.png --mesh-screenshot out/map/3d_mesh_view.png "$@"
echo
echo "Maps: out/map/map_*.pndt.gz (+ .ply), index.json, instances.json;"
echo "pictures: out/map/view_*.png (with class legends), floor_plan.png, 3d_view.png, 3d_mesh_view.png; input: out/scene/"
