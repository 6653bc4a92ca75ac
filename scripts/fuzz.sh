#!/usr/bin/env bash
# Fuzzes every reader of outside data with libFuzzer (clang, address + undefined
# sanitizers) for SECONDS each (default 30), starting from the committed seeds
# (tests/fuzz/corpus/<target>/, plus the map archive and rawlog seeds written by
# fuzz_make_seeds) and each format's dictionary (tests/fuzz/dict/).
#   scripts/fuzz.sh [SECONDS] [TARGET...]        e.g. scripts/fuzz.sh 20; scripts/fuzz.sh 600 fuzz_npz
# Build: build-fuzz/ (clang++-14, PNDT_BUILD_FUZZERS=ON, only the libraries the readers need).
# Corpora grow in build-fuzz/corpus/<target>/; a crash, leak, timeout or allocation over the
# limits leaves its input in build-fuzz/artifacts/ and fails the script. Allocation limits:
# -rss_limit_mb=2048 -malloc_limit_mb=1024, so a header claiming a huge image or voxel count
# must be refused before allocating. Prints one line per target: executions, coverage, result.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH="${1:-30}"
shift || true
ALL=(fuzz_npy fuzz_npz fuzz_pose_text fuzz_json fuzz_image fuzz_ini fuzz_map_archive fuzz_rawlog)
[ $# -gt 0 ] && TARGETS=("$@") || TARGETS=("${ALL[@]}")
B=build-fuzz
# FUZZ_WITH_TESTS=1: the same build also compiles the reader libraries' own tests (tests/core,
# tests/io, tests/mrpt) and tests/sim (built with clang: the generated rooms must not depend on
# the compiler) under ASan + UBSan, for scripts/test_sanitized.sh ci (run there).
WITH_TESTS="${FUZZ_WITH_TESTS:-0}"
CXX="${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++)}"
LAUNCHER=()
command -v ccache > /dev/null && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
EXCLUDE="libs/pndt_sim;libs/pndt_data;libs/pndt_eval;libs/pndt_nav;libs/pndt_seg;libs/pndt_app;libs/pndt_live"
for a in apps/*/; do EXCLUDE="$EXCLUDE;${a%/}"; done
TESTS=OFF
if [ "$WITH_TESTS" = 1 ]; then
    TESTS=ON
    EXCLUDE="${EXCLUDE/libs\/pndt_sim;/}"  # tests/core maps generated frames
    for t in tests/*/; do
        # tests/sim: the generated rooms must not depend on the compiler (IndoorScenePinned).
        case "${t%/}" in tests/core | tests/io | tests/mrpt | tests/sim | tests/fuzz) ;; *) EXCLUDE="$EXCLUDE;${t%/}" ;; esac
    done
fi
if true; then  # (re)configure: keeps the cache in step with this script
    # RelWithDebInfo with libFuzzer's recommended -O1 and line tables; assertions stay on.
    cmake -S . -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" \
        -DCMAKE_CXX_COMPILER="$CXX" "${LAUNCHER[@]}" -DPNDT_BUILD_TESTS=$TESTS -DPNDT_BUILD_FUZZERS=ON "-DPNDT_EXCLUDE=$EXCLUDE" \
        "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
        "-DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=address,undefined" > /dev/null
fi
if [ "$WITH_TESTS" = 1 ]; then
    cmake --build "$B" -j"${JOBS:-2}"
else
    cmake --build "$B" -j"${JOBS:-2}" --target "${TARGETS[@]}" fuzz_make_seeds
fi
mkdir -p "$B/corpus" "$B/artifacts" "$B/seeds"
"$B/bin/fuzz_make_seeds" "$B/seeds" > /dev/null
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$(pwd)/scripts/sanitizers/lsan.supp:print_suppressions=0}"
failed=0
printf '%-18s %10s %8s %8s %8s %s\n' target execs exec/s cov corpus result
for t in "${TARGETS[@]}"; do
    name="${t#fuzz_}"
    work="$B/corpus/$name"
    mkdir -p "$work"
    seeds=()
    for s in tests/fuzz/corpus/"$name" "$B/seeds/$name"; do [ -d "$s" ] && seeds+=("$s"); done
    dict=()
    [ -f "tests/fuzz/dict/$name.dict" ] && dict=(-dict="tests/fuzz/dict/$name.dict")
    log="$B/artifacts/$t.log"
    limits=(-rss_limit_mb=2048 -malloc_limit_mb=1024)
    # Every target runs as it is: the rawlog reader checks each object's sizes before MRPT
    # allocates them (libs/pndt_app/src/rawlog_object_check.cpp), so an allocation over the
    # limits is a finding there too (it used to need -fork=1 -ignore_ooms=1 and
    # allocator_may_return_null=1, see doc/hardening.md).
    set +e
    "$B/bin/$t" "$work" "${seeds[@]}" "${dict[@]}" -max_total_time="$SECONDS_EACH" -timeout=10 \
        "${limits[@]}" -max_len=65536 -print_final_stats=1 \
        -artifact_prefix="$B/artifacts/$t-" > "$log" 2>&1
    rc=$?
    set -e
    execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
    rate=$(grep -oE 'stat::average_exec_per_sec: *[0-9]+' "$log" | tail -1 | grep -oE '[0-9]+$' || echo 0)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo 0)
    corp=$(grep -o 'corp: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo 0)
    if [ $rc -eq 0 ]; then result=ok; else result="FAILED (rc $rc, $log)"; failed=1; fi
    printf '%-18s %10s %8s %8s %8s %s\n' "$t" "$execs" "$rate" "$cov" "$corp" "$result"
    [ $rc -eq 0 ] || grep -m3 -E "ERROR|SUMMARY|runtime error|out-of-memory" "$log" | sed "s/^/    /" || true
done
exit $failed
