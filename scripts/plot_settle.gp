# SPDX-License-Identifier: BSD-3-Clause
# Plot the settled lumped-mass cable against Irvine's elastic catenary.
# Usage: gnuplot -e "dir='out/settle'" scripts/plot_settle.gp
if (!exists("dir")) dir = 'out/settle'
set terminal pngcairo size 1000,620 font "sans,11"
set output dir.'/settled_shape.png'
set datafile separator ','
set key bottom right
set grid
set xlabel 'x [m]'
set ylabel 'z [m]'
set title 'Cable released from the straight chord, settled to rest, vs elastic catenary'
plot dir.'/nodes.csv' using ($1==64 ? $6 : 1/0):($1==64 ? $7 : 1/0) with lines lw 2 lc rgb '#888888' title 'Irvine elastic catenary', \
     ''               using ($1==8 ? $4 : 1/0):($1==8 ? $5 : 1/0) with linespoints pt 7 ps 1.2 lc rgb '#d62728' title 'lumped mass, N = 8', \
     ''               using ($1==32 ? $4 : 1/0):($1==32 ? $5 : 1/0) with points pt 6 ps 0.9 lc rgb '#1f77b4' title 'lumped mass, N = 32'
