set datafile separator ','
set logscale xy
set grid
set key outside right
set terminal pngcairo size 900,520
configs = 'nee-random-area nee-sobol-area nee-random-solid nee-sobol-solid nee-sobol-solid-rr5 nee-sobol-solid-rr4 nee-sobol-solid-rr3 mis-sobol-solid-rr4'
set output 'mse_x_spp_3.png'
set xlabel 'samples per pixel'
set ylabel 'MSE x spp'
set title 'MSE x spp against spp (64x48, 3 bounces; flat: independent samples)'
plot for [e in configs] 'points.csv' using ((strcol(2) eq e && $1 == 3) ? $3 : 1/0):6 with linespoints title e
set output 'error_vs_time_3.png'
set xlabel 'GPU time (s, lavapipe)'
set ylabel 'RMSE'
set title 'RMSE against time (3 bounces)'
plot for [e in configs] 'points.csv' using ((strcol(2) eq e && $1 == 3) ? $4 : 1/0):5 with linespoints title e
set output 'mse_x_spp_8.png'
set xlabel 'samples per pixel'
set ylabel 'MSE x spp'
set title 'MSE x spp against spp (64x48, 8 bounces; flat: independent samples)'
plot for [e in configs] 'points.csv' using ((strcol(2) eq e && $1 == 8) ? $3 : 1/0):6 with linespoints title e
set output 'error_vs_time_8.png'
set xlabel 'GPU time (s, lavapipe)'
set ylabel 'RMSE'
set title 'RMSE against time (8 bounces)'
plot for [e in configs] 'points.csv' using ((strcol(2) eq e && $1 == 8) ? $4 : 1/0):5 with linespoints title e
