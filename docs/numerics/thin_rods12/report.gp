# Written by dyngen 0.1.0 report for robot 'thin_rods12' (thin_rods12.yaml); rewritten on every run.
#
# Error against run time for each variant, one panel per algorithm: the point is the median
# relative error, the bar reaches the worst one. Errors of exactly 0 are drawn at 1e-20, errors
# of 1 or more (no correct digit, or a non-finite output) at 1.
# Redraw with: gnuplot report.gp
set terminal svg size 1600,460 dynamic enhanced font "sans,11" background rgb "white"
if (!exists("output_file")) output_file = "report.svg"
set output output_file
$rnea << EOD
938.765 3.15022e-16 3.15022e-16 1.344e-15
238.912 3.15022e-16 3.15022e-16 1.344e-15
268.073 2.89707e-16 2.89707e-16 1.41927e-15
271.633 3.27066e-16 3.27066e-16 1.8687e-15
888.872 1.70588e-07 1.70588e-07 8.79739e-07
198.836 1.70588e-07 1.70588e-07 8.79739e-07
EOD
$crba << EOD
980.569 1.84915e-16 1.84915e-16 5.53736e-16
249.461 1.84915e-16 1.84915e-16 5.53736e-16
212.2 1.76994e-16 1.76994e-16 5.68586e-16
232.947 1.71191e-16 1.71191e-16 5.30604e-16
903.41 9.96426e-08 9.96426e-08 2.52772e-07
169.21 9.96426e-08 9.96426e-08 2.52772e-07
EOD
$aba << EOD
2215.12 2.26985e-06 2.26985e-06 0.000206182
825.884 2.26985e-06 2.26985e-06 0.000206182
586.812 2.19271e-06 2.19271e-06 0.000155389
998.395 2.53514e-06 2.53514e-06 0.000233099
1870.64 1 1 1
726.145 1 1 1
1308.69 2.26985e-06 2.26985e-06 0.000206182
1285.2 1 1 1
EOD

set logscale xy
set format x "%g"
set format y "10^{%L}"
set grid
set xlabel "median time per call (ns)"
set ylabel "relative error"
set key font ",9" spacing 0.9
set multiplot layout 1,4 title "thin_rods12: error against time, 1000 states" noenhanced
unset key
set title "RNEA (inverse dynamics, tau)"
set xrange [133:1.41e+03]
set yrange [2.9e-17:8.8e-06]
plot $rnea every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $rnea every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $rnea every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $rnea every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $rnea every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $rnea every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "CRBA (mass matrix, M)"
set xrange [113:1.47e+03]
set yrange [1.71e-17:2.53e-06]
plot $crba every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $crba every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $crba every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $crba every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $crba every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $crba every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "ABA (forward dynamics, qdd)"
set xrange [391:3.32e+03]
set yrange [2.19e-07:10]
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
