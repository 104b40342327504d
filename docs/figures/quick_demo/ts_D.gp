# ts_D.gp: written by `capflow figure`; edit and re-run `gnuplot ts_D.gp`
# Taylor deformation D(t) (paper figs. 5a, 11a)
# data: ts_D.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set title 'Taylor deformation D(t)' noenhanced
set xlabel 't'
set ylabel 'D'
set key top left box opaque
set grid
dat = 'ts_D.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'Sans,14' background '#ffffff'
set output 'ts_D.svg'
plot \
  dat index 0 using 1:2 with lines lw 2 lc 1 dt 1 title 'quick_demo' noenhanced
# raster image
set terminal pngcairo size 1000,750 enhanced font 'Sans,12'
set output 'ts_D.png'
replot
set output
