#!/usr/bin/env bash
# The damping-frame study of issue 47 (docs/cutting.md, "Damping and the frame of reference"):
# traditional Si3N4 cuts (Table 2's specimen and model, a_p 1 mm, L 5 mm), PFC local damping
# against the fragment frame, in the lab and the tool's frame and at 0.25–4 m/s, and a pilot of
# the fragment frame with contact dashpots; one thread a run, two runs at a time. Every run
# names its damping frame (the cutting default changed from lab to fragment on 2026-12-02; the
# lab runs' keys and results are the same either way). Resumable: a finished run
# (cutting.result.json present) is skipped, an interrupted one resumes from its checkpoints.
#
# Usage: scripts/damping-frame-runs.sh OUT [JOBS]. $DEM: the dem binary (default
# target/release/dem). Tables and the plot: scripts/damping_frame_study.py OUT --plot P.png.
set -euo pipefail
out=${1:?usage: scripts/damping-frame-runs.sh OUT [JOBS]}
jobs=${2:-2}
root=$(cd "$(dirname "$0")/.." && pwd)
dem=${DEM:-$root/target/release/dem}
mkdir -p "$out"
one() {
    local name=$1 seed=$2
    shift 2
    [ -f "$out/$name/cutting.result.json" ] && return 0
    nice "$dem" test cutting --width 20mm --height 10mm --r-min 0.175mm --r-max 0.285mm \
        --model "$root/data/models/si3n4.model.json" --specimen-from-model --depth 1mm \
        --length 5mm --threads 1 --method traditional --seed "$seed" "$@" \
        --out "$out/$name" > "$out/$name.log" 2>&1 || echo "FAILED $name (see $out/$name.log)"
}
export -f one
export out dem root
{
    for s in 1 2 3 4 5; do
        echo "spec-s$s $s --speed 1 --damping-frame lab"
        echo "lab-tool-s$s $s --speed 1 --damping-frame lab --frame tool"
        echo "frag-lab-s$s $s --speed 1 --damping-frame fragment"
        echo "frag-tool-s$s $s --speed 1 --damping-frame fragment --frame tool"
    done
    for v in 0.5 2 4 0.25; do
        for s in 1 2 3 4 5; do
            echo "frag-v$v-s$s $s --speed $v --damping-frame fragment"
        done
        [ "$v" = 0.25 ] && continue
        for s in 1 2 3 4 5; do
            echo "lab-v$v-s$s $s --speed $v --damping-frame lab"
        done
    done
    # Pilot: the fragment frame with contact dashpots at 0.2 of critical (e 0.53 for a head-on
    # pair), frame-invariant by construction, on the choosing seeds 1-2.
    for v in 1 0.5 2 4; do
        for s in 1 2; do
            echo "fragc-v$v-s$s $s --speed $v --damping-frame fragment --contact-damping 0.2"
        done
    done
    for s in 1 2 3 4 5; do
        echo "lab-v0.25-s$s $s --speed 0.25 --damping-frame lab"
    done
} | xargs -P "$jobs" -L 1 bash -c 'one "$@"' _
