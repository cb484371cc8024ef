# Figures 3, 4, 5 of the study and the units evidence, from a single_cell_migration run.
#   gnuplot -e "dir='results/single_cell_migration'; figdir='paper/report/figures'" experiments/single_cell_migration/plot.gp
if (!exists("dir")) dir = 'results/single_cell_migration'
if (!exists("figdir")) figdir = dir
set datafile separator ','
ratios = "055 070 100"
label(s) = (s eq "055") ? "s* = 0.55" : (s eq "070") ? "s* = 0.7" : "s* = 1.0"
times = "0 0.05 0.10 0.20 0.30 0.50 0.80 0.90 1.00 1.25 1.50 2.00 3.00 7.50"

# Figure 3: shape and position, one row per s*, one panel per time (channel height to scale,
# each panel a 10 um window centred on the cell).
set terminal pngcairo size 1900,520 font ',9'
set output figdir.'/single_cell_migration_fig3.png'
set datafile separator whitespace
set multiplot layout 3,14 title 'Fig. 3: one cell in the 20 x 10 um channel (window 10 um wide, centred on the cell; walls at 0 and 10 um)' margins 0.03,0.99,0.04,0.9 spacing 0.004,0.02
unset key
set xrange [-5:5]
set yrange [0:10]
set size ratio -1
unset xtics
set ytics 5 format ''
do for [s in ratios] {
  do for [k=1:14] {
    set title (s eq "055") ? word(times, k).' ms' : ''
    set ylabel (k == 1) ? label(s) : ''
    f = dir.'/narrow_si_s'.s.'/snapshots_centred.dat'
    plot f index (k-1) using 1:2 with lines lw 1.5 lc rgb '#b2182b', 5 with lines dt 3 lc rgb 'gray'
  }
}
unset multiplot
unset size
set size noratio
set xtics auto
set ytics auto format '%g'
set autoscale

set datafile separator ','
set datafile columnheaders  # series.csv columns by name (their order grew over versions)
set terminal pngcairo size 800,520 font ',11'
set key top left

# Figure 4: centroid height against time in the narrow channel.
set output figdir.'/single_cell_migration_fig4.png'
set title 'Fig. 4: centroid height in the 20 x 10 um channel (centreline 5 um)'
set xlabel 't (ms)'
set ylabel 'centroid height (um)'
set xrange [0:7.5]
set yrange [2.5:5.5]
plot for [s in ratios] dir.'/narrow_si_s'.s.'/series.csv' using (column("t")*1e3):(column("cell0_y")*1e6) with lines lw 2 title label(s), \
     5 with lines dt 2 lc rgb 'gray' title 'centreline'

# Figure 5: centroid height in the wide channel, 800 ms (semi-implicit coupling).
set output figdir.'/single_cell_migration_fig5.png'
set key bottom right
set title 'Fig. 5: centroid height in the 100 x 50 um channel (centreline 25 um; semi-implicit coupling)'
set xlabel 't (ms)'
set autoscale x
set yrange [*:*]
# Points: the mean node height of each membrane snapshot (0, 100, 200, 400, 800 ms), read from
# snapshots_centred.dat, so the figure has the trajectory even where series.csv is missing.
snap(s) = sprintf("< awk 'BEGIN{print \"t_ms,y_um\"} /^# t = /{if(n)print t*1e3 \",\" m/n; t=$4; m=0; n=0; next} NF==2{m+=$2; n++} END{if(n)print t*1e3 \",\" m/n}' %s/wide_si_s%s/snapshots_centred.dat", dir, s)
plot for [s in ratios] dir.'/wide_si_s'.s.'/series.csv' using (column("t")*1e3):(column("cell0_y")*1e6) with lines lw 2 title label(s), \
     for [i=1:3] snap(word(ratios, i)) using 1:2 with points pt 7 ps 1.2 lc i title label(word(ratios, i)).' (snapshots)', \
     25 with lines dt 2 lc rgb 'gray' title 'centreline'

# Units evidence: the two readings of the constants over the first millisecond (make evidence's
# runs: drawn when the other reading's runs are there).
if (system('test -f '.dir.'/narrow_cgs_s055/series.csv && echo 1 || echo 0') eq "1") {
set output figdir.'/single_cell_migration_units.png'
set multiplot layout 1,2 title 'Which reading of the 2D constants? SI (J/m as given) against CGS (100 x stiffer)'
set title 'centroid height'
set xrange [0:1]
set yrange [2.5:5.5]
plot for [s in "055 100"] dir.'/narrow_si_s'.s.'/series.csv' using (column("t")*1e3):(column("cell0_y")*1e6) with lines lw 2 title 'SI, '.label(s), \
     for [s in "055 100"] dir.'/narrow_cgs_s'.s.'/series.csv' using (column("t")*1e3):(column("cell0_y")*1e6) with lines lw 2 dt 2 title 'CGS, '.label(s)
set title 'shape at 1 ms (centred)'
set datafile separator whitespace
set datafile nocolumnheaders
set xrange [-5:5]
set yrange [-4:4]
set size ratio -1
set xlabel 'x - x_c (um)'
set ylabel 'y - 5 um'
plot for [s in "055 100"] dir.'/narrow_si_s'.s.'/snapshots_centred.dat' index 8 using 1:($2-5) with lines lw 2 title 'SI, '.label(s), \
     for [s in "055 100"] dir.'/narrow_cgs_s'.s.'/snapshots_centred.dat' index 3 using 1:($2-5) with lines lw 2 dt 2 title 'CGS, '.label(s)
unset multiplot
set size noratio
}

# Error against run time (work-precision): one line per coupling and mesh size, Δt halving along it.
conv = dir.'/convergence.csv'
if (system('test -f '.conv.' && echo 1 || echo 0') eq "1") {
  set output figdir.'/single_cell_migration_work_precision.png'
  set terminal pngcairo size 1050,560 font ',11'
  set datafile separator ','
  set datafile columnheaders
  set size noratio
  set size 1,1
  set autoscale
  unset xrange
  unset yrange
  set logscale xy
  set format y '10^{%L}'
  set title sprintf('Error of the centroid height at %s against wall time (narrow channel, one thread)', '0.25 ms')
  set xlabel 'wall time of the run (s)'
  set ylabel '|y - y_{finest}| (um)'
  set key outside right top
  sel(c, h) = sprintf("< awk -F, 'NR==1 || ($1==\"%s\" && $2==%s)' %s", c, h, conv)
  plot for [h in "0.5 0.25 0.125"] sel("explicit", h) using 5:($7 > 0 ? $7 : 1/0) with linespoints pt 7 title 'explicit, h = '.h.' um', \
       for [h in "0.5 0.25 0.125"] sel("semi-implicit", h) using 5:($7 > 0 ? $7 : 1/0) with linespoints pt 5 dt 2 title 'semi-implicit, h = '.h.' um', \
       for [h in "0.5 0.25 0.125"] sel("semi-implicit Richardson", h) using 5:($7 > 0 ? $7 : 1/0) with linespoints pt 9 dt 3 title 'semi-implicit, Richardson, h = '.h.' um', \
       sel("semi-implicit-extrapolated", "0.125") using 5:($7 > 0 ? $7 : 1/0) with linespoints pt 11 lw 2 title 'semi-implicit, extrapolated Lie (incremental p), h = 0.125 um'
}

# The movie: the s* = 0.7 cell in the narrow channel, the whole run (experiments/common/movie.gp).
movie_files = dir.'/narrow_si_s070/frames.dat'
if (system('test -s '.movie_files.' && echo 1') eq '1') {
  movie_labels = 's* = 0.7, the narrow channel (20 x 10 um, periodic in x_1)'
  movie_title = 'One cell leaving the wall (Figs. 3-4)'
  movie_out = figdir.'/single_cell_migration_movie.gif'
  load system('dirname '.ARG0).'/../common/movie.gp'  # beside this script, from any folder
}
