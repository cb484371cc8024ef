# Figures of the cell_free_layer experiment (Figs. 9-10 of DOI 10.1002/fld.2455, redrawn from our runs).
#   gnuplot -e "dir='results/cell_free_layer'; figdir='paper/report/figures'" experiments/cell_free_layer/plot.gp
if (!exists("dir")) dir = 'results/cell_free_layer'
if (!exists("figdir")) figdir = dir
L = 100.0; H = 50.0
wrap(x) = x - L*floor(x/L)
# The index (0-based) of the snapshot nearest to t ms in a snapshots.dat (one block per '# t =').
index_at(f, t) = int(system(sprintf("awk '/^# t =/{d=$4*1e3-%g; if(d<0)d=-d; if(n==0||d<best){best=d; k=n}; n++} END{print k+0}' %s", t, f)))
time_at(f, k) = real(system(sprintf("awk '/^# t =/{if(n==%d)print $4*1e3; n++}' %s", k, f)))
# Each row's reported run: its finest Δt (figure_runs.txt, written by --check).
run(c) = system(sprintf("awk -v c=%s '$1 == c {print $2}' %s/figure_runs.txt 2>/dev/null | grep . || echo %s", c, dir, c))
last_time(c) = real(system(sprintf("tail -1 %s/layer_%s.dat | awk '{print $1}'", dir, run(c))))

# Figs. 9 and 10: the membranes at the study's four instants (x1 modulo L).
set terminal pngcairo size 1200, 700 font ',10'
do for [n in "50 100"] {
  c = 'n'.n
  f = sprintf('%s/%s/snapshots.dat', dir, run(c))
  tend = last_time(c)
  times = n eq '50' ? sprintf('0 %g %g %g', tend/3, 2*tend/3, tend) : sprintf('0 %g %g %g', tend/2, 3*tend/4, tend)
  set output figdir.'/cell_free_layer_membranes_'.n.'.png'
  set multiplot layout 2,2 title n.' cells, s* = 0.7 (Hct '.(n eq '50' ? '17.24' : '34.48').' %)'
  set size ratio -1
  set xrange [0:L]; set yrange [0:H]
  set xlabel 'x_1 (um)'; set ylabel 'x_2 (um)'
  unset key
  do for [w in times] {
    k = index_at(f, real(w))
    set title sprintf('t = %.0f ms', time_at(f, k))
    plot f index k using (wrap($1*1e6)):($2*1e6) with points pt 7 ps 0.15 lc rgb 'red'
  }
  unset multiplot
}

# The cell-free layer against time (mean of the walls; the other arrangements thin), the study's
# values and the empirical estimate 100/Hct at the end.
set size noratio
set terminal pngcairo size 1000, 620 font ',11'
set output figdir.'/cell_free_layer_layer.png'
set title 'Cell-free layer: gap between each wall and the nearest membrane node, mean of the two walls'
set xlabel 't (ms)'; set ylabel 'cell-free layer (um)'
set autoscale x; set autoscale y
set key outside bottom center horizontal maxcols 3
# (layer_n50.dat heads the list, drawn again under its thick line: gnuplot's plot iteration runs
# at least once, so the list must not be empty)
ens = 'layer_'.run('n50').'.dat '.system(sprintf("cd %s && ls layer_n*_seed*.dat 2>/dev/null | tr '\\n' ' '", dir))
long = last_time('n50') > 100
rep = dir.'/layer_n50_repulsion.dat'  # the evidence run (full runs only)
has_rep = system('test -f '.rep.' && echo 1 || echo 0') eq "1"
# (the other arrangements are make evidence's runs: drawn where it ran on this machine)
others = words(ens) > 1 ? ' (thin dashed: the other arrangements)' : ''
plot dir.'/layer_'.run('n50').'.dat' using 1:4 with lines lw 2 lc 1 title '50 cells, '.run('n50').others noenhanced, \
     dir.'/layer_'.run('n100').'.dat' using 1:4 with lines lw 2 lc 2 title '100 cells, '.run('n100').others noenhanced, \
     for [i=1:words(ens)] dir.'/'.word(ens, i) using 1:4 with lines lw 0.7 dt 2 lc (strstrt(word(ens, i), 'n100') ? 2 : 1) notitle, \
     (has_rep ? rep : dir.'/layer_'.run('n50').'.dat') using 1:(has_rep ? $4 : 1/0) with lines lw 1 dt 3 lc 3 title (has_rep ? '50 cells with the repulsion' : ''), \
     '-' using (long ? $1 : 1/0):2 with points pt 7 ps 1.5 lc rgb 'black' title 'study', \
     '-' using (long ? $1 : 1/0):2 with points pt 6 ps 1.5 lc rgb 'black' title 'empirical 100/Hct (the study''s comparison)'
150 6.24
200 2.94
e
150 5.8
200 2.9
e

# The 100 cells' layer against Δt, coupling, start and the pressure's form (full runs only: drawn
# when any of the evidence runs has been collected): the study's case at Δt = 3 and 1.5 us, with the
# study's form of the pressure at both, with the study's own scheme (explicit, to 20 ms), from wider
# wall gaps and without the repulsion.
ev = system(sprintf("cd %s && ls layer_n100_dt*.dat layer_n100_study_pressure*.dat layer_n100_wide_gaps.dat layer_n100_explicit_early.dat layer_n100_no_repulsion.dat 2>/dev/null | tr '\\n' ' '", dir))
if (words(ev) > 0) {
  set output figdir.'/cell_free_layer_layer_evidence.png'
  set title '100 cells: the cell-free layer (mean of the walls) against the time step, the pressure''s form, the coupling and the start'
  set xlabel 't (ms)'; set ylabel 'cell-free layer (um)'
  set xrange [0:205]; set autoscale y
  set key outside bottom center horizontal maxcols 3
  label(f) = strstrt(f, 'wide') ? 'dt = 3 us, started 2.9 um off the walls' : \
             strstrt(f, 'no_repulsion') ? 'dt = 3 us, no repulsion' : \
             strstrt(f, 'study_pressure_dt1.5us') ? 'dt = 1.5 us, the study''s pressure form' : \
             strstrt(f, 'study_pressure') ? 'dt = 3 us, the study''s pressure form' : \
             strstrt(f, 'explicit') ? 'the study''s scheme (explicit, its pressure form), dt = 0.05 us, to 20 ms' : \
             strstrt(f, 'dt1.5us') ? 'dt = 1.5 us' : f
  plot dir.'/layer_n100.dat' using 1:4 with lines lw 1.5 lc 2 title 'dt = 3 us (the study''s case)', \
       for [i=1:words(ev)] dir.'/'.word(ev, i) using 1:4 with lines lw 1.5 lc (i + 2) title label(word(ev, i)), \
       '+' using (200):(2.94) every ::0::0 with points pt 7 ps 1.5 lc rgb 'black' title 'study'
}

# The time-averaged hematocrit across the channel.
set output figdir.'/cell_free_layer_profile.png'
set title 'Area fraction of cells across the channel, averaged over the last snapshots'
set xlabel 'x_2 (um)'; set ylabel 'Hct(x_2) (%)'
set xrange [0:H]; set yrange [0:*]
plot dir.'/profile_'.run('n50').'.dat' using 1:2 with lines lw 2 lc 1 title '50 cells', \
     dir.'/profile_'.run('n100').'.dat' using 1:2 with lines lw 2 lc 2 title '100 cells'

# Error against run time (work-precision), full runs only: one line per coupling and h (drawn
# when the table has a run with an error; a sweep collected before its conv_* cases has none).
conv = dir.'/convergence.csv'
if (system("test -f ".conv." && awk -F, 'NR > 1 && $6 > 0 {n++} END {print (n > 0)}' ".conv." || echo 0") eq "1") {
  set terminal pngcairo size 800, 680 font ',11'
  set output figdir.'/cell_free_layer_work_precision.png'
  set datafile separator ','
  set autoscale
  set logscale xy
  set format y '10^{%L}'
  set title 'RMS error of the 50 centroids at 1.2 ms against wall time'
  set xlabel 'wall time of the run (s)'
  set ylabel 'RMS |x - x^{finest}| (um)'
  set key below left Left reverse maxcols 1  # below the axes: the runs reach every corner
  hs = system(sprintf("awk -F, 'NR > 1 {print $2}' %s | sort -gru | tr '\\n' ' '", conv))  # the table's h, coarse first
  sel(k, h) = sprintf("< awk -F, 'NR==1 || ($1==\"%s\" && $2==%s && $8==\"\")' %s", k, h, conv)
  # The kinds (convergence.csv, no commas in them): the coupling + the pressure's form.
  plot for [h in hs] sel("semi-implicit + incremental p", h) using 5:($6 > 0 ? $6 : 1/0) skip 1 with linespoints pt 5 dt 2 title 'semi-implicit, incremental p (the experiment''s), h = '.h.' um', \
       sel("semi-implicit + study-form p", "0.3125") using 5:($6 > 0 ? $6 : 1/0) skip 1 with linespoints pt 4 dt 3 title 'semi-implicit, the study''s form of p, h = 0.3125 um', \
       for [h in hs] sel("explicit + study-form p", h) using 5:($6 > 0 ? $6 : 1/0) skip 1 with linespoints pt 7 title 'explicit, the study''s form of p (the study''s scheme), h = '.h.' um', \
       sel("explicit + incremental p", "0.3125") using 5:($6 > 0 ? $6 : 1/0) skip 1 with linespoints pt 6 title 'explicit, incremental p, h = 0.3125 um', \
       for [h in hs] sel("semi-implicit-extrapolated + incremental p", h) using 5:($6 > 0 ? $6 : 1/0) skip 1 with linespoints pt 11 lw 2 title 'semi-implicit, extrapolated Lie, incremental p, h = '.h.' um'
}

# The rows as distributions (reference/reference_table.hpp): each arrangement at the rows' Δt and
# the study's value, per crowd; beside it the arrangements' spread against time (its plateau: the
# starts have decorrelated). Drawn where ensemble_n50.dat or ensemble_n100.dat has two members.
members(n) = int(system(sprintf("grep -vc '^#' %s/ensemble_n%s.dat 2>/dev/null || echo 0", dir, n)))
if (members('50') > 1 || members('100') > 1) {
  set datafile separator whitespace
  unset logscale; unset format; set format y '%g'
  set terminal pngcairo size 1200, 520 font ',11'
  set output figdir.'/cell_free_layer_ensemble.png'
  set multiplot layout 1,2 title 'The crowds as distributions: every arrangement at the rows'' Δt'
  set title 'Cell-free layer over the last ms (mean of the walls)'
  set xlabel 'arrangement (seed)'; set ylabel 'cell-free layer (um)'
  set autoscale; set xrange [0:7]; set yrange [0:*]
  set key below maxcols 2
  # (the study's values as the experiment wrote them into each file's head, from reference-data/)
  study(n) = real(system(sprintf("awk '$2 == \"study\" {print $3}' %s/ensemble_n%s.dat 2>/dev/null | grep . || echo NaN", dir, n)))
  study50 = study('50')
  study100 = study('100')
  crowds = system(sprintf("cd %s && for n in 50 100; do [ -f ensemble_n$n.dat ] && [ -f spread_n$n.dat ] && printf '%%s ' $n; done", dir))
  plot for [n in crowds] dir.'/ensemble_n'.n.'.dat' using 2:3 with points pt 7 ps 1.4 lc (n eq '50' ? 1 : 2) title n.' cells, ours', \
       study50 with lines dt 2 lw 2 lc 1 title 'study, 50 cells', study100 with lines dt 2 lw 2 lc 2 title 'study, 100 cells'
  set title 'Spread of the layer over the arrangements against time'
  set xlabel 't (ms)'; set ylabel 's over the arrangements (um)'
  set autoscale; set yrange [0:*]
  plot for [n in crowds] dir.'/spread_n'.n.'.dat' using 1:3 with lines lw 2 lc (n eq '50' ? 1 : 2) title n.' cells'
  unset multiplot
}

# The movie: the 100 cells, the reported run (experiments/common/movie.gp).
movie_files = sprintf('%s/%s/frames.dat', dir, run('n100'))
if (system('test -s '.movie_files.' && echo 1') eq '1') {
  movie_labels = '100 cells (Hct 34 %), '.run('n100')
  movie_title = 'The cell-free layer forming (Fig. 10)'
  movie_out = figdir.'/cell_free_layer_movie.gif'
  load system('dirname '.ARG0).'/../common/movie.gp'  # beside this script, from any folder
}
