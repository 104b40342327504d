# profiles_quick_demo_z.gp: written by `capflow figure`; edit and re-run `gnuplot profiles_quick_demo_z.gp`
# Profile of run quick_demo in the plane z = 0 at several times (paper figs. 6a, 7a, 12a)
# data: profiles_quick_demo_z.dat (block i = index i)
# source: runs/quick_demo/profiles/profile_000000.csv
# source: runs/quick_demo/profiles/profile_000020.csv
# source: runs/quick_demo/profiles/profile_000040.csv
# source: runs/quick_demo/profiles/profile_000060.csv
set encoding utf8
set minussign
set border lw 1.2
set grid lc rgb '#d0d0d0' lw 1
set tics nomirror out scale 0.6
set xlabel '{/:Italic x} / {/:Italic a}'
set autoscale fix
set offsets graph 0.03, graph 0.03, graph 0.06, graph 0.06
set size ratio -1
dat = 'profiles_quick_demo_z.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'DejaVu Sans,14' background '#ffffff'
set output 'profiles_quick_demo_z.svg'
set ylabel '{/:Italic y} / {/:Italic a}'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 1 lc rgb '#808080' dt 2 title 'undisturbed', \
  dat index 1 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title '{/:Italic t} = 0', \
  dat index 2 using 1:2 with lines lw 2 lc rgb '#d55e00' dt 1 title '{/:Italic t} = 0.8', \
  dat index 3 using 1:2 with lines lw 2 lc rgb '#009e73' dt 1 title '{/:Italic t} = 1.6', \
  dat index 4 using 1:2 with lines lw 2 lc rgb '#cc79a7' dt 1 title '{/:Italic t} = 2.4'
# raster image
set terminal pngcairo size 1000,750 enhanced font 'DejaVu Sans,12' background '#ffffff'
set output 'profiles_quick_demo_z.png'
set ylabel '{/:Italic y} / {/:Italic a}'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 1 lc rgb '#808080' dt 2 title 'undisturbed', \
  dat index 1 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title '{/:Italic t} = 0', \
  dat index 2 using 1:2 with lines lw 2 lc rgb '#d55e00' dt 1 title '{/:Italic t} = 0.8', \
  dat index 3 using 1:2 with lines lw 2 lc rgb '#009e73' dt 1 title '{/:Italic t} = 1.6', \
  dat index 4 using 1:2 with lines lw 2 lc rgb '#cc79a7' dt 1 title '{/:Italic t} = 2.4'
set output
