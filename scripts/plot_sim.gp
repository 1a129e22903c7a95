# SPDX-License-Identifier: BSD-3-Clause
# Figures of a cdpr-sim run (cdpr-sim calls this; see docs/scenarios.md).
# Usage: gnuplot -c scripts/plot_sim.gp DIR KIND [TITLE]
#   DIR   output directory of the run (reads DIR/timeseries.csv)
#   TITLE first line of every figure's title (cdpr-sim passes the scenario's description)
#   KIND  circle -> DIR/figure4.png (the paper's Figure 4: path and tracking error)
#                   and DIR/errors.png (error per coordinate)
#         line   -> DIR/figure5.png (the paper's Figure 5: error per coordinate)
#         hold, cyclic -> DIR/errors.png  (error per coordinate)
#   every kind   -> DIR/tensions.png (tensions, lengths, payout rates, node counts)
#   periodic (a DIR/laps.csv) -> DIR/laps.png (RMS and largest error per lap)
# Columns are addressed by their header names (timeseries.csv's first row).
dir = (ARGC >= 1) ? ARG1 : 'out/paper-circle'
kind = (ARGC >= 2) ? ARG2 : 'circle'
name = (ARGC >= 3) ? ARG3 : dir
data = dir.'/timeseries.csv'

set datafile separator ','
set terminal pngcairo size 1200,900 font 'sans,10'
set grid
set key top right
mm = 1000.0

if (kind eq 'circle') {
    set output dir.'/figure4.png'
    set multiplot layout 2,2 title name."\nPath and tracking error (the paper's Figure 4)" noenhanced
    set title '(a) path seen from above'
    set xlabel 'x [m]'
    set ylabel 'y [m]'
    set size ratio -1
    plot data using 'xd_m':'yd_m' with lines lw 2 lc rgb '#888888' title 'desired', \
         ''   using 'x_m':'y_m' with lines lw 1 lc rgb '#d62728' title 'cabin'
    set size noratio
    set title '(b) height'
    set xlabel 't [s]'
    set ylabel 'z [m]'
    plot data using 't_s':'zd_m' with lines lw 2 lc rgb '#888888' title 'desired', \
         ''   using 't_s':'z_m' with lines lw 1 lc rgb '#d62728' title 'cabin'
    set title '(c) position error (cabin - desired)'
    set ylabel 'error [m]'
    plot data using 't_s':'ex_m' with lines title 'x', \
         ''   using 't_s':'ey_m' with lines title 'y', \
         ''   using 't_s':'ez_m' with lines title 'z'
    set title '(d) tracking error magnitude'
    set logscale y
    set format y '%g'
    set yrange [1e-5:*]
    set ylabel '|error|'
    plot data using 't_s':'epos_m' with lines lw 1.5 title 'position [m]', \
         ''   using 't_s':'erot_rad' with lines lw 1 title 'attitude [rad]'
    unset logscale y
    set format y
    set yrange [*:*]
    unset multiplot
}

# Error per coordinate (the paper's Figure 5 layout).
if (1) {
    set output dir.'/'.((kind eq 'line') ? 'figure5.png' : 'errors.png')
    set multiplot layout 3,2 title name."\nError per coordinate, cabin - desired".\
        ((kind eq 'line') ? " (the paper's Figure 5)" : '') noenhanced
    set xlabel 't [s]'
    set title 'x'
    set ylabel 'e_x [mm]'
    plot data using 't_s':(column('ex_m')*mm) with lines lw 1.5 notitle
    set title 'alpha'
    set ylabel 'e_{alpha} [mrad]'
    plot data using 't_s':(column('ealpha_rad')*mm) with lines lw 1.5 notitle
    set title 'y'
    set ylabel 'e_y [mm]'
    plot data using 't_s':(column('ey_m')*mm) with lines lw 1.5 notitle
    set title 'beta'
    set ylabel 'e_{beta} [mrad]'
    plot data using 't_s':(column('ebeta_rad')*mm) with lines lw 1.5 notitle
    set title 'z'
    set ylabel 'e_z [mm]'
    plot data using 't_s':(column('ez_m')*mm) with lines lw 1.5 notitle
    set title 'gamma'
    set ylabel 'e_{gamma} [mrad]'
    plot data using 't_s':(column('egamma_rad')*mm) with lines lw 1.5 notitle
    unset multiplot
}

set output dir.'/tensions.png'
set multiplot layout 2,2 title name."\nCables: tensions, unstretched lengths, payout rates, segments" noenhanced
set xlabel 't [s]'
set key top right
set title 'cabin-end tension T_0'
set ylabel 'T [N]'
plot for [j=1:6] data using 't_s':'T_cabin'.j.'_N' with lines title 'cable '.j
set title 'unstretched length (solid) and feed-forward (dashed)'
set ylabel 'L [m]'
plot for [j=1:6] data using 't_s':'L'.j.'_m' with lines lc j title 'cable '.j, \
     for [j=1:6] data using 't_s':'Lff'.j.'_m' with lines dt 2 lc j notitle
set title 'payout rate (+ = out)'
set ylabel 'u [m/s]'
plot for [j=1:6] data using 't_s':'u'.j.'_m_per_s' with lines title 'cable '.j
set title 'segments per cable'
set ylabel 'n'
set yrange [*:*]
plot for [j=1:6] data using 't_s':'n'.j with steps title 'cable '.j
unset multiplot

# Per-lap errors of a periodic trajectory (laps.csv is written only when a lap completed).
if (system('test -s '.dir.'/laps.csv && echo 1') eq "1") {
    set output dir.'/laps.png'
    set terminal pngcairo size 900,500 font 'sans,10'
    set title name."\nPosition error per lap" noenhanced
    set xlabel 'lap'
    set ylabel 'error [m]'
    set yrange [0:*]
    set xtics 1
    set key top right
    plot dir.'/laps.csv' using 'lap':'rms_m' with linespoints pt 7 title 'RMS', \
         dir.'/laps.csv' using 'lap':'max_m' with linespoints pt 6 dt 2 title 'largest'
}
