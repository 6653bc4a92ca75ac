#!/usr/bin/env bash
# Fault tests of pndt-map's outputs (ctest label `faults`, doc/hardening.md):
#   kill9     kill -9 at KILLS (default 50) random moments of a replay writing short-term maps
#             every 0.2 s into the same folder: after each kill every map_*.pndt.gz present
#             loads and index.json is valid JSON listing only complete maps.
#   full      the output folder on a full disk: a 512 KiB tmpfs when mounting is allowed (root),
#             run with 0 / 250 / 320 / 424 / 450 / 472 / 480 KiB of it taken (so a map archive
#             meets the full disk first in some runs, a PLY or maps.rawlog in others); else a
#             per-file size limit (ulimit -f with SIGXFSZ ignored, so writes fail with EFBIG as
#             on a full disk). Exit code 3, an error naming the file and the reason, no temporary
#             file left, index.json valid and its maps complete.
#   readonly  a folder holding earlier maps made read-only (a read-only bind mount when
#             allowed, else running as user nobody, else chmod a-w): exit code 3, an error
#             naming the file, the earlier maps byte-identical.
# Usage: faults.sh MODE PNDT_MAP PNDT_GENERATE CHECK_MAP_DIR WORKDIR
set -uo pipefail
MODE=$1 MAP=$2 GEN=$3 CHECK=$4 W=$5
mkdir -p "$W"
fail() { echo "FAIL ($MODE): $*"; exit 1; }

# One small generated scene shared by the modes (generated once, under a lock).
(
    flock 9
    if ! ls "$W"/scene/*.rawlog > /dev/null 2>&1; then
        "$GEN" -n 24 --formats rawlog --threads 1 --seed 3 -o "$W/scene.tmp" > "$W/generate.log" 2>&1 ||
            { cat "$W/generate.log"; exit 1; }
        rm -rf "$W/scene" && mv "$W/scene.tmp" "$W/scene"
    fi
) 9> "$W/.scene.lock" || fail "could not generate the scene"
SCENE=$(ls "$W"/scene/*.rawlog | head -1)
run_map() { "$MAP" "$SCENE" --period 0.2 --no-progress "$@"; }

case "$MODE" in
kill9)
    KILLS=${KILLS:-50}
    out="$W/kill9"
    rm -rf "$out"
    RANDOM=${SEED:-23}
    kills_during_run=0
    for i in $(seq 1 "$KILLS"); do
        delay=$(printf '0.%03d' $((RANDOM % 1000)))
        [ $((RANDOM % 3)) -eq 0 ] && delay="1.$(printf '%03d' $((RANDOM % 1000)))"
        # A simple command, so $! is pndt-map itself (not a subshell that would survive as its parent)
        "$MAP" "$SCENE" --period 0.2 --no-progress -o "$out" > "$W/kill9.log" 2>&1 &
        pid=$!
        sleep "$delay"
        kill -9 "$pid" 2> /dev/null && kills_during_run=$((kills_during_run + 1))
        wait "$pid" 2> /dev/null
        "$CHECK" "$out" > "$W/kill9_check.log" 2>&1 || { cat "$W/kill9_check.log"; fail "after kill $i at ${delay} s"; }
    done
    # The kills must have hit a running mapper that wrote maps (not, say, one that stopped at once
    # on a configuration error).
    [ "$kills_during_run" -ge $((KILLS / 2)) ] || { cat "$W/kill9.log"; fail "only $kills_during_run kills hit a running pndt-map"; }
    "$CHECK" "$out" --min-maps 1 > "$W/kill9_check.log" 2>&1 || { cat "$W/kill9_check.log" "$W/kill9.log"; fail "no map was written"; }
    echo "kill9: $KILLS kills ($kills_during_run while running), every map present loads, index.json valid: $(cat "$W/kill9_check.log")"
    ;;
full)
    d="$W/full"
    # Space left when the run starts (KiB of the tmpfs pre-filled): which file meets the full
    # disk first (a map file or maps.rawlog) depends on it, so both are met.
    for fill in 0 250 320 424 450 472 480; do
        umount "$d" 2> /dev/null
        rm -rf "$d" && mkdir -p "$d"
        if mount -t tmpfs -o size=512k tmpfs "$d" 2> /dev/null; then
            method="tmpfs of 512 KiB, $fill KiB taken"
            [ "$fill" -gt 0 ] && head -c "${fill}k" /dev/zero > "$d/filler"
            run_map -o "$d/map" > "$W/full.log" 2>&1
            rc=$?
        else
            method="ulimit -f 160 (KiB per file, SIGXFSZ ignored)"
            (trap '' XFSZ; ulimit -f 160; run_map -o "$d/map") > "$W/full.log" 2>&1
            rc=$?
        fi
        "$CHECK" "$d/map" --no-tmp > "$W/full_check.log" 2>&1
        check=$?
        mounted=0
        mountpoint -q "$d" && mounted=1 && umount "$d"
        [ $rc -eq 3 ] || { cat "$W/full.log"; fail "exit code $rc, expected 3 ($method)"; }
        grep -q "error: .*$d/map/" "$W/full.log" || { cat "$W/full.log"; fail "the error does not name the file ($method)"; }
        grep -qE "No space left on device|File too large" "$W/full.log" || { cat "$W/full.log"; fail "the error does not say why ($method)"; }
        [ $check -eq 0 ] || { cat "$W/full_check.log"; fail "output folder damaged ($method)"; }
        echo "full ($method): exit 3, $(grep -m1 "error:" "$W/full.log"); $(cat "$W/full_check.log")"
        [ $mounted -eq 1 ] || break  # the per-file limit does not depend on the space left
    done
    ;;
readonly)
    d="$W/ro"
    umount "$d/map" 2> /dev/null
    rm -rf "$d" && mkdir -p "$d"
    run_map -o "$d/map" --max-frames 6 > "$W/ro_first.log" 2>&1 || { cat "$W/ro_first.log"; fail "first run"; }
    before=$(cd "$d/map" && md5sum map_*.pndt.gz index.json)
    [ -n "$before" ] || fail "the first run wrote no map"
    if mount --bind "$d/map" "$d/map" 2> /dev/null && mount -o remount,bind,ro "$d/map" 2> /dev/null; then
        method="read-only bind mount"
        run_map -o "$d/map" > "$W/ro.log" 2>&1
        rc=$?
        umount "$d/map"
    elif [ "$(id -u)" = 0 ] && command -v setpriv > /dev/null; then
        mountpoint -q "$d/map" && umount "$d/map"
        method="run as nobody on a root-owned folder"
        chmod 755 "$d/map" && chmod -R o+rX "$W/scene"
        setpriv --reuid=65534 --regid=65534 --clear-groups "$MAP" "$SCENE" --period 0.2 --no-progress -o "$d/map" > "$W/ro.log" 2>&1
        rc=$?
    else
        method="chmod a-w"
        chmod a-w "$d/map"
        run_map -o "$d/map" > "$W/ro.log" 2>&1
        rc=$?
        chmod u+w "$d/map"
    fi
    after=$(cd "$d/map" && md5sum map_*.pndt.gz index.json)
    [ $rc -eq 3 ] || { cat "$W/ro.log"; fail "exit code $rc, expected 3 ($method)"; }
    grep -q "error: .*$d/map/" "$W/ro.log" || { cat "$W/ro.log"; fail "the error does not name the file"; }
    [ "$before" = "$after" ] || fail "earlier maps changed"
    "$CHECK" "$d/map" --no-tmp > "$W/ro_check.log" 2>&1 || { cat "$W/ro_check.log"; fail "output folder damaged"; }
    echo "readonly ($method): exit 3, $(grep -m1 "error:" "$W/ro.log"); earlier maps unchanged; $(cat "$W/ro_check.log")"
    ;;
*) fail "unknown mode" ;;
esac
