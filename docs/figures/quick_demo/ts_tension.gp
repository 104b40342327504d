# ts_tension.gp: written by `capflow figure`; edit and re-run `gnuplot ts_tension.gp`
# Largest and smallest principal tensions against time (paper figs. 9, 14)
# data: ts_tension.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set minussign
set border lw 1.2
set grid lc rgb '#d0d0d0' lw 1
set tics nomirror out scale 0.6
set xlabel '{/:Italic t} / {/:Italic G}^{−1}'
set autoscale fix
set offsets graph 0.03, graph 0.03, graph 0.06, graph 0.06
dat = 'ts_tension.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'DejaVu Sans,14' background '#ffffff'
set output 'ts_tension.svg'
set ylabel 'principal tension {/:Italic τ} / {/:Italic G}_s'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title '{/:Italic τ}_{max}', \
  dat index 0 using 1:3 with lines lw 2 lc rgb '#d55e00' dt 1 title '{/:Italic τ}_{min}'
# raster image
set terminal pngcairo size 1000,750 enhanced font 'DejaVu Sans,12' background '#ffffff'
set output 'ts_tension.png'
set ylabel 'principal tension {/:Italic τ} / {/:Italic G}_s'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title '{/:Italic τ}_{max}', \
  dat index 0 using 1:3 with lines lw 2 lc rgb '#d55e00' dt 1 title '{/:Italic τ}_{min}'
set output
