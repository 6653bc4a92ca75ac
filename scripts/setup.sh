#!/usr/bin/env bash
# Installs the Debian 12 packages PanopticNDT needs and builds it (Release, with tests).
# Usage: scripts/setup.sh [build-dir]        (default: build)
# Set PNDT_SKIP_APT=1 to skip the apt step (packages already installed), PNDT_HARDENING=1 to
# also install the fuzzing / sanitizer compilers.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libmrpt-dev mrpt-apps            # MRPT 2.5: maps, obs, opengl, serialisation; rawlog-edit & co.
  libeigen3-dev robin-map-dev      # math; the voxel hash map
  libopencv-dev                    # image codecs (PNG depth, colour); DNN for the segmentation front-end
  python3-onnx python3-numpy       # tiny ONNX test models, written at build time (tests/seg)
  libfmt-dev libcli11-dev nlohmann-json3-dev zlib1g-dev
  libceres-dev                     # frame-to-map pose refinement (libs/pndt_refine)
  libopenni2-dev                   # OpenNI2 RGB-D capture for pndt-live and its virtual camera driver
  libgtest-dev liboctomap-dev     # OctoMap, for the side-by-side benchmark
  libegl-mesa0 libgl1-mesa-dri     # off-screen rendering of 3D views (EGL, no display)
  xvfb xauth x11-utils             # a virtual display for the interactive viewer (xwininfo: RawLogViewer test)
  file                             # CPack's .deb dependency scan (dpkg-shlibdeps), the install_deb_consumer test
)

# PNDT_HARDENING=1 adds clang and libFuzzer for scripts/fuzz.sh and scripts/test_sanitized.sh
# (CI sets it; doc/hardening.md).
if [ "${PNDT_HARDENING:-0}" = 1 ]; then
  PACKAGES+=(clang libclang-rt-14-dev)
fi

if [ "${PNDT_SKIP_APT:-0}" != 1 ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "[setup] installing: ${missing[*]}"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
  else
    echo "[setup] all Debian packages present"
  fi
fi

cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPNDT_BUILD_TESTS=ON
cmake --build "$BUILD_DIR" -j"$(nproc)"
echo "[setup] built into $BUILD_DIR/bin"
