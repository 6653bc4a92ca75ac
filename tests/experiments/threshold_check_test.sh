#!/usr/bin/env bash
# scripts/threshold_check.sh on a small generated sequence (8 frames, 20 cm):
#   - a line for the defaults and one per setting, in the documented format;
#   - the override reaches the map: theta_l = 0.999 leaves no semantic update (3D PQ 0), while the
#     defaults label the room (PQ > 20);
#   - several keys in one setting are applied together (their line is printed once);
#   - over two seeds, each setting's mean line is the mean of its two runs' PQ;
#   - an unknown key fails with exit 1 and names the setting; a malformed one with exit 2.
# Usage: threshold_check_test.sh SCRIPT BIN_DIR WORK_DIR
set -uo pipefail
script=$1 bin=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
run() { PNDT_BIN=$bin "$script" -s small -e 1 -n 8 -v 0.2 -o "$work" "$@"; }

out=$(run theta_l=0.999 fragment_merge_frames=3,label_fill_distance=0.5) || fail "exit $? on good settings"
echo "$out"
[ "$(echo "$out" | wc -l)" -eq 3 ] || fail "expected 3 lines"
line() { echo "$out" | grep -E "^small 1 $1  PQ [0-9.]+  pillow PQ " || fail "no line for $1"; }
pq() { line "$1" | sed -E 's/.*  PQ ([0-9.]+)  pillow.*/\1/'; }
d=$(pq defaults) t=$(pq 'theta_l=0\.999')
line 'fragment_merge_frames=3,label_fill_distance=0\.5' > /dev/null
awk -v d="$d" 'BEGIN { exit !(d > 20) }' || fail "defaults PQ $d, expected > 20"
awk -v t="$t" 'BEGIN { exit !(t == 0) }' || fail "theta_l=0.999 PQ $t, expected 0"

err=$(run bogus_key=1 2>&1 > /dev/null)
rc=$?
[ $rc -eq 1 ] || fail "unknown key: exit $rc, expected 1"
echo "$err" | grep -q "pndt-map failed (bogus_key=1)" || fail "unknown key not named: $err"
grep -q "unknown key 'bogus_key'" "$work"/small_1_8.map_bogus_key=1.log || fail "pndt-map's log does not name the key"

# Two seeds: a line per run and setting, then each setting's mean over the two runs.
out=$(run -e 1,2 theta_l=0.999) || fail "exit $? on two seeds"
echo "$out"
[ "$(echo "$out" | wc -l)" -eq 6 ] || fail "expected 4 run lines and 2 mean lines"
for s in defaults 'theta_l=0\.999'; do
    runs=$(echo "$out" | grep -E "^small [12] $s  PQ " | sed -E 's/.*  PQ ([0-9.]+)  pillow.*/\1/' | tr '\n' ' ')
    mean=$(echo "$out" | grep -E "^mean $s  PQ [0-9.]+  over 2 of 2 runs$" | sed -E 's/.*  PQ ([0-9.]+)  over.*/\1/')
    [ -n "$mean" ] || fail "no mean line for $s"
    awk -v r="$runs" -v m="$mean" 'BEGIN { split(r, a, " "); exit !(a[1] != "" && a[2] != "" && (a[1] + a[2]) / 2 - m < 0.006 && m - (a[1] + a[2]) / 2 < 0.006) }' ||
        fail "mean $mean of $s is not the mean of its runs ($runs)"
done

run "theta_l" > /dev/null 2>&1
rc=$?
[ $rc -eq 2 ] || fail "malformed setting: exit $rc, expected 2"
echo PASS
