#!/usr/bin/env bash
# What one map option does on generated sequences: each (scene, seed) is generated once, mapped by
# pndt-map with the defaults and with each override given, and scored in 3D by pndt-eval against
# its ground truth (overall 3D PQ, and the PQ of one class). A diagnosis tool: thresholds are
# chosen by pndt-experiments' validation, never from what this prints on the reported scenes.
#
# Usage: scripts/threshold_check.sh [-s SCENES] [-e SEEDS] [-n FRAMES] [-v VOXEL] [-c CLASS] [-o DIR] SETTING ...
#   SETTING: KEY=VALUE, or several joined by commas (KEY=V,KEY2=V2: changed together); KEY is a
#   key of [MAP_PanopticNDTMap_00_creationOpts] (config/panoptic_ndt.ini)
#   defaults: -s living,office  -e 1,2  -n 60  -v 0.1  -c pillow  -o out/threshold_check;
#   PNDT_BIN: the folder of pndt-generate, pndt-map and pndt-eval (default build/bin)
# Example (doc/results.md, the pillow check): scripts/threshold_check.sh fragment_merge_frames=3
# Prints one line per (scene, seed, setting): "scene seed setting  PQ <3D PQ>  <class> PQ <value>";
# over more than one run, then one per setting: "mean setting  PQ <mean 3D PQ>  over <n> of <runs> runs".
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BIN=${PNDT_BIN:-$REPO/build/bin}
scenes=living,office seeds=1,2 frames=60 voxel=0.1 cls=pillow out=out/threshold_check
while getopts "s:e:n:v:c:o:h" opt; do
    case $opt in
        s) scenes=$OPTARG ;;
        e) seeds=$OPTARG ;;
        n) frames=$OPTARG ;;
        v) voxel=$OPTARG ;;
        c) cls=$OPTARG ;;
        o) out=$OPTARG ;;
        *) sed -n 2,14p "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { echo "threshold_check: give at least one KEY=VALUE (see -h)" >&2; exit 2; }
for setting in "$@"; do
    IFS=, read -ra kvs <<< "$setting"
    for kv in "${kvs[@]}"; do
        [[ $kv =~ ^[A-Za-z_]+=[^=]+$ ]] || { echo "threshold_check: '$kv' (in '$setting') is not KEY=VALUE" >&2; exit 2; }
    done
done
for b in pndt-generate pndt-map pndt-eval; do
    [ -x "$BIN/$b" ] || { echo "threshold_check: $BIN/$b missing: build first (scripts/run_demo.sh)" >&2; exit 1; }
done
mkdir -p "$out"
declare -A pq_sum pq_runs

# "PQ 67.0" of the summary line, and the class row's PQ column of pndt-eval's table.
score() {
    local eval=$1
    local pq cpq
    pq=$(sed -n 2p "$eval" | grep -o 'PQ [0-9.]*' | head -1 | cut -d' ' -f2)
    cpq=$(awk -F'|' -v c="$cls" '{gsub(/ /, "", $3)} $3 == c {gsub(/ /, "", $7); print $7}' "$eval")
    echo "PQ ${pq:-?}  $cls PQ ${cpq:--}"
}

for scene in ${scenes//,/ }; do
    for seed in ${seeds//,/ }; do
        seq=$out/${scene}_${seed}_$frames
        if [ ! -f "$seq/summary.json" ]; then
            "$BIN/pndt-generate" --scene "$scene" --seed "$seed" -n "$frames" --formats rawlog,gt -o "$seq" > "$seq.generate.log" 2>&1 ||
                { echo "threshold_check: pndt-generate failed, see $seq.generate.log" >&2; exit 1; }
        fi
        rawlog=$(ls "$seq"/*.rawlog)
        ply=$(find "$seq/gt/ply" -name '*.ply' | head -1)
        for setting in defaults "$@"; do
            tag=${setting//[^A-Za-z0-9._=-]/_}
            map=$seq.map_$tag
            args=()
            if [ "$setting" != defaults ]; then
                IFS=, read -ra kvs <<< "$setting"
                for kv in "${kvs[@]}"; do args+=(-s "MAP_PanopticNDTMap_00_creationOpts.$kv"); done
            fi
            rm -rf "$map"
            "$BIN/pndt-map" "$rawlog" --out "$map" --period 0 --voxel-size "$voxel" "${args[@]}" > "$map.log" 2>&1 ||
                { echo "threshold_check: pndt-map failed ($setting), see $map.log" >&2; exit 1; }
            # The sequence is its own GT: a setting that labels (almost) nothing scores 0, not a refusal.
            "$BIN/pndt-eval" "$map/map_0000.pndt.gz" --gt-ply "$ply" --min-labelled 0 > "$map.eval" 2>&1 ||
                { echo "threshold_check: pndt-eval failed ($setting), see $map.eval" >&2; exit 1; }
            line=$(score "$map.eval")
            echo "$scene $seed $setting  $line"
            read -r _ pq _ <<< "$line"
            if [[ $pq =~ ^[0-9.]+$ ]]; then
                pq_sum[$setting]=$(awk -v a="${pq_sum[$setting]:-0}" -v b="$pq" 'BEGIN { print a + b }')
                pq_runs[$setting]=$((${pq_runs[$setting]:-0} + 1))
            fi
        done
    done
done
# Over several runs, each setting's mean 3D PQ (runs without a score left out, their count shown).
runs=$(($(wc -w <<< "${scenes//,/ }") * $(wc -w <<< "${seeds//,/ }")))
if [ "$runs" -gt 1 ]; then
    for setting in defaults "$@"; do
        n=${pq_runs[$setting]:-0}
        mean=$(awk -v s="${pq_sum[$setting]:-0}" -v n="$n" 'BEGIN { if (n) printf "%.2f", s / n; else print "?" }')
        echo "mean $setting  PQ $mean  over $n of $runs runs"
    done
fi
