# ts_tension.gp: written by `capflow figure`; edit and re-run `gnuplot ts_tension.gp`
# Principal tensions tau_max and tau_min vs t (paper figs. 9, 14)
# data: ts_tension.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set title 'Principal tensions tau_max and tau_min vs t' noenhanced
set xlabel 't'
set ylabel 'tension / G_s'
set key top left box opaque
set grid
dat = 'ts_tension.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'Sans,14' background '#ffffff'
set output 'ts_tension.svg'
plot \
  dat index 0 using 1:2 with lines lw 2 lc 1 dt 1 title 'quick_demo: τ_max' noenhanced, \
  dat index 0 using 1:3 with lines lw 2 lc 1 dt 2 title 'quick_demo: τ_min' noenhanced
# raster image
set terminal pngcairo size 1000,750 enhanced font 'Sans,12'
set output 'ts_tension.png'
replot
set output
