#!/usr/bin/env bash
# The Python bindings (issue 53, docs/python.md), run from .ci/run: a fresh virtual
# environment in a temporary folder, `pip install .` from the repository root (maturin from
# PyPI builds python/, timed), then the pytest suite python/tests (its CLI-equal test runs
# `dem test cutting`: $DEM_CLI, else target/release/dem, else `cargo run --release`) and the
# tutorial docs/python/tutorial.py. Exits non-zero on any failure.
#
# Cost (measured here, on 2 cores shared with other jobs): the build, then ~20-60 s of tests
# and ~4 s of tutorial. The build uses the quick profile of python/Cargo.toml (opt-level 1;
# the same results: the CLI-equal tests pass with it; runs ~30 % slower). Cold, on a fresh
# clone: 243 s at load ~4, 401-414 s at load ~6 (the release profile: 358-379 s at load ~4.5);
# the whole script 4 min 40 s to 8 min. With the build folder of an earlier run: ~30 s.
# PyO3 turns on features of syn, num-complex, ... that the workspace does not, so the
# workspace's own target/ saves little; CARGO_TARGET_DIR (default <repo>/target) is shared all
# the same.
#
# Usage: scripts/python-check.sh   ($PYTHON: the interpreter, default python3;
# $PYTHON_CHECK_PROFILE: the cargo profile, default quick, `release` for what users build)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
PY=${PYTHON:-python3}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$root/target}
if ! "$PY" -c 'import ensurepip, venv' 2>/dev/null; then
    # Debian's python3 without the venv module.
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv; } >/dev/null 2>&1 \
        || { echo "python-check: $PY has no venv module and python3-venv could not be installed" >&2; exit 1; }
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$PY" -m venv "$work/venv"
venv="$work/venv/bin"
"$venv/python" -m pip install --quiet --upgrade pip
t0=$(date +%s)
MATURIN_PEP517_ARGS="--profile ${PYTHON_CHECK_PROFILE:-quick}" \
    "$venv/python" -m pip install --quiet ".[test,pandas]"
t1=$(date +%s)
echo "python-check: pip install . took $((t1 - t0)) s"
# The tests import the installed package, not the source folder.
(cd "$work" && "$venv/python" -m pytest -q -p no:cacheprovider "$root/python/tests")
t2=$(date +%s)
echo "python-check: pytest took $((t2 - t1)) s"
TUTORIAL_OUT="$work/tutorial" "$venv/python" docs/python/tutorial.py > "$work/tutorial.log" \
    || { cat "$work/tutorial.log"; echo "python-check: the tutorial failed"; exit 1; }
for f in grain-01.png forces.png cut.png; do
    [ -s "$work/tutorial/$f" ] || { echo "python-check: the tutorial wrote no $f"; exit 1; }
done
t3=$(date +%s)
echo "python-check: tutorial took $((t3 - t2)) s; all passed in $((t3 - t0)) s"
