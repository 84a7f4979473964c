#!/usr/bin/env bash
# Rewrites docs/schema/<kind>.schema.json from `dem schema <kind>` for every kind `dem schema
# --list` names (run after changing a file type; dem-cli/tests/schema_cli.rs checks the
# committed files equal what `dem schema` prints).
#
# Usage: scripts/write-schemas.sh. $DEM: the dem binary (default: `cargo run -q -p dem-cli --`,
# a debug build).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -n "${DEM:-}" ]; then
    dem=("$DEM")
else
    dem=(cargo run -q -p dem-cli --)
fi
mkdir -p docs/schema
for kind in $("${dem[@]}" schema --list | cut -d' ' -f1); do
    "${dem[@]}" schema "$kind" > "docs/schema/$kind.schema.json.tmp"
    mv "docs/schema/$kind.schema.json.tmp" "docs/schema/$kind.schema.json"
    echo "docs/schema/$kind.schema.json"
done
