# Figures of the four_cells_vs_disks experiment (Figs. 6-8 of DOI 10.1002/fld.2455, redrawn from our runs).
#   gnuplot -e "dir='results/four_cells_vs_disks'; figdir='paper/report/figures'" experiments/four_cells_vs_disks/plot.gp
if (!exists("dir")) dir = 'results/four_cells_vs_disks'
if (!exists("figdir")) figdir = dir
L = 100.0; H = 50.0
wrap(x) = x - L*floor(x/L)
cases = "kb1 kb10 kb100 kb1000 s07 disks"
label(c) = c eq 'kb1' ? 's* = 1, k_b' : c eq 'kb10' ? 's* = 1, 10 k_b' : c eq 'kb100' ? 's* = 1, 100 k_b' : \
           c eq 'kb1000' ? 's* = 1, 1000 k_b' : c eq 's07' ? 's* = 0.7, k_b' : 'rigid disks, r = 2.8 um'
# Each case as its rows report it: its finest Δt run (figure_runs.txt, written by --check).
run(c) = system(sprintf("awk -v c=%s '$1 == c {print $2}' %s/figure_runs.txt 2>/dev/null | grep . || echo %s", c, dir, c))
last_time(c) = system(sprintf("tail -1 %s/heights_%s.dat | awk '{print $1}'", dir, run(c)))

# Figs. 6 and 7 (right): the membranes and the disks at the end of each run.
set terminal pngcairo size 1200, 900 font ',10'
set output figdir.'/four_cells_vs_disks_membranes.png'
set multiplot layout 3,2 title 'Cells and disks at the end of the run (membranes: x_1 modulo L)'
set size ratio -1
set xrange [0:L]; set yrange [0:H]
set xlabel 'x_1 (um)'; set ylabel 'x_2 (um)'
unset key
set arrow 1 from 0, H/2 to L, H/2 nohead dt 2 lc rgb 'gray50'
do for [c in cases] {
  set title label(c).' at t = '.last_time(c).' ms'
  if (c eq 'disks') {
    plot dir.'/'.run('disks').'/disks_end.dat' using 1:2:3 with circles fs solid 0.3 lc rgb 'blue', \
         '' using ($1 - L):2:3 with circles fs solid 0.3 lc rgb 'blue', '' using ($1 + L):2:3 with circles fs solid 0.3 lc rgb 'blue'
  } else {
    n = int(system(sprintf("grep -c '^# t =' %s/%s/snapshots.dat", dir, run(c))))
    plot sprintf('%s/%s/snapshots.dat', dir, run(c)) index n-1 using (wrap($1*1e6)):($2*1e6) with points pt 7 ps 0.3 lc rgb 'red'
  }
}
unset multiplot
unset arrow 1

# Figs. 6-8 (left): the bodies' centroid heights against time.
set size noratio
set terminal pngcairo size 1200, 900 font ',10'
set output figdir.'/four_cells_vs_disks_heights.png'
set multiplot layout 3,2 title 'Centroid heights x_2 of the four bodies (centreline 25 um)'
set autoscale x; set yrange [0:H]
set xlabel 't (ms)'; set ylabel 'x_2 (um)'
do for [c in cases] {
  set title label(c)
  plot for [k=2:5] sprintf('%s/heights_%s.dat', dir, run(c)) using 1:k with lines lw 1.5
}
unset multiplot

# The mean distance from the centreline against time, every case, the perturbed starts thin, the
# study's values at 200 ms as points.
set terminal pngcairo size 1000, 680 font ',11'
set output figdir.'/four_cells_vs_disks_distance.png'
set title 'Mean distance of the four bodies from the centreline (perturbed starts: thin dashed)'
set xlabel 't (ms)'; set ylabel 'mean |x_2 - H/2| (um)'
set autoscale y
set key outside bottom center horizontal maxcols 3
long = real(last_time('kb1')) > 100  # the study's points only beside a full run
# (the reported k_b run heads the list, drawn again under its thick line: gnuplot's plot iteration
# runs at least once, so the list must not be empty — make reproduce has no perturbed starts)
ens = 'heights_'.run('kb1').'.dat '.system(sprintf("cd %s && ls heights_*_seed*.dat 2>/dev/null | tr '\\n' ' '", dir))
plot for [i=1:words(cases)] sprintf('%s/heights_%s.dat', dir, run(word(cases, i))) using 1:6 with lines lw 2 lc i title label(word(cases, i)), \
     for [f in ens] dir.'/'.f using 1:6 with lines lw 0.7 dt 2 lc (strstrt(f, 'disks') ? 6 : 1) notitle, \
     '-' using (long ? $1 : 1/0):2 with points pt 7 ps 1.5 lc rgb 'black' title 'study, 200 ms (k_b ... 1000 k_b, disks)'
200 9.22
200 9.38
200 11.10
200 12.23
200 12.73
e

# Error against run time (work-precision), full runs only: one line per bodies/coupling and h
# (drawn when the table has a run with an error: make reproduce's study-only runs have none).
conv = dir.'/convergence.csv'
if (system("test -f ".conv." && awk -F, 'NR > 1 && $6 > 0 {n++} END {print (n > 0)}' ".conv." || echo 0") eq "1") {
  set terminal pngcairo size 800, 560 font ',11'
  set output figdir.'/four_cells_vs_disks_work_precision.png'
  set datafile separator ','
  set autoscale
  set logscale xy
  set format y '10^{%L}'
  set title 'RMS error of the centroid heights x_2 at 1.2 ms against wall time (four cells against four disks)'
  set xlabel 'wall time of the run (s)'
  set ylabel 'RMS |x_2 - x_2^{finest}| (um)'
  set key bottom left inside
  hs = system(sprintf("awk -F, 'NR > 1 {print $2}' %s | sort -gru | tr '\\n' ' '", conv))  # the table's h, coarse first
  sel(k, h) = sprintf("< awk -F, 'NR==1 || ($1==\"%s\" && $2==%s && $8==\"\")' %s", k, h, conv)
  plot for [h in hs] sel("semi-implicit", h) using 5:($7 > 0 ? $7 : 1/0) skip 1 with linespoints pt 5 dt 2 title 'cells, semi-implicit, h = '.h.' um', \
       for [h in hs] sel("explicit", h) using 5:($7 > 0 ? $7 : 1/0) skip 1 with linespoints pt 7 title 'cells, explicit, h = '.h.' um', \
       for [h in hs] sel("disks", h) using 5:($7 > 0 ? $7 : 1/0) skip 1 with linespoints pt 9 title 'disks, h = '.h.' um', \
       for [h in hs] sel("semi-implicit Richardson", h) using 5:($7 > 0 ? $7 : 1/0) skip 1 with linespoints pt 4 dt 3 title 'cells, semi-implicit, Richardson, h = '.h.' um', \
       for [h in hs] sel("semi-implicit-extrapolated", h) using 5:($7 > 0 ? $7 : 1/0) skip 1 with linespoints pt 11 lw 2 title 'cells, semi-implicit, extrapolated Lie (incremental p), h = '.h.' um'
}

# The movie: the four cells (s* = 1, k_b) and the four disks side by side, each its reported run.
movie_files = sprintf('%s/%s/frames.dat %s/%s/frames.dat', dir, run('kb1'), dir, run('disks'))
if (system(sprintf('test -s %s && test -s %s && echo 1', word(movie_files, 1), word(movie_files, 2))) eq '1') {
  movie_labels = label('kb1').', '.run('kb1').'|'.label('disks').', '.run('disks')
  movie_title = 'Four cells and four disks (Figs. 6-7)'
  movie_out = figdir.'/four_cells_vs_disks_movie.gif'
  load system('dirname '.ARG0).'/../common/movie.gp'  # beside this script, from any folder
}
