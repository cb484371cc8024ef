# A movie of one or more runs, one panel each, from their frames.dat ([output] frames; the format:
# lib/scene/movie_frames.hpp): an animated GIF (gnuplot's gif terminal; Debian's gnuplot-nox has it,
# no video encoder needed). Called by the experiments' plot.gp:
#   movie_files = 'a/frames.dat b/frames.dat'; movie_labels = 'cells|disks'
#   movie_title = '...'; movie_out = 'figures/x_movie.gif'; load system('dirname '.ARG0).'/../common/movie.gp'
# The panels share the frames of the shortest run; the membranes are red, the disks blue with a
# radius that shows their turn, the obstacles grey (each filled in a light shade); the walls are the thick lines at x2 = 0 and H.
reset
panels = words(movie_files)
f1 = word(movie_files, 1)
L = real(system(sprintf("awk 'NR == 1 {print $(NF - 1) * 1e6}' %s", f1)))  # um, drawn (the file's unit: m)
H = real(system(sprintf("awk 'NR == 1 {print $NF * 1e6}' %s", f1)))
frames = 1e9
do for [p = 1:panels] {
  n = int(system(sprintf("grep -c '^# t =' %s", word(movie_files, p))))
  frames = (n < frames) ? n : frames
}
times_ms = system(sprintf("awk '/^# t =/ {printf \"%%.6f\\n\", 1e3 * $4}' %s", f1))  # (gnuplot reads no 1e-05)
label(p) = system(sprintf("echo '%s' | cut -d'|' -f%d", movie_labels, p))
colour(kind) = kind == 0 ? 0xb22222 : kind == 1 ? 0x1f5fa8 : 0x707070
fill(kind) = kind == 0 ? 0xf2c8c8 : kind == 1 ? 0xc8d8ee : 0xdcdcdc  # solid, light: few colours, a small GIF

width = 720
panel_height = int(width * H / L) + 50
set terminal gif animate delay 10 loop 0 size width, panels * panel_height + 40 font ',10'
set output movie_out
set size ratio -1
set xrange [0:L]; set yrange [0:H]
unset key; unset xtics; unset ytics
set border 15 lw 0.5 lc rgb 'gray60'
set arrow 1 from 0, 0 to L, 0 nohead lw 3 lc rgb 'black' front
set arrow 2 from 0, H to L, H nohead lw 3 lc rgb 'black' front
do for [k = 0:frames - 1] {
  set multiplot layout panels, 1 title sprintf('%s    t = %.2f ms', movie_title, real(word(times_ms, k + 1)))
  do for [p = 1:panels] {
    set title label(p)
    plot word(movie_files, p) index k using ($1 * 1e6):($2 * 1e6):(fill($3)) with filledcurves closed fc rgb variable fs solid 1.0 noborder, \
         '' index k using ($1 * 1e6):($2 * 1e6):(colour($3)) with lines lw 1.5 lc rgb variable
  }
  unset multiplot
}
set output
unset arrow 1; unset arrow 2
