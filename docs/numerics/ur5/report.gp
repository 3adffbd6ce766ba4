# Written by dyngen 0.1.0 report for robot 'ur5' (ur5.urdf); rewritten on every run.
#
# Error against run time for each variant, one panel per algorithm: the point is the median
# relative error, the bar reaches the worst one. Errors of exactly 0 are drawn at 1e-20, errors
# of 1 or more (no correct digit, or a non-finite output) at 1.
# Redraw with: gnuplot report.gp
set terminal svg size 1600,460 dynamic enhanced font "sans,11" background rgb "white"
if (!exists("output_file")) output_file = "report.svg"
set output output_file
$rnea << EOD
457.505 1.36509e-16 1.36509e-16 1.29444e-15
113.378 1.36509e-16 1.36509e-16 1.29444e-15
125.525 1.29446e-16 1.29446e-16 1.0148e-15
121.572 1.42645e-16 1.42645e-16 9.83948e-16
413.138 8.68919e-08 8.68919e-08 6.76835e-07
93.1717 8.68919e-08 8.68919e-08 6.76835e-07
EOD
$crba << EOD
404.662 9.95325e-17 9.95325e-17 3.53868e-16
83.9545 9.95325e-17 9.95325e-17 3.53868e-16
67.4796 9.11354e-17 9.11354e-17 3.38086e-16
71.3489 9.11196e-17 9.11196e-17 4.51562e-16
340.079 5.8912e-08 5.8912e-08 1.89677e-07
47.8634 5.8912e-08 5.8912e-08 1.89677e-07
EOD
$aba << EOD
1027.93 2.4198e-15 2.4198e-15 1.55363e-14
206.911 2.4198e-15 2.4198e-15 1.55363e-14
211.083 2.07085e-15 2.07085e-15 1.48228e-14
198.671 2.63865e-15 2.63865e-15 1.57229e-14
888.502 1.21794e-06 1.21794e-06 1.54597e-05
176.396 1.21794e-06 1.21794e-06 1.54597e-05
419.863 1.99892e-15 1.99892e-15 2.28804e-14
345.558 1.18916e-06 1.18916e-06 7.82572e-06
EOD

set logscale xy
set format x "%g"
set format y "10^{%L}"
set grid
set xlabel "median time per call (ns)"
set ylabel "relative error"
set key font ",9" spacing 0.9
set multiplot layout 1,4 title "ur5: error against time, 1000 states" noenhanced
unset key
set title "RNEA (inverse dynamics, tau)"
set xrange [62.1:686]
set yrange [1.29e-17:6.77e-06]
plot $rnea every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $rnea every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $rnea every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $rnea every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $rnea every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $rnea every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "CRBA (mass matrix, M)"
set xrange [31.9:607]
set yrange [9.11e-18:1.9e-06]
plot $crba every ::0::0 using 1:2:3:4 with yerrorbars lc 1 pt 4 ps 1.3 title "runtime double", \
     $crba every ::1::1 using 1:2:3:4 with yerrorbars lc 2 pt 5 ps 1.3 title "generated double", \
     $crba every ::2::2 using 1:2:3:4 with yerrorbars lc 3 pt 6 ps 1.3 title "generated double, FMA", \
     $crba every ::3::3 using 1:2:3:4 with yerrorbars lc 4 pt 7 ps 1.3 title "generated double, fast-math", \
     $crba every ::4::4 using 1:2:3:4 with yerrorbars lc 5 pt 8 ps 1.3 title "runtime float", \
     $crba every ::5::5 using 1:2:3:4 with yerrorbars lc 6 pt 9 ps 1.3 title "generated float"
set title "ABA (forward dynamics, qdd)"
set xrange [118:1.54e+03]
set yrange [2e-16:0.000155]
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
