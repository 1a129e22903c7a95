#!/usr/bin/env bash
# The main job. Installs what is missing, builds the Release configuration, and runs
#  1. the validation case of the foundation: one cable released from the straight chord
#     between two fixed points settles into its sagging shape; the settled mid-span sag and
#     end tensions are printed next to Irvine's elastic catenary for N = 8..64 segments, node
#     positions go to out/settle/nodes.csv and the shape to out/settle/settled_shape.png;
#  2. the paper's two simulations (Duan et al. 2010, §4) from their scenario files: the
#     six-cable 50 m model tracking a circle (with the paper's initial offset) and a line,
#     closed by the sag-aware feed-forward controller. Each run writes out/<scenario>/
#     timeseries.csv, summary.json and figures (figure4.png / figure5.png, tensions.png) and
#     prints its summary. (The real-time issue replaces these batch runs with the closed loop
#     over LCM.)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh

cmake --preset release >/dev/null
cmake --build --preset release --target cdpr-settle cdpr-sim

out=out/settle
mkdir -p "$out"
build/release/apps/cdpr-settle --out "$out"
gnuplot -e "dir='$out'" scripts/plot_settle.gp
echo "plot: $out/settled_shape.png"

for scenario in paper-circle paper-line; do
    echo
    echo "==== scenarios/$scenario.yaml"
    build/release/apps/cdpr-sim "scenarios/$scenario.yaml" --out "out/$scenario"
done
