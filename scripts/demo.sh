#!/usr/bin/env bash
# Builds the Release configuration and runs the settling demo; exits with its status.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh

cmake --preset release
cmake --build --preset release

exe=build/release/apps/cdpr-settle
if [[ ! -x $exe ]]; then
    echo "demo: $exe is not built (apps/cdpr-settle/main.c does not exist yet); nothing to run"
    exit 0
fi
mkdir -p out
exec "$exe" --out out/settle
