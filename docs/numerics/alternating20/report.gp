# Written by dyngen 0.1.0 report for robot 'alternating20' (alternating20.yaml); rewritten on every run.
#
# Error against run time for each variant, one panel per algorithm: the point is the median
# relative error, the bar reaches the worst one. Errors of exactly 0 are drawn at 1e-20, errors
# of 1 or more (no correct digit, or a non-finite output) at 1.
# Redraw with: gnuplot report.gp
set terminal svg size 1600,460 dynamic enhanced font "sans,11" background rgb "white"
if (!exists("output_file")) output_file = "report.svg"
set output output_file
$rnea << EOD
1636.66 4.13136e-16 4.13136e-16 2.92556e-15
618.531 4.13136e-16 4.13136e-16 2.92556e-15
470.873 3.59187e-16 3.59187e-16 1.93614e-15
563.97 4.01426e-16 4.01426e-16 3.74527e-15
1511.81 2.12818e-07 2.12818e-07 9.67208e-07
473.954 2.12818e-07 2.12818e-07 9.67208e-07
EOD
$crba << EOD
2064.07 3.0807e-16 3.0807e-16 1.14629e-15
1267.53 3.0807e-16 3.0807e-16 1.14629e-15
620.653 2.88487e-16 2.88487e-16 8.67373e-16
799.811 2.82525e-16 2.82525e-16 6.58187e-16
1826.93 1.38838e-07 1.38838e-07 3.83427e-07
685.046 1.38838e-07 1.38838e-07 3.83427e-07
EOD
$aba << EOD
3704.61 7.15468e-14 7.15468e-14 9.30541e-13
1520.4 7.15468e-14 7.15468e-14 9.30541e-13
1124.3 6.7947e-14 6.7947e-14 8.92709e-13
1559.97 7.83845e-14 7.83845e-14 9.26587e-13
3303.2 3.82019e-05 3.82019e-05 0.000428984
1428.37 3.82019e-05 3.82019e-05 0.000428984
3380.67 7.64666e-14 7.64666e-14 7.49554e-13
2743.08 4.05501e-05 4.05501e-05 0.000503166
EOD

set logscale xy
set format x "%g"
set format y "10^{%L}"
set grid
set xlabel "median time per call (ns)"
set ylabel "relative error"
set key font ",9" spacing 0.9
set multiplot layout 1,4 title "alternating20: error against time, 1000 states" noenhanced
unset key
set title "RNEA (inverse dynamics, tau)"
set xrange [314:2.45e+03]
set yrange [3.59e-17:9.67e-06]
plot $rnea every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $rnea every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $rnea every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $rnea every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $rnea every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $rnea every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "CRBA (mass matrix, M)"
set xrange [414:3.1e+03]
set yrange [2.83e-17:3.83e-06]
plot $crba every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $crba every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $crba every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $crba every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $crba every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $crba every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "ABA (forward dynamics, qdd)"
set xrange [750:5.56e+03]
set yrange [6.79e-15:0.00503]
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
