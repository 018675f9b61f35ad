# The roofline of `brdfbake report --kinds kernels` (issue 36) from its JSON: the device's measured
# fp32 and fp64 roofs, min(peak, flops per byte x triad GB/s), and each counted kernel as a point.
#   gnuplot -e "json='kernels.json'; out='docs/roofline_pocl.png'" bench/plot_roofline.gp
if (!exists("json")) json = 'kernels.json'
if (!exists("out")) out = 'roofline.png'
q(f) = system(sprintf("jq -r '.kernels.%s' %s", f, json))
p32 = real(q('peaks.fp32_gflops')); p64 = real(q('peaks.fp64_gflops')); bw = real(q('peaks.bandwidth_gbs'))
shape = q('kernel_shape'); device = system(sprintf("jq -r '.device' %s", json))
rows(p) = sprintf("< jq -r '.kernels.rows[] | select(.counted and .precision == \"%s\") | \"\\(.intensity) \\(.gflops) \\(.kernel)\"' %s", p, json)
set terminal pngcairo size 900,600 noenhanced
set output out
set logscale xy
set grid
set key outside right
set samples 400
set xrange [0.01:1000]
set xlabel 'flops per byte (counted: Oclgrind, every lane; bytes: global and constant loads and stores)'
set ylabel 'GFLOP/s (counted flops / device seconds)'
set title sprintf("%s shape: fp32 %.0f, fp64 %.0f GFLOP/s, triad %.1f GB/s\n%s", shape, p32, p64, bw, device) font ',10'
roof(x, p) = x * bw < p ? x * bw : p
plot roof(x, p32) with lines lw 2 lc 'black' title 'fp32 roof', \
     roof(x, p64) with lines lw 2 dt 2 lc 'black' title 'fp64 roof', \
     rows('fp32') using 1:2 with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'kernels fp32', \
     rows('fp32') using 1:2:3 with labels left offset 1,0.5 font ',8' notitle, \
     rows('fp64') using 1:2 with points pt 5 ps 1.3 lc rgb '#d62728' title 'kernels fp64', \
     rows('fp64') using 1:2:3 with labels left offset 1,-0.5 font ',8' notitle
