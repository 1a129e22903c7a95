#!/usr/bin/env bash
# The main job. Installs what is missing, builds the Release configuration, and runs the
# validation case of the foundation: one cable released from the straight chord between two
# fixed points settles into its sagging shape; the settled mid-span sag and end tensions are
# printed next to Irvine's elastic catenary for N = 8..64 segments, node positions are written
# to out/settle/nodes.csv and the shape is plotted to out/settle/settled_shape.png.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh

cmake --preset release >/dev/null
cmake --build --preset release --target cdpr-settle

out=out/settle
mkdir -p "$out"
build/release/apps/cdpr-settle --out "$out"
gnuplot -e "dir='$out'" scripts/plot_settle.gp
echo "plot: $out/settled_shape.png"
