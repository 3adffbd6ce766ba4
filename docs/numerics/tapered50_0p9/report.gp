# Written by dyngen 0.1.0 report for robot 'tapered50_0p9' (tapered50_0p9.yaml); rewritten on every run.
#
# Error against run time for each variant, one panel per algorithm: the point is the median
# relative error, the bar reaches the worst one. Errors of exactly 0 are drawn at 1e-20, errors
# of 1 or more (no correct digit, or a non-finite output) at 1.
# Redraw with: gnuplot report.gp
set terminal svg size 1600,460 dynamic enhanced font "sans,11" background rgb "white"
if (!exists("output_file")) output_file = "report.svg"
set output output_file
$rnea << EOD
3746.18 2.40094e-16 2.40094e-16 1.3038e-15
1677.92 2.40094e-16 2.40094e-16 1.3038e-15
1213.73 2.19818e-16 2.19818e-16 1.2986e-15
1697.35 2.40198e-16 2.40198e-16 1.11253e-15
3484.5 1.30563e-07 1.30563e-07 7.82895e-07
1402.09 1.30563e-07 1.30563e-07 7.82895e-07
EOD
$crba << EOD
9471.43 1.59041e-16 1.59041e-16 4.52e-16
4770.33 1.59041e-16 1.59041e-16 4.52e-16
3663.03 1.48995e-16 1.48995e-16 4.28307e-16
5032.32 1.55292e-16 1.55292e-16 4.60505e-16
11223.4 8.62362e-08 8.62362e-08 2.53334e-07
4496.81 8.62362e-08 8.62362e-08 2.53334e-07
EOD
$aba << EOD
9517.02 6.58437e-12 6.58437e-12 1.51002e-10
4664.23 6.58437e-12 6.58437e-12 1.51002e-10
3367.58 5.91455e-12 5.91455e-12 2.19305e-10
4757.98 7.34584e-12 7.34584e-12 1.55781e-10
8648.86 0.00330207 0.00330207 0.075626
3932.45 0.00330207 0.00330207 0.075626
13324.9 6.63475e-12 6.63475e-12 1.5081e-10
12532.7 0.00336426 0.00336426 0.0747935
EOD

set logscale xy
set format x "%g"
set format y "10^{%L}"
set grid
set xlabel "median time per call (ns)"
set ylabel "relative error"
set key font ",9" spacing 0.9
set multiplot layout 1,4 title "tapered50_0p9: error against time, 1000 states" noenhanced
unset key
set title "RNEA (inverse dynamics, tau)"
set xrange [809:5.62e+03]
set yrange [2.2e-17:7.83e-06]
plot $rnea every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $rnea every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $rnea every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $rnea every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $rnea every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $rnea every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "CRBA (mass matrix, M)"
set xrange [2.44e+03:1.68e+04]
set yrange [1.49e-17:2.53e-06]
plot $crba every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $crba every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $crba every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $crba every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $crba every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $crba every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "ABA (forward dynamics, qdd)"
set xrange [2.25e+03:2e+04]
set yrange [5.91e-13:0.756]
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
