$planar_chain_rnea << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 19.735536 18.824306 139.311663 490.997651 409.252666 59 535
4 36.676086 36.559207 273.343623 762.276362 686.925577 158 1199
8 85.001138 73.286997 547.313960 1482.662012 1263.598547 377 2527
16 213.210272 144.054764 1104.157384 2933.098295 2370.553057 794 5183
32 432.563683 302.457535 2216.119346 5369.693171 4737.361383 1649 10495
EOD
$planar_chain_crba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 13.747966 13.680385 96.334866 315.888701 467.798987 12 333
4 30.803753 28.245310 223.929331 538.981874 857.232078 53 998
8 65.886264 66.779653 591.448483 1040.197695 1783.748173 211 2892
16 193.530787 197.037028 1575.024404 2177.317912 4086.770324 813 8936
32 1014.105455 993.316103 4841.339086 5932.495944 10302.856367 3227 30048
EOD
$planar_chain_aba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 24.740369 26.017414 283.050539 570.060108 865.784373 84 1124
4 70.742279 65.387130 647.508092 914.938012 1575.915311 296 2878
8 198.272561 170.650748 1381.542287 1721.820308 3281.017779 743 6386
16 469.632332 377.295621 2946.061639 3817.585444 8228.303102 1620 13402
32 1036.184794 875.896198 5898.664335 10589.162156 21947.694358 3375 27434
EOD
$spatial_chain_rnea << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 42.102879 42.175993 124.386570 517.982120 405.816000 221 535
4 104.853414 105.339963 268.871687 860.129226 719.886378 805 1199
8 244.782990 369.872688 559.982508 1421.221305 1285.140895 1954 2527
16 594.788852 842.654612 1121.945444 2690.109149 2556.547565 4252 5183
32 1276.967452 1951.558188 2224.325411 5334.765406 4931.515255 8848 10495
EOD
$spatial_chain_crba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 25.276529 26.310541 94.002932 313.960454 458.776419 81 333
4 62.358113 62.036499 230.266363 545.251119 856.307037 420 998
8 289.397340 231.161102 579.423557 1044.882457 1835.336380 1835 2892
16 1413.488474 1351.359606 1537.140609 2526.913666 4368.524531 6753 8936
32 5637.221550 4969.330481 4748.809138 5675.843903 10093.150723 24941 30048
EOD
$spatial_chain_aba << EOD
# links generated unrolled runtime mujoco kdl ops_generated ops_runtime
2 52.307071 56.862104 281.961874 648.320152 847.185349 325 1124
4 195.640109 186.462237 643.250086 910.466320 1567.197461 1583 2878
8 924.928705 914.344973 1567.835357 1923.556002 3576.606093 4458 6386
16 1801.558991 2123.008147 2952.645494 4179.169779 7441.841405 10208 13402
32 3673.535050 5009.617530 5902.429896 10578.705244 22424.680353 21708 27434
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
