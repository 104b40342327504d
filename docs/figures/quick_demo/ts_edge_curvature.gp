# ts_edge_curvature.gp: written by `capflow figure`; edit and re-run `gnuplot ts_edge_curvature.gp`
# Edge curvature (z = 0 profile, +x tip) against time (paper figs. 8, 13)
# data: ts_edge_curvature.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set minussign
set border lw 1.2
set grid lc rgb '#d0d0d0' lw 1
set tics nomirror out scale 0.6
set xlabel '{/:Italic t} / {/:Italic G}^{−1}'
set autoscale fix
set offsets graph 0.03, graph 0.03, graph 0.06, graph 0.06
dat = 'ts_edge_curvature.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'DejaVu Sans,14' background '#ffffff'
set output 'ts_edge_curvature.svg'
set ylabel 'edge curvature {/:Italic κ} / {/:Italic a}^{−1}'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title 'quick\_demo'
# raster image
set terminal pngcairo size 1000,750 enhanced font 'DejaVu Sans,12' background '#ffffff'
set output 'ts_edge_curvature.png'
set ylabel 'edge curvature {/:Italic κ} / {/:Italic a}^{−1}'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title 'quick\_demo'
set output
