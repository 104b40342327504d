# profiles_quick_demo_y.gp: written by `capflow figure`; edit and re-run `gnuplot profiles_quick_demo_y.gp`
# Profile in the plane y = 0, run quick_demo (paper figs. 6b, 7b, 12b)
# data: profiles_quick_demo_y.dat (block i = index i)
# source: runs/quick_demo/profiles/profile_000000.csv
# source: runs/quick_demo/profiles/profile_000020.csv
# source: runs/quick_demo/profiles/profile_000040.csv
# source: runs/quick_demo/profiles/profile_000060.csv
set encoding utf8
set title 'Profile in the plane y = 0, run quick_demo' noenhanced
set xlabel 'x'
set ylabel 'z'
set key outside right top box opaque
set grid
set size ratio -1
dat = 'profiles_quick_demo_y.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'Sans,14' background '#ffffff'
set output 'profiles_quick_demo_y.svg'
plot \
  dat index 0 using 1:2 with lines lw 1 lc rgb '#808080' dt 2 title 'undisturbed' noenhanced, \
  dat index 1 using 1:2 with lines lw 2 lc 1 title 't = 0' noenhanced, \
  dat index 2 using 1:2 with lines lw 2 lc 2 title 't = 0.8' noenhanced, \
  dat index 3 using 1:2 with lines lw 2 lc 3 title 't = 1.6' noenhanced, \
  dat index 4 using 1:2 with lines lw 2 lc 4 title 't = 2.4' noenhanced
# raster image
set terminal pngcairo size 1000,750 enhanced font 'Sans,12'
set output 'profiles_quick_demo_y.png'
replot
set output
