# Written by dyngen 0.1.0 report for robot 'atlas' (atlas.urdf); rewritten on every run.
#
# Error against run time for each variant, one panel per algorithm: the point is the median
# relative error, the bar reaches the worst one. Errors of exactly 0 are drawn at 1e-20, errors
# of 1 or more (no correct digit, or a non-finite output) at 1.
# Redraw with: gnuplot report.gp
set terminal svg size 1600,460 dynamic enhanced font "sans,11" background rgb "white"
if (!exists("output_file")) output_file = "report.svg"
set output output_file
$rnea << EOD
2368.66 1.97114e-16 1.97114e-16 1.3099e-15
1227.94 1.97114e-16 1.97114e-16 1.3099e-15
852.859 1.71275e-16 1.71275e-16 6.18439e-16
1187.52 2.01406e-16 2.01406e-16 1.37396e-15
2221.26 1.13937e-07 1.13937e-07 3.9402e-07
1050.15 1.13937e-07 1.13937e-07 3.9402e-07
EOD
$crba << EOD
2623.48 6.53487e-17 6.53487e-17 1.66174e-16
1365.09 6.53487e-17 6.53487e-17 1.66174e-16
1043.38 6.15176e-17 6.15176e-17 1.81346e-16
1336.3 7.03206e-17 7.03206e-17 2.18811e-16
2459.49 3.40065e-08 3.40065e-08 8.08496e-08
1052.52 3.40065e-08 3.40065e-08 8.08496e-08
EOD
$aba << EOD
5886.24 8.68085e-14 8.68085e-14 1.99492e-12
2661.85 8.68085e-14 8.68085e-14 1.99492e-12
1992.69 7.58222e-14 7.58222e-14 1.64157e-12
2872.33 9.3181e-14 9.3181e-14 2.06542e-12
5008.37 4.57604e-05 4.57604e-05 0.000613938
2438.77 4.57604e-05 4.57604e-05 0.000613938
6861.65 8.09061e-14 8.09061e-14 9.98415e-13
6355.35 4.44725e-05 4.44725e-05 0.000763496
EOD

set logscale xy
set format x "%g"
set format y "10^{%L}"
set grid
set xlabel "median time per call (ns)"
set ylabel "relative error"
set key font ",9" spacing 0.9
set multiplot layout 1,4 title "atlas: error against time, 1000 states" noenhanced
unset key
set title "RNEA (inverse dynamics, tau)"
set xrange [569:3.55e+03]
set yrange [1.71e-17:3.94e-06]
plot $rnea every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $rnea every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $rnea every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $rnea every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $rnea every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $rnea every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "CRBA (mass matrix, M)"
set xrange [696:3.94e+03]
set yrange [6.15e-18:8.08e-07]
plot $crba every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $crba every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $crba every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $crba every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $crba every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $crba every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "ABA (forward dynamics, qdd)"
set xrange [1.33e+03:1.03e+04]
set yrange [7.58e-15:0.00763]
plot $aba every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $aba every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $aba every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $aba every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $aba every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $aba every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float", \
     $aba every ::6::6 using 1:2:3:4 with yerrorbars lc 7 pt 10 ps 1.3 title "generated CRBA+LDLT double", \
     $aba every ::7::7 using 1:2:3:4 with yerrorbars lc 8 pt 11 ps 1.3 title "generated CRBA+LDLT float"
unset title
unset border
unset tics
unset grid
unset xlabel
unset ylabel
unset logscale
set xrange [0:1]
set yrange [0:1]
set key center center
plot NaN with points lc 1 pt 4 ps 1.3 title "runtime double", \
     NaN with points lc 2 pt 5 ps 1.3 title "generated double", \
     NaN with points lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     NaN with points lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     NaN with points lc 5 pt 8 ps 1.3 title "runtime float", \
     NaN with points lc 6 pt 9 ps 1.3 title "generated float", \
     NaN with points lc 7 pt 10 ps 1.3 title "generated CRBA+LDLT double", \
     NaN with points lc 8 pt 11 ps 1.3 title "generated CRBA+LDLT float"

unset multiplot
