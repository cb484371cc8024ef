# Figures of the channel_flow experiment.
#   gnuplot -e "dir='results/channel_flow'; figdir='paper/report/figures'" experiments/channel_flow/plot.gp
if (!exists("dir")) dir = 'results/channel_flow'
if (!exists("figdir")) figdir = dir
set datafile separator ','
set terminal pngcairo size 1100,420 font ',11'
set key bottom right

set output figdir.'/channel_flow_startup.png'
set multiplot layout 1,2 title 'Cell-free start-up from rest: mean velocity against the Fourier series'
do for [w in "narrow wide"] {
  set title w.' channel'
  set xlabel 't (ms)'
  set ylabel 'U (cm/s)'
  plot dir.'/'.w.'/startup.csv' every ::1 using ($1*1e3):($3*100) with lines lw 2 title 'exact (P1 mean)', \
       ''                      every 4::1 using ($1*1e3):($2*100) with points pt 6 title 'rbcflow'
}
unset multiplot

set output figdir.'/channel_flow_profile.png'
set multiplot layout 1,2 title 'Cell-free velocity profile at the end against the parabola f y (H - y) / (2 mu)'
do for [w in "narrow wide"] {
  set title w.' channel'
  set xlabel 'u_1 (cm/s)'
  set ylabel 'y (um)'
  plot dir.'/'.w.'/profile_vs_parabola.csv' every ::1 using ($3*100):($1*1e6) with lines lw 2 title 'parabola', \
       ''                                   every 2::1 using ($2*100):($1*1e6) with points pt 6 ps 0.6 title 'rbcflow'
}
unset multiplot
