$planar_chain_rnea << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 17.894462 18.719714 122.641463 523.363850 446.488387 47 439
4 42.456610 40.871756 243.151118 879.322890 779.062170 122 1007
8 73.056290 63.827111 624.172414 1915.695183 1390.556243 283 2143
16 200.341571 160.096404 1263.157167 2844.606786 3231.498983 594 4415
32 503.500009 419.105559 2563.888624 5456.260769 6406.364923 1227 8959
EOD
$planar_chain_crba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 12.308123 12.376159 115.793635 471.169032 493.632444 12 333
4 29.879283 29.887239 261.395761 612.188011 945.088693 53 998
8 82.445219 69.196831 640.307054 1526.134277 1954.552937 211 2892
16 207.771256 209.193747 1769.682822 3312.038395 5730.086115 813 8936
32 1069.032814 1067.736132 6009.026960 6423.880739 11756.799992 3227 30048
EOD
$planar_chain_aba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 24.542124 24.066023 313.362938 599.299422 919.296372 74 1076
4 80.908355 81.310464 699.062546 973.756908 1703.428429 271 2764
8 172.807713 173.006662 1491.505914 1869.093779 3521.589559 675 6140
16 441.988198 468.833308 3226.985267 4104.838015 8635.653726 1479 12892
32 1048.374735 903.596632 6218.679644 11386.719239 26210.021339 3075 26396
EOD
$spatial_chain_rnea << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 40.976366 42.270021 114.680067 687.066430 448.870344 182 439
4 94.254594 94.316567 300.154004 834.521340 732.637173 690 1007
8 210.379208 211.081974 572.554193 1610.274953 1384.183839 1683 2143
16 578.237426 826.749336 1060.787885 2909.304081 2717.785116 3669 4415
32 1307.423821 2047.632039 2149.619091 5535.567210 5232.293698 7641 8959
EOD
$spatial_chain_crba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 29.350946 28.408918 110.972028 352.317891 518.174186 81 333
4 60.141205 68.697412 268.495715 594.936786 957.084420 420 998
8 310.007176 228.049956 646.696168 1163.986121 1952.038576 1835 2892
16 1500.338172 1429.567247 1817.509280 2471.027431 4445.410078 6753 8936
32 6120.521759 5209.671840 5516.204983 6025.353860 10907.137758 24941 30048
EOD
$spatial_chain_aba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 62.850990 54.905433 309.313616 648.179395 1162.803137 301 1076
4 200.591423 210.556789 687.232767 1308.657238 1737.413506 1532 2764
8 1005.184264 997.407235 1472.499850 2558.055453 4580.438184 4347 6140
16 1942.550248 2385.020768 3519.492769 4164.058445 8203.261302 9977 12892
32 4894.784734 5190.077918 6233.352316 12730.493905 24381.524322 21237 26396
EOD
set terminal svg size 1500,950 dynamic font 'sans,11'
set output 'benchmarks.svg'
set logscale xy
set xtics (2, 4, 8, 16, 32, 64, 128)
set autoscale xfix
set offsets graph 0.05, graph 0.05, 0, 0
set grid
set key top left font ',9'
set xlabel 'links'
set multiplot layout 2,3 title 'dyngen benchmarks: chains (solid: planar, dashed: spatial)'
set title 'rnea: time per call'
set ylabel 'ns'
plot $planar_chain_rnea using 1:2 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_rnea using 1:2 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_rnea using 1:3 with linespoints lc rgb '#66a61e' dt 1 pt 7 ps 0.5 title 'unrolled planar', $spatial_chain_rnea using 1:3 with linespoints lc rgb '#66a61e' dt 2 pt 7 ps 0.5 title 'unrolled spatial', $planar_chain_rnea using 1:4 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_rnea using 1:4 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial', $planar_chain_rnea using 1:5 with linespoints lc rgb '#7570b3' dt 1 pt 7 ps 0.5 title 'mujoco planar', $spatial_chain_rnea using 1:5 with linespoints lc rgb '#7570b3' dt 2 pt 7 ps 0.5 title 'mujoco spatial', $planar_chain_rnea using 1:6 with linespoints lc rgb '#e7298a' dt 1 pt 7 ps 0.5 title 'kdl planar', $spatial_chain_rnea using 1:6 with linespoints lc rgb '#e7298a' dt 2 pt 7 ps 0.5 title 'kdl spatial'
set title 'crba: time per call'
set ylabel 'ns'
plot $planar_chain_crba using 1:2 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_crba using 1:2 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_crba using 1:3 with linespoints lc rgb '#66a61e' dt 1 pt 7 ps 0.5 title 'unrolled planar', $spatial_chain_crba using 1:3 with linespoints lc rgb '#66a61e' dt 2 pt 7 ps 0.5 title 'unrolled spatial', $planar_chain_crba using 1:4 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_crba using 1:4 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial', $planar_chain_crba using 1:5 with linespoints lc rgb '#7570b3' dt 1 pt 7 ps 0.5 title 'mujoco planar', $spatial_chain_crba using 1:5 with linespoints lc rgb '#7570b3' dt 2 pt 7 ps 0.5 title 'mujoco spatial', $planar_chain_crba using 1:6 with linespoints lc rgb '#e7298a' dt 1 pt 7 ps 0.5 title 'kdl planar', $spatial_chain_crba using 1:6 with linespoints lc rgb '#e7298a' dt 2 pt 7 ps 0.5 title 'kdl spatial'
set title 'aba: time per call'
set ylabel 'ns'
plot $planar_chain_aba using 1:2 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_aba using 1:2 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_aba using 1:3 with linespoints lc rgb '#66a61e' dt 1 pt 7 ps 0.5 title 'unrolled planar', $spatial_chain_aba using 1:3 with linespoints lc rgb '#66a61e' dt 2 pt 7 ps 0.5 title 'unrolled spatial', $planar_chain_aba using 1:4 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_aba using 1:4 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial', $planar_chain_aba using 1:5 with linespoints lc rgb '#7570b3' dt 1 pt 7 ps 0.5 title 'mujoco planar', $spatial_chain_aba using 1:5 with linespoints lc rgb '#7570b3' dt 2 pt 7 ps 0.5 title 'mujoco spatial', $planar_chain_aba using 1:6 with linespoints lc rgb '#e7298a' dt 1 pt 7 ps 0.5 title 'kdl planar', $spatial_chain_aba using 1:6 with linespoints lc rgb '#e7298a' dt 2 pt 7 ps 0.5 title 'kdl spatial'
set title 'rnea: operations per call'
set ylabel 'add, mul, div, neg, sin, cos'
plot $planar_chain_rnea using 1:7 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_rnea using 1:7 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_rnea using 1:8 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_rnea using 1:8 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial'
set title 'crba: operations per call'
set ylabel 'add, mul, div, neg, sin, cos'
plot $planar_chain_crba using 1:7 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_crba using 1:7 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_crba using 1:8 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_crba using 1:8 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial'
set title 'aba: operations per call'
set ylabel 'add, mul, div, neg, sin, cos'
plot $planar_chain_aba using 1:7 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_aba using 1:7 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_aba using 1:8 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_aba using 1:8 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial'
unset multiplot
