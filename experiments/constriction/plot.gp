# Figures of the constriction experiment (Figs. 11-13 of DOI 10.1002/fld.2455, redrawn from our run).
#   gnuplot -e "dir='results/constriction'; figdir='paper/report/figures'" experiments/constriction/plot.gp
if (!exists("dir")) dir = 'results/constriction'
if (!exists("figdir")) figdir = dir
run = dir.'/run'
L = 120.0
wrap(x) = x - L*floor(x/L)
# The blocks (um): 40-80 x 0-7.5 and 22.5-30.
set object 1 rect from 40,0 to 80,7.5 fc rgb 'gray70' fs solid border lc rgb 'black' front
set object 2 rect from 40,22.5 to 80,30 fc rgb 'gray70' fs solid border lc rgb 'black' front
set size ratio -1
set xrange [0:120]; set yrange [0:30]
set xlabel 'x_1 (um)'; set ylabel 'x_2 (um)'
unset key

# Fig. 11: membranes at the snapshot times (x1 taken modulo L; a cell across x1 = L is drawn in two parts).
n = int(system("grep -c '^# t =' ".run."/snapshots.dat"))
set terminal pngcairo size 1100, 260*n font ',10'
set output figdir.'/constriction_membranes.png'
set multiplot layout n,1 title 'Membranes (s* = 0.481) at the snapshot times'
do for [k=0:n-1] {
  set title system(sprintf("awk 'BEGIN{b=0} /^# t =/{if(b==%d){sub(/;.*/, \"\"); sub(/^# /, \"\"); print; exit} b++}' %s/snapshots.dat", k, run))
  plot run.'/snapshots.dat' index k using (wrap($1*1e6)):($2*1e6) with points pt 7 ps 0.25 lc rgb 'red'
}
unset multiplot

# Fig. 12: |u| (cm/s) at the last two snapshot times, with blocks and membranes.
set terminal pngcairo size 1100, 620 font ',10'
set output figdir.'/constriction_velocity.png'
set multiplot layout 2,1 title 'Velocity magnitude (cm/s)'
set cblabel '|u| (cm/s)'
set palette rgbformulae 33,13,10
do for [k=n-2:n-1] {
  set title system(sprintf("head -1 %s/field_%d.dat | sed 's/;.*//; s/# //'", run, k))
  plot run.'/field_'.k.'.dat' using ($1*1e6):($2*1e6):($3*100) with image, \
       run.'/snapshots.dat' index k using (wrap($1*1e6)):($2*1e6) with points pt 7 ps 0.2 lc rgb 'white'
}
unset multiplot

# Fig. 13: centroid heights against time.
unset object 1; unset object 2
set size noratio
set terminal pngcairo size 1000, 450 font ',11'
set output figdir.'/constriction_centroids.png'
set title 'Centroid heights x_2 of the 12 cells (passage: 7.5-22.5 um)'
set xlabel 't (ms)'; set ylabel 'x_2 (um)'
set autoscale x; set yrange [0:30]
set arrow 1 from graph 0, first 7.5 to graph 1, first 7.5 nohead dt 2 lc rgb 'gray40'
set arrow 2 from graph 0, first 22.5 to graph 1, first 22.5 nohead dt 2 lc rgb 'gray40'
plot for [c=2:13] dir.'/centroids.dat' using 1:c with lines lw 1.5

# Error against run time (work-precision): one line per coupling and mesh size, Δt halving along
# it (convergence.csv of the full run; the quick case has none).
conv = dir.'/convergence.csv'
if (system('test -f '.conv.' && echo 1 || echo 0') eq "1") {
  unset arrow 1; unset arrow 2
  set terminal pngcairo size 800, 560 font ',11'
  set output figdir.'/constriction_work_precision.png'
  set datafile separator ','
  set autoscale; unset xrange; unset yrange
  set logscale xy
  set format y '10^{%L}'
  set title 'RMS centroid error of the 12 cells at 1 ms against wall time (constriction)'
  set xlabel 'wall time of the run (s)'
  set ylabel 'RMS |x_c - x_c^{finest}| (um)'
  set key bottom left
  hs = system(sprintf("awk -F, 'NR > 1 {print $2}' %s | sort -gru | tr '\\n' ' '", conv))  # the table's h, coarse first
  sel(c, h) = sprintf("< awk -F, 'NR==1 || ($1==\"%s\" && $2==%s && $10==\"\")' %s", c, h, conv)
  plot for [h in hs] sel("semi-implicit", h) using 6:($8 > 0 ? $8 : 1/0) skip 1 with linespoints pt 5 dt 2 title 'semi-implicit, h = '.h.' um', \
       for [h in hs] sel("explicit", h) using 6:($8 > 0 ? $8 : 1/0) skip 1 with linespoints pt 7 title 'explicit, h = '.h.' um', \
       for [h in hs] sel("semi-implicit Richardson", h) using 6:($8 > 0 ? $8 : 1/0) skip 1 with linespoints pt 9 dt 3 title 'semi-implicit, Richardson, h = '.h.' um', \
       for [h in hs] sel("semi-implicit-extrapolated", h) using 6:($8 > 0 ? $8 : 1/0) skip 1 with linespoints pt 11 lw 2 title 'semi-implicit, extrapolated Lie, h = '.h.' um'
}

# The movie: the cells through the passage (experiments/common/movie.gp).
movie_files = dir.'/run/frames.dat'
if (system('test -s '.movie_files.' && echo 1') eq '1') {
  movie_labels = 'the constriction (obstacles grey)'
  movie_title = 'Cells through a constriction (Figs. 11-12)'
  movie_out = figdir.'/constriction_movie.gif'
  load system('dirname '.ARG0).'/../common/movie.gp'  # beside this script, from any folder
}
