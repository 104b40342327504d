# ts_edge_curvature.gp: written by `capflow figure`; edit and re-run `gnuplot ts_edge_curvature.gp`
# Edge curvature (z = 0 profile, +x tip) vs t (paper figs. 8, 13)
# data: ts_edge_curvature.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set title 'Edge curvature (z = 0 profile, +x tip) vs t' noenhanced
set xlabel 't'
set ylabel 'edge curvature'
set key top left box opaque
set grid
dat = 'ts_edge_curvature.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'Sans,14' background '#ffffff'
set output 'ts_edge_curvature.svg'
plot \
  dat index 0 using 1:2 with lines lw 2 lc 1 dt 1 title 'quick_demo' noenhanced
# raster image
set terminal pngcairo size 1000,750 enhanced font 'Sans,12'
set output 'ts_edge_curvature.png'
replot
set output
