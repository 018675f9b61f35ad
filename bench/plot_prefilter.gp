# Worst-level RMS relative error against device time for the prefiltered chain (256^2 -> 16^2, GGX),
# one curve per estimator and variant (bench/prefilter_bench's CSV).
#   gnuplot -e "csv='bench-out/prefilter_bench.csv'; env='builtin:sun'; out='docs/prefilter_accuracy_sun.png'" bench/plot_prefilter.gp
if (!exists("csv")) csv = 'bench-out/prefilter_bench.csv'
if (!exists("env")) env = 'builtin:sun'
if (!exists("out")) out = 'docs/prefilter_accuracy.png'
set terminal pngcairo size 900,600 noenhanced
set output out
set datafile separator ','
set logscale xy
set format y '%.0e'
set grid
set key outside right
set xlabel 'device time of the filtering (s, PoCL, 2 cores)'
set ylabel 'worst level: RMS relative error against the brute-force reference'
set title 'prefiltered GGX chain, '.env.': accuracy against time (labels: refinement / samples)'
sel(v) = sprintf("< awk -F, '$1==\"%s\" && $3==\"%s\"' %s", env, v, csv)
plot for [v in "quadrature+env quadrature FIS+env FIS plain+env plain"] \
       sel(v) using 5:6 with linespoints title v, \
     sel('quadrature+env') using 5:6:4 with labels offset 0,1 font ',8' notitle, \
     sel('FIS+env') using 5:6:4 with labels offset 0,1 font ',8' notitle, \
     0.01 with lines dashtype 2 lc 'black' title '1% goal'
