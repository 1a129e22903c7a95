# SPDX-License-Identifier: BSD-3-Clause
# Figures of a cdpr-sim run (cdpr-sim calls this; see docs/scenarios.md, "Outputs").
# Usage: gnuplot -c scripts/plot_sim.gp DIR KIND [TITLE [NCABLES [PAPER]]]
#   DIR      output directory of the run (reads DIR/timeseries.csv, DIR/laps.csv)
#   KIND     the trajectory type: circle, line, hold or cyclic
#   TITLE    first line of every figure's title (cdpr-sim: "FILE: description")
#   NCABLES  the robot's cable count (default 6): one tension panel each
#   PAPER    1 for the paper's robot: the figures that follow the paper's Figures 4 and 5 say so
#            and keep those names
# Every figure is written twice, DIR/NAME.png (pngcairo) and DIR/NAME.pdf (pdfcairo, vector):
#   circle -> path (figure4 with PAPER: path seen from above, height, error per axis, error
#             magnitude with position and attitude on their own axes) and errors
#   line   -> errors (figure5 with PAPER: error per coordinate)
#   hold, cyclic -> errors
#   every kind -> tensions (one panel per cable: cabin-end and winch-end tension) and cables
#                 (unstretched lengths with the feed-forward, payout rates, segments)
#   a DIR/laps.csv (a periodic trajectory with a complete lap) -> laps (RMS and largest error)
#   a DIR/shapes.csv (cdpr-sim --shapes) -> shapes (each cable's sag profile in its vertical
#             plane: every snapshot, the first and the last highlighted)
# Columns are addressed by their header names (timeseries.csv's first row).
dir = (ARGC >= 1) ? ARG1 : 'out/paper-circle'
kind = (ARGC >= 2) ? ARG2 : 'circle'
name = (ARGC >= 3) ? ARG3 : dir
nc = (ARGC >= 4) ? int(ARG4) : 6
paper = (ARGC >= 5) ? int(ARG5) : 0
data = dir.'/timeseries.csv'
has_laps = (system('test -s '.dir.'/laps.csv && echo 1') eq "1")
n_laps = has_laps ? int(system('tail -n +2 '.dir.'/laps.csv | wc -l')) : 0

path_name = (paper != 0) ? 'figure4' : 'path'
err_name = (kind eq 'line' && paper != 0) ? 'figure5' : 'errors'
# Cable j's colour: eight distinguishable ones, dashed from the ninth cable on.
array cable_rgb[8] = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', \
                      '#e377c2', '#17becf']
rgb(j) = cable_rgb[(j - 1) % 8 + 1]
dash(j) = ((j - 1) / 8) + 1
tension_cols = (nc <= 4) ? 2 : ((nc <= 9) ? 3 : 4)
tension_rows = (nc + tension_cols - 1) / tension_cols

set datafile separator ','
# The segment counts' range, for whole-number ticks and no empty range (counts that never
# change).
n_lo = 1e9
n_hi = -1e9
do for [j=1:nc] {
    stats data using 'n'.j nooutput
    n_lo = (STATS_min < n_lo) ? STATS_min : n_lo
    n_hi = (STATS_max > n_hi) ? STATS_max : n_hi
}
n_step = ((n_hi - n_lo) <= 12) ? 1 : (((n_hi - n_lo) <= 60) ? 5 : 20)
# Cable shapes (cdpr-sim --shapes): the first and last snapshot times.
shapes = dir.'/shapes.csv'
has_shapes = (system('test -s '.shapes.' && echo 1') eq "1")
if (has_shapes) {
    stats shapes using 't_s' nooutput
    t_first = STATS_min
    t_last = STATS_max
}
set grid
mm = 1000.0

do for [ext in 'png pdf'] {
    if (ext eq 'png') {
        big = "pngcairo size 1200,900 font 'sans,10'"
        wide = "pngcairo size 900,500 font 'sans,10'"
    } else {
        big = "pdfcairo size 10in,7.5in font 'sans,9'"
        wide = "pdfcairo size 7.5in,4.2in font 'sans,9'"
    }
    eval 'set terminal '.big
    set key below horizontal

    if (kind eq 'circle') {
        set output dir.'/'.path_name.'.'.ext
        set multiplot layout 2,2 title name."\nPath and tracking error".\
            ((paper != 0) ? " (after the paper's Figure 4)" : '') noenhanced
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
        plot data using 't_s':'ex_m' with lines lc rgb rgb(1) title 'x', \
             ''   using 't_s':'ey_m' with lines lc rgb rgb(2) title 'y', \
             ''   using 't_s':'ez_m' with lines lc rgb rgb(3) title 'z'
        # One unit per axis: position on the left, attitude on the right.
        set title '(d) tracking error magnitude'
        set logscale y
        set logscale y2
        set format y '%g'
        set format y2 '%g'
        set ylabel 'position error [m]' tc rgb rgb(1)
        set y2label 'attitude error [rad]' tc rgb rgb(4)
        set ytics nomirror
        set y2tics
        plot data using 't_s':'epos_m' with lines lw 1.5 lc rgb rgb(1) axes x1y1 title 'position', \
             ''   using 't_s':'erot_rad' with lines lw 1 lc rgb rgb(4) axes x1y2 title 'attitude'
        unset logscale y
        unset logscale y2
        unset y2tics
        unset y2label
        set ytics mirror
        set format y
        set ylabel tc default
        unset multiplot
    }

    # Error per coordinate (the paper's Figure 5 layout).
    set output dir.'/'.err_name.'.'.ext
    set multiplot layout 3,2 title name."\nError per coordinate, cabin - desired".\
        ((err_name eq 'figure5') ? " (after the paper's Figure 5)" : '') noenhanced
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

    # Tensions: one panel per cable, its two ends (legend under the panels, off the data).
    set output dir.'/tensions.'.ext
    set multiplot layout tension_rows,tension_cols title name.\
        "\nCable tensions: cabin end T_0 (solid), winch end (dashed)" noenhanced
    set xlabel 't [s]'
    set ylabel 'T [N]'
    set key off
    do for [j=1:nc] {
        set title 'cable '.j
        plot data using 't_s':'T_cabin'.j.'_N' with lines lw 1.2 lc rgb rgb(j) notitle, \
             ''   using 't_s':'T_winch'.j.'_N' with lines lw 1 dt 2 lc rgb rgb(j) notitle
    }
    unset multiplot

    # Lengths, payout rates and segments, the cables in their colours, the legend beside.
    set output dir.'/cables.'.ext
    set multiplot layout 3,1 title name."\nCables: unstretched lengths, payout rates, segments" \
        noenhanced
    set key outside right top vertical
    set title 'unstretched length (solid) and feed-forward (dashed)'
    set ylabel 'L [m]'
    plot for [j=1:nc] data using 't_s':'L'.j.'_m' with lines lc rgb rgb(j) dt dash(j) \
             title 'cable '.j, \
         for [j=1:nc] data using 't_s':'Lff'.j.'_m' with lines dt 2 lc rgb rgb(j) notitle
    set title 'payout rate (+ = out)'
    set ylabel 'u [m/s]'
    plot for [j=1:nc] data using 't_s':'u'.j.'_m_per_s' with lines lc rgb rgb(j) dt dash(j) \
             title 'cable '.j
    set title 'segments per cable'
    set ylabel 'n'
    set yrange [n_lo - 0.5:n_hi + 0.5]
    set ytics n_step
    plot for [j=1:nc] data using 't_s':'n'.j with steps lc rgb rgb(j) dt dash(j) title 'cable '.j
    set yrange [*:*]
    set ytics autofreq
    unset multiplot
    set key below horizontal

    # Sag profiles (cdpr-sim --shapes): each cable's sag below its straight chord against the
    # horizontal distance from its exit point, every snapshot in grey, the first and the last
    # in colour.
    if (has_shapes) {
        set output dir.'/shapes.'.ext
        set multiplot layout tension_rows,tension_cols title name.\
            sprintf("\nCable sag below the straight chord: every snapshot (grey), t = %g s (blue) and %g s (red)", \
                    t_first, t_last) noenhanced
        set xlabel 'horizontal distance from the exit point [m]'
        set ylabel 'sag below the chord [m]'
        set key off
        do for [j=1:nc] {
            set title 'cable '.j
            plot shapes using (column('cable') == j ? column('h_m') : NaN):'sag_m' with lines \
                     lw 0.5 lc rgb '#bbbbbb' notitle, \
                 '' using ((column('cable') == j && column('t_s') == t_first) ? \
                     column('h_m') : NaN):'sag_m' with linespoints pt 7 ps 0.3 lw 1.2 \
                     lc rgb rgb(1) notitle, \
                 '' using ((column('cable') == j && column('t_s') == t_last) ? \
                     column('h_m') : NaN):'sag_m' with linespoints pt 7 ps 0.3 lw 1.2 \
                     lc rgb rgb(4) notitle
        }
        unset multiplot
        set key below horizontal
    }

    # Per-lap errors of a periodic trajectory: one point per lap, laps as whole numbers.
    if (has_laps) {
        eval 'set terminal '.wide
        set output dir.'/laps.'.ext
        set title name."\nPosition error per lap" noenhanced
        set xlabel 'lap'
        set ylabel 'error [m]'
        set xrange [0.5:n_laps + 0.5]
        set yrange [0:*]
        set xtics 1
        plot dir.'/laps.csv' using 'lap':'rms_m' with linespoints pt 7 lc rgb rgb(1) title 'RMS', \
             dir.'/laps.csv' using 'lap':'max_m' with linespoints pt 6 dt 2 lc rgb rgb(4) \
                 title 'largest'
        set xrange [*:*]
        set yrange [*:*]
        set xtics autofreq
    }
    unset output
}
