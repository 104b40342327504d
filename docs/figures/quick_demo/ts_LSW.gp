# ts_LSW.gp: written by `capflow figure`; edit and re-run `gnuplot ts_LSW.gp`
# Half-lengths L, S, W (inertia ellipsoid) vs t (paper figs. 5, 11)
# data: ts_LSW.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set title 'Half-lengths L, S, W (inertia ellipsoid) vs t' noenhanced
set xlabel 't'
set ylabel 'half-length'
set key top left box opaque
set grid
dat = 'ts_LSW.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'Sans,14' background '#ffffff'
set output 'ts_LSW.svg'
plot \
  dat index 0 using 1:2 with lines lw 2 lc 1 dt 1 title 'quick_demo: L' noenhanced, \
  dat index 0 using 1:3 with lines lw 2 lc 1 dt 2 title 'quick_demo: S' noenhanced, \
  dat index 0 using 1:4 with lines lw 2 lc 1 dt 4 title 'quick_demo: W' noenhanced
# raster image
set terminal pngcairo size 1000,750 enhanced font 'Sans,12'
set output 'ts_LSW.png'
replot
set output
