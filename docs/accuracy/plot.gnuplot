set datafile separator ','
set logscale xy
set grid
set key top right
set terminal pngcairo size 800,560
set output 'error_vs_spp.png'
set xlabel 'samples per pixel'
set ylabel 'RMSE'
set title 'RMSE against samples (default scene, 64x48, 3 bounces)'
plot for [e in 'nee bsdf mis baseline'] 'points.csv' using ((strcol(1) eq e) ? $2 : 1/0):6 with linespoints title e
set output 'error_vs_time.png'
set xlabel 'GPU time (s, lavapipe)'
set title 'RMSE against time'
plot for [e in 'nee bsdf mis baseline'] 'points.csv' using ((strcol(1) eq e) ? $5 : 1/0):6 with linespoints title e
