# ts_LSW.gp: written by `capflow figure`; edit and re-run `gnuplot ts_LSW.gp`
# Half-lengths L, S, W of the inertia ellipsoid against time (paper figs. 5, 11)
# data: ts_LSW.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set minussign
set border lw 1.2
set grid lc rgb '#d0d0d0' lw 1
set tics nomirror out scale 0.6
set xlabel '{/:Italic t} / {/:Italic G}^{−1}'
set autoscale fix
set offsets graph 0.03, graph 0.03, graph 0.06, graph 0.06
dat = 'ts_LSW.dat'
# vector image
set terminal svg size 800,600 dynamic enhanced font 'DejaVu Sans,14' background '#ffffff'
set output 'ts_LSW.svg'
set ylabel 'half-lengths {/:Italic L}, {/:Italic S}, {/:Italic W} / {/:Italic a}'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title '{/:Italic L}', \
  dat index 0 using 1:3 with lines lw 2 lc rgb '#d55e00' dt 1 title '{/:Italic S}', \
  dat index 0 using 1:4 with lines lw 2 lc rgb '#009e73' dt 1 title '{/:Italic W}'
# raster image
set terminal pngcairo size 1000,750 enhanced font 'DejaVu Sans,12' background '#ffffff'
set output 'ts_LSW.png'
set ylabel 'half-lengths {/:Italic L}, {/:Italic S}, {/:Italic W} / {/:Italic a}'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title '{/:Italic L}', \
  dat index 0 using 1:3 with lines lw 2 lc rgb '#d55e00' dt 1 title '{/:Italic S}', \
  dat index 0 using 1:4 with lines lw 2 lc rgb '#009e73' dt 1 title '{/:Italic W}'
set output
