#!/usr/bin/env bash
# Crash tests of `dem run` (issue 20 item 7), run from .ci/run:
#
# 1. kill -9: a 4,000-disc column settling in a box, checkpointed every 200 steps (each
#    checkpoint ~3 MB, so some kills land inside checkpoint writes), is killed with SIGKILL at
#    random moments and restarted from its newest checkpoint until it finishes. After every
#    kill each checkpoint in the folder must load (JSON, checksum: a restart from it), and the
#    final checkpoint's world and history must equal those of an uninterrupted run, bit for bit.
# 2. a full disk: the same scene into a 1 MB tmpfs (needs root and mount; the check says so
#    and fails when it cannot mount). `dem run` must end with exit 2 and a message naming the
#    file and "No space left", and leave no temporary (partial) file behind.
#
# Usage: scripts/crash-tests.sh [KILLS]   (default 8). $DEM: the dem binary (default
# target/release/dem). Exits 1 on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
DEM=${DEM:-target/release/dem}
kills=${1:-8}
work=$(mktemp -d)
trap 'umount "$work/full" 2>/dev/null || true; rm -rf "$work"' EXIT
fail() { echo "crash-tests: FAIL: $*" >&2; exit 1; }

python3 - "$work/scene.json" <<'PY'
import json, random, sys
random.seed(3)
discs = []
for iy in range(80):
    for ix in range(50):
        discs.append([-24.5 + ix * 1.0, 0.6 + iy * 1.0, round(random.uniform(0.38, 0.48), 3)])
scene = {
    "schema": "dem.scene/1", "name": "crash column", "units": "mm", "thickness": 1.0, "seed": 5,
    "materials": [
        {"name": "grain", "density": 2650, "kn": 2e4, "ks": 1e4, "friction": 0.5, "damping_ratio": 0.2},
        {"name": "steel", "kn": 2e4, "ks": 1e4, "friction": 0.3, "damping_ratio": 0.2}],
    "contact": {"law": "linear_spring_dashpot"},
    "bodies": {"discs": [{"material": "grain", "random_speed": 5.0, "discs": discs}]},
    "walls": [
        {"name": "floor", "a": [-25, 0], "b": [25, 0], "material": "steel"},
        {"name": "left", "a": [-25, 90], "b": [-25, 0], "material": "steel"},
        {"name": "right", "a": [25, 0], "b": [25, 90], "material": "steel"}],
    "gravity": [0, -9810], "damping": {"local": 0.3},
    "run": {"steps": 20000, "dt_factor": 0.2},
    "outputs": {"history_every": 100, "vtk_every": 0, "checkpoint_every": 200, "checkpoint_keep": 3},
}
json.dump(scene, open(sys.argv[1], "w"))
PY

same_world() {
  python3 - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for k in ("world", "history_rows", "scene_hash"):
    if a[k] != b[k]:
        sys.exit(f"{k} differs")
PY
}

echo "== crash-tests: uninterrupted reference run"
t0=$(date +%s.%N)
"$DEM" run "$work/scene.json" --out "$work/ref" --threads 1 >/dev/null
t_ref=$(python3 -c "import time; print(time.time() - $t0)")
echo "reference: $(printf %.2f "$t_ref") s"

echo "== crash-tests: $kills kills with SIGKILL, restarts from the newest checkpoint"
out="$work/crash"
restart=()
done_ok=0
tmps=0
for k in $(seq 1 "$kills") last; do
  "$DEM" run "$work/scene.json" --out "$out" --threads 1 "${restart[@]}" >"$work/log" 2>&1 &
  pid=$!
  if [ "$k" = last ]; then
    wait "$pid" || fail "the last run did not finish: $(cat "$work/log")"
    done_ok=1
    break
  fi
  # Early enough that most runs are killed (each gets a start-up and a restart).
  sleep "$(python3 -c "import random; print(random.uniform(0.05, 0.1 * $t_ref))")"
  if kill -9 "$pid" 2>/dev/null; then
    wait "$pid" 2>/dev/null || true
    echo "kill $k: killed during the run"
  else
    wait "$pid" || fail "run $k failed: $(cat "$work/log")"
    echo "kill $k: the run had finished; starting again from its newest checkpoint"
  fi
  tmps=$((tmps + $(ls -A "$out" 2>/dev/null | grep -c '\.tmp$' || true)))
  # Every checkpoint left must be whole: the restart below checks its checksum, and each
  # must parse.
  newest=""
  for c in $(ls "$out"/ckpt-0*.json 2>/dev/null | sort); do
    python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$c" || fail "$c is not whole JSON"
    newest=$c
  done
  if [ -n "$newest" ]; then restart=(--restart "$newest"); else restart=(); fi
done
[ "$done_ok" = 1 ] || fail "never finished"
same_world "$work/ref/ckpt-final.json" "$out/ckpt-final.json" || fail "the restarted run differs from the uninterrupted one"
cmp -s "$work/ref/history.csv" "$out/history.csv" || fail "history.csv differs from the uninterrupted run's"
left=$(ls -A "$out" | grep -c '\.tmp$' || true)
echo "after $kills kills: final world and history identical to the uninterrupted run; kills inside a write (temporary files found at a restart): $tmps; left at the end: $left"

echo "== crash-tests: a full disk (1 MB tmpfs)"
mkdir -p "$work/full"
mount -t tmpfs -o size=1m tmpfs "$work/full" 2>/dev/null || fail "cannot mount a tmpfs (needs root): the full-disk check did not run"
set +e
"$DEM" run "$work/scene.json" --out "$work/full/o" --threads 1 >"$work/full.log" 2>&1
rc=$?
set -e
[ "$rc" = 2 ] || fail "a full disk ended with exit $rc, not 2: $(cat "$work/full.log")"
grep -q "No space left" "$work/full.log" || fail "no 'No space left' in: $(cat "$work/full.log")"
partial=$(ls -A "$work/full/o" | grep '\.tmp$' || true)
[ -z "$partial" ] || fail "partial files left on the full disk: $partial"
echo "full disk: exit 2, no partial file: $(grep -m1 "No space left" "$work/full.log" | sed "s#$work/##g")"
echo "crash-tests: all passed"
