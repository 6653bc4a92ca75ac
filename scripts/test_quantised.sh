#!/usr/bin/env bash
# The core's and the map file's tests once more with quantised histogram
# weights (CMake option PNDT_QUANTISED_HISTOGRAMS), in their own build folder:
# the record layout is fixed at build time, so the default build cannot cover it.
# Usage: scripts/test_quantised.sh [build folder, default build-quantised]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${1:-build-quantised}"
TESTS=(test_core_units test_core_map test_core_threads test_core_alloc test_plugin)
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPNDT_BUILD_TESTS=ON \
    -DPNDT_QUANTISED_HISTOGRAMS=ON > /dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)" --target "${TESTS[@]}"
for t in "${TESTS[@]}"; do
    echo "== $t (quantised histogram weights)"
    "$BUILD_DIR/bin/$t" --gtest_brief=1
done
