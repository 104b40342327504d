# ts_D_ca.gp: written by `capflow figure`; edit and re-run `gnuplot ts_D_ca.gp`
# Taylor deformation D (top) and the capillary number Ca it was driven with (bottom) against time
# data: ts_D_ca.dat (block i = index i)
# source: runs/quick_demo/timeseries.csv
set encoding utf8
set minussign
set border lw 1.2
set grid lc rgb '#d0d0d0' lw 1
set tics nomirror out scale 0.6
set xlabel '{/:Italic t} / {/:Italic G}^{−1}'
set autoscale fix
set offsets graph 0.03, graph 0.03, graph 0.06, graph 0.06
dat = 'ts_D_ca.dat'
# vector image
set terminal svg size 800,800 dynamic enhanced font 'DejaVu Sans,14' background '#ffffff'
set output 'ts_D_ca.svg'
set multiplot layout 2,1 margins 0.13,0.97,0.15,0.98 spacing 0,0.03
set format x ''
unset xlabel
set ylabel 'Taylor deformation {/:Italic D}'
unset logscale y
unset key
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title 'quick\_demo'
set format x '%g'
set xlabel '{/:Italic t} / {/:Italic G}^{−1}'
set ylabel 'capillary number Ca'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 1 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title 'quick\_demo'
unset multiplot
# raster image
set terminal pngcairo size 1000,1000 enhanced font 'DejaVu Sans,12' background '#ffffff'
set output 'ts_D_ca.png'
set multiplot layout 2,1 margins 0.13,0.97,0.15,0.98 spacing 0,0.03
set format x ''
unset xlabel
set ylabel 'Taylor deformation {/:Italic D}'
unset logscale y
unset key
plot \
  dat index 0 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title 'quick\_demo'
set format x '%g'
set xlabel '{/:Italic t} / {/:Italic G}^{−1}'
set ylabel 'capillary number Ca'
unset logscale y
set key below horizontal center Left reverse samplen 2.5 spacing 1.1 width 2 noopaque nobox
plot \
  dat index 1 using 1:2 with lines lw 2 lc rgb '#0072b2' dt 1 title 'quick\_demo'
unset multiplot
set output
