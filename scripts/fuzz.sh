#!/bin/bash
# Fuzz one reader with libFuzzer (cargo fuzz, nightly Rust): scripts/fuzz.sh TARGET [SECONDS]
# TARGET: outline | grains | template | scene | specimen | checkpoint | history | study | sweep
# (their bodies: validation/src/fuzz_targets.rs).
# New inputs go to fuzz/work/TARGET (not committed); crashes to fuzz/work/crashes-TARGET/.
# Keep a crash, after its fix, as fuzz/regressions/TARGET/<what>.json: CI replays it
# (validation/tests/fuzz_regressions.rs). docs/reliability.md, "Fuzzing".
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
t=${1:?usage: scripts/fuzz.sh TARGET [SECONDS]}
secs=${2:-600}
case $t in
  outline) seeds=(../data/outlines) ;;
  template) seeds=(../examples/scenes/templates) ;;
  scene) seeds=(../examples/scenes) ;;
  study) seeds=(../data/studies) ;;
  sweep) seeds=(../examples/studies ../data/studies) ;;
  grains | specimen | checkpoint | history) seeds=() ;;
  *) echo "unknown target $t" >&2; exit 2 ;;
esac
[ -d "corpus/$t" ] && seeds+=("corpus/$t")
[ -d "regressions/$t" ] && seeds+=("regressions/$t")
command -v cargo-fuzz > /dev/null || cargo install cargo-fuzz
mkdir -p "work/$t" "work/crashes-$t"
exec cargo +nightly fuzz run -O "$t" "work/$t" "${seeds[@]}" -- \
  -max_total_time="$secs" -max_len=16384 -rss_limit_mb=3072 -timeout=20 \
  -artifact_prefix="work/crashes-$t/" -print_final_stats=1
