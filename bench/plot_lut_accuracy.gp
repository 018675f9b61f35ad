# Error against device time for the DFG tables, one curve per estimator and precision.
#   gnuplot -e "csv='bench-out/lut_accuracy.csv'; kind='ggx'; out='docs/lut_accuracy_ggx.png'" bench/plot_lut_accuracy.gp
if (!exists("csv")) csv = 'bench-out/lut_accuracy.csv'
if (!exists("kind")) kind = 'ggx'
if (!exists("out")) out = 'docs/lut_accuracy_'.kind.'.png'
set terminal pngcairo size 900,600 noenhanced
set output out
set datafile separator ','
set logscale xy
set format y '%.0e'
set grid
set key outside right
set xlabel 'device time of the 128x128 table (ms, PoCL, 2 cores)'
set ylabel 'max error against the converged reference'
set title 'DFG table '.kind.': accuracy against time (labels: samples per texel)'
sel(e, p) = sprintf("< awk -F, '$1==\"%s\" && $2==\"%s\" && $3==\"%s\"' %s", kind, e, p, csv)
plot for [e in "quadrature vndf ndf uniform"] for [p in "fp32 fp64"] \
       sel(e, p) using ($6*1000):7 with linespoints title e.' '.p, \
     sel('quadrature', 'fp32') using ($6*1000):7:4 with labels offset 0,1 font ',8' notitle, \
     1e-4 with lines dashtype 2 lc 'black' title '1e-4 goal'
