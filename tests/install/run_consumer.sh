#!/usr/bin/env bash
# Installs the build into a temporary prefix, then configures, builds and runs an outside project
# (tests/install/consumer) against it with find_package(PanopticNDT) only.
# Usage: run_consumer.sh BUILD_DIR CONSUMER_SOURCE_DIR
set -euo pipefail
BUILD=$1
SRC=$2
WORK=$(mktemp -d "${TMPDIR:-/tmp}/pndt-install-test.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cmake --install "$BUILD" --prefix "$WORK/prefix" > "$WORK/install.log"
for f in include/pndt/build_config.h include/pndt/panoptic_map.h lib/libpndt_mrpt_plugin.so \
         lib/cmake/PanopticNDT/PanopticNDTConfig.cmake bin/pndt-map share/panopticndt/config/panoptic_ndt.ini; do
  [ -e "$WORK/prefix/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done
cmake -S "$SRC" -B "$WORK/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$WORK/prefix" > "$WORK/configure.log" \
  || { cat "$WORK/configure.log" >&2; exit 1; }
cmake --build "$WORK/build" > "$WORK/build.log" || { cat "$WORK/build.log" >&2; exit 1; }
"$WORK/build/consumer"
# The installed app finds its installed config (not the source tree's).
"$WORK/prefix/bin/pndt-map" --help > /dev/null
echo "installed into $WORK/prefix, consumer built and run"
