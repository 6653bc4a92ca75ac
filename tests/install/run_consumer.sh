#!/usr/bin/env bash
# Installs the build into a temporary prefix, then configures, builds and runs an outside project
# (tests/install/consumer) against it with find_package(PanopticNDT) only.
# With --deb the prefix is the Debian package instead: `cpack -G DEB`, its control fields checked,
# then unpacked (dpkg-deb -x) and used as the prefix.
# Usage: run_consumer.sh BUILD_DIR CONSUMER_SOURCE_DIR [--deb]
set -euo pipefail
BUILD=$1
SRC=$2
MODE=${3:-install}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/pndt-install-test.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
if [ "$MODE" = --deb ]; then
  (cd "$WORK" && cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$WORK/pkg" > "$WORK/cpack.log" 2>&1) \
    || { cat "$WORK/cpack.log" >&2; exit 1; }
  DEB=$(ls "$WORK"/pkg/panopticndt_*.deb)
  [ "$(dpkg-deb -f "$DEB" Package)" = panopticndt ] || { echo "package name: $(dpkg-deb -f "$DEB" Package)" >&2; exit 1; }
  DEPENDS=$(dpkg-deb -f "$DEB" Depends)
  # The -dev packages find_package needs, and runtime libraries found by dpkg-shlibdeps.
  for dep in libmrpt-dev libceres-dev libopencv-dev libc6 libstdc++6 libmrpt-maps; do
    case "$DEPENDS" in *"$dep"*) ;; *) echo "$DEB: Depends lacks $dep: $DEPENDS" >&2; exit 1 ;; esac
  done
  dpkg-deb -x "$DEB" "$WORK/root"
  PREFIX="$WORK/root/usr"
else
  cmake --install "$BUILD" --prefix "$WORK/prefix" > "$WORK/install.log"
  PREFIX="$WORK/prefix"
fi
for f in include/pndt/build_config.h include/pndt/panoptic_map.h lib/libpndt_mrpt_plugin.so \
         lib/cmake/PanopticNDT/PanopticNDTConfig.cmake bin/pndt-map share/panopticndt/config/panoptic_ndt.ini \
         share/panopticndt/config/reactive2d.ini; do
  [ -e "$PREFIX/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done
cmake -S "$SRC" -B "$WORK/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$PREFIX" \
  -DPNDT_EMBEDDING_EXAMPLE="$(cd "$SRC/../../../doc/examples" && pwd)/embedding_example.cpp" > "$WORK/configure.log" \
  || { cat "$WORK/configure.log" >&2; exit 1; }
cmake --build "$WORK/build" > "$WORK/build.log" || { cat "$WORK/build.log" >&2; exit 1; }
"$WORK/build/consumer"
"$WORK/build/ini_only"
"$WORK/build/embedding_example" > "$WORK/example.log" || { cat "$WORK/example.log" >&2; echo "the embedding example failed" >&2; exit 1; }
# The installed app finds its installed config (not the source tree's).
"$PREFIX/bin/pndt-map" --help > /dev/null
# pndt-nav's navigator settings (--planner tps, --simulate) come from the installed config too.
NAV_HELP=$("$PREFIX/bin/pndt-nav" --help)
case "$NAV_HELP" in *share/panopticndt/config/reactive2d.ini*) ;;
  *) echo "$NAV_HELP" >&2; echo "pndt-nav does not default to the installed reactive2d.ini" >&2; exit 1 ;; esac
# pndt-demo too: it read the source tree's panoptic_ndt.ini, so a robot without the tree failed.
DEMO_HELP=$("$PREFIX/bin/pndt-demo" --help)
case "$DEMO_HELP" in *share/panopticndt/config/panoptic_ndt.ini*) ;;
  *) echo "$DEMO_HELP" >&2; echo "pndt-demo does not default to the installed panoptic_ndt.ini" >&2; exit 1 ;; esac
echo "installed into $PREFIX ($MODE), consumer built and run"
