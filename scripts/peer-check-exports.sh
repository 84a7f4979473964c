#!/usr/bin/env bash
# Peer check of `dem clump --export` (docs/exports.md): makes templates from shipped outlines
# (four improved-ORC grains, one classic ORC grain), exports them to every format, loads the
# YADE and LAMMPS exports in YADE and LAMMPS and compares the mass, mass centre and I_z they
# compute with the templates' (PFC and MercuryDPM files are read back as those codes read
# them). Prints a table; exits 1 on a mismatch, 2 when a peer is missing or fails.
#
# Needs: yade and lmp (Debian: apt-get install -y yade lammps), python3. The `dem` binary:
# $DEM if set (CI can pass DEM=target/release/dem), else a debug build of dem-cli.
set -euo pipefail
cd "$(dirname "$0")/.."
for tool in yade lmp python3; do
  if ! command -v "$tool" >/dev/null; then
    echo "peer-check: $tool not found (Debian: apt-get install -y yade lammps python3)" >&2
    exit 2
  fi
done
start=$(date +%s)
if [ -z "${DEM:-}" ]; then
  cargo build -q -p dem-cli
  DEM=target/debug/dem
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
o=data/outlines
"$DEM" clump "$o/equant-01.csv" "$o/elongated-02.csv" "$o/concave-03.csv" "$o/rough-04.csv" \
  --out "$work/improved" --export pfc,yade,lammps,mercury --threads 1 >"$work/improved.log"
"$DEM" clump "$o/mixed-01.csv" --method orc \
  --out "$work/orc" --export pfc,yade,lammps,mercury --threads 1 >"$work/orc.log"
grep '^export' "$work/improved.log"
python3 scripts/peer/peer_check.py "$work"/improved/*.json "$work"/orc/*.json
echo "peer-check: $(($(date +%s) - start)) s in all"
