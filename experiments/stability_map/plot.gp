# Stability map: largest stable Δt against k_l and k_b for the map's mesh sizes, both couplings and
# the semi-implicit one in the extrapolated Lie scheme.
#   gnuplot -e "dir='results/stability_map'; figdir='paper/report/figures'" experiments/stability_map/plot.gp
if (!exists("dir")) dir = 'results/stability_map'
if (!exists("figdir")) figdir = dir
set datafile separator ','
set terminal pngcairo size 1200,500 font ',10'
set output figdir.'/stability_map_dt.png'
set multiplot layout 1,2 title 'Largest stable time step, narrow channel, one s* = 0.55 cell (SI constants); dotted: advective cap (Q = 4)'
set logscale xy
set format y '10^{%L}'
set xlabel 'k_l / 5e-8 (k_b as in the study)'
set ylabel 'largest stable Δt (s)'
set key bottom left
hs = system(sprintf("awk -F, 'NR > 1 {print $2}' %s/stability_map.csv | sort -gru | tr '\\n' ' '", dir))  # the map's h, coarse first
sel(c, h, other) = sprintf("< awk -F, '$1==\"%s\" && $2==%s && $%d==1' %s/stability_map.csv", c, h, other, dir)
plot for [h in hs] sel("explicit", h, 4) using 3:5 with linespoints pt 7 title 'explicit, h = '.h.' µm', \
     for [h in hs] sel("semi-implicit", h, 4) using 3:5 with linespoints pt 5 dt 2 title 'semi-implicit, h = '.h.' µm', \
     for [h in hs] sel("semi-implicit-extrapolated", h, 4) using 3:5 with points pt 6 ps 1.6 title 'semi-implicit, extrapolated Lie, h = '.h.' µm', \
     for [h in hs] sel("semi-implicit", h, 4) using 3:7 with lines dt 3 lc rgb 'gray' notitle
set xlabel 'k_b / 5e-10 (k_l as in the study)'
plot for [h in hs] sel("explicit", h, 3) using 4:5 with linespoints pt 7 title 'explicit, h = '.h.' µm', \
     for [h in hs] sel("semi-implicit", h, 3) using 4:5 with linespoints pt 5 dt 2 title 'semi-implicit, h = '.h.' µm', \
     for [h in hs] sel("semi-implicit-extrapolated", h, 3) using 4:5 with points pt 6 ps 1.6 title 'semi-implicit, extrapolated Lie, h = '.h.' µm', \
     for [h in hs] sel("semi-implicit", h, 3) using 4:7 with lines dt 3 lc rgb 'gray' notitle
unset multiplot
