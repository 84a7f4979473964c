#!/bin/bash
# The pictures of one cut of each specimen type at three moments (issue 24, like S0's figures
# 3-5): scripts/cut-pictures.sh RUNS_DIR [PICTURES_DIR]
# Runs (once: a finished cut is kept) the Table 2 cut of seed 1, a_p = 1 mm, v = 2 m/s, L = 10
# mm with 3 VTK snapshots for the traditional, ORC and improved-ORC specimens into
# RUNS_DIR/<method> (90, 96 and 514 s of CPU on the development VM), then draws with
# `dem render` the specimen and the cut at 1/3, 2/3 and the end of its travel into
# PICTURES_DIR/cut-<method>-<k>.png (default docs/pictures), k = 0 (specimen) to 3.
set -euo pipefail
runs=${1:?usage: scripts/cut-pictures.sh RUNS_DIR [PICTURES_DIR]}
here=$(cd "$(dirname "$0")/.." && pwd)
pics=${2:-$here/docs/pictures}
dem=${DEM:-dem}
mkdir -p "$runs" "$pics"
# The cut's region: the specimen is 20 x 10 mm (surface at y = 10 mm); the tool cuts 10 mm from
# its left edge, chips fly above it.
view=0,20.3,3.5,13.5
for m in traditional orc improved; do
  out=$runs/$m
  if [ ! -f "$out/cutting.result.json" ]; then
    "$dem" test cutting --method "$m" --width 20mm --height 10mm --r-min 0.175mm \
      --r-max 0.285mm --grain-size 0.86mm --template-r-min 0.08mm --irregular few \
      --model "$here/data/models/si3n4.model.json" --specimen-from-model --length 10mm \
      --depth 1mm --speed 2 --seed 1 --snapshots 3 --out "$out"
  fi
  snaps=($(ls "$out"/snap-*.vtp | sort))
  "$dem" render "$out/specimen.json" --view "$view" --width 600 --out "$pics/cut-$m-0.png"
  "$dem" render "${snaps[1]}" --bonds --view "$view" --width 600 --out "$pics/cut-$m-1.png"
  "$dem" render "${snaps[2]}" --bonds --view "$view" --width 600 --out "$pics/cut-$m-2.png"
  "$dem" render "$out/ckpt-final.json" --bonds --broken --view "$view" --width 600 \
    --out "$pics/cut-$m-3.png"
done
