#!/usr/bin/env bash
# The depth series of issue 47 item 4 (docs/cutting.md, "Depth trend"): traditional Si3N4 cuts
# on Table 2's specimen and calibrated model with local damping in the fragment frame, v 1 m/s,
# a_p 0.25, 0.5, 1, 2, 3 mm over L = 10 mm (Table 2's length: the window [2 a_p, L] is 4 mm
# long at 3 mm), then two depths (0.5 and 1 mm, L 5 mm) with discs 2x finer beside the same
# cuts on the coarse discs. One thread a run, JOBS runs at a time. Resumable: a finished run
# (cutting.result.json present) is skipped, an interrupted one resumes from its checkpoints.
#
# Usage: scripts/depth-runs.sh OUT [JOBS]. $DEM: the dem binary (default target/release/dem).
# Tables and the plot: scripts/depth_study.py OUT --plot P.png.
set -euo pipefail
out=${1:?usage: scripts/depth-runs.sh OUT [JOBS]}
jobs=${2:-2}
root=$(cd "$(dirname "$0")/.." && pwd)
dem=${DEM:-$root/target/release/dem}
mkdir -p "$out"
one() {
    local name=$1 seed=$2
    shift 2
    [ -f "$out/$name/cutting.result.json" ] && return 0
    nice "$dem" test cutting --width 20mm --height 10mm \
        --model "$root/data/models/si3n4.model.json" --specimen-from-model \
        --threads 1 --method traditional --seed "$seed" --speed 1 --damping-frame fragment \
        "$@" --out "$out/$name" > "$out/$name.log" 2>&1 || echo "FAILED $name (see $out/$name.log)"
}
export -f one
export out dem root
coarse="--r-min 0.175mm --r-max 0.285mm"
fine="--r-min 0.0875mm --r-max 0.1425mm"
{
    for s in 1 2 3 4 5; do
        for d in 0.25 0.5 1 2 3; do
            echo "d$d-s$s $s --depth ${d}mm --length 10mm $coarse"
        done
        if [ "$s" -le 2 ]; then
            echo "l5-d0.5-s$s $s --depth 0.5mm --length 5mm $coarse"
            echo "fine-l5-d0.5-s$s $s --depth 0.5mm --length 5mm $fine"
            echo "fine-l5-d1-s$s $s --depth 1mm --length 5mm $fine"
        fi
    done
} | xargs -P "$jobs" -L 1 bash -c 'one "$@"' _
