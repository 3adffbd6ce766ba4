$planar_chain_rnea << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 25.718011 129.131651 437.505581 388.155427 65 535
4 43.968675 270.458073 700.232449 655.182787 176 1199
8 96.060260 571.161334 1326.038774 1191.423406 421 2527
16 180.657368 1154.961066 2415.353959 2341.027832 888 5183
32 401.900603 2289.535462 4766.963425 4546.563551 1845 10495
EOD
$planar_chain_crba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 12.373979 98.207316 288.892930 424.308856 16 333
4 24.946028 237.039094 509.308729 828.988433 62 998
8 71.646780 606.263786 1011.023822 1687.724747 240 2892
16 209.539326 1521.648601 2102.080399 3772.082165 866 8936
32 1048.201377 4811.551804 5055.226485 9681.087748 3288 30048
EOD
$planar_chain_aba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 32.349327 281.100034 481.932578 808.269290 90 1122
4 82.548362 661.715259 874.164774 1461.718087 317 2874
8 209.382498 1350.891031 1671.545400 3142.376112 796 6378
16 441.869819 2849.819189 3703.614715 7225.764348 1719 13386
32 951.338072 5624.018908 10277.141712 21441.297351 3620 27402
EOD
$spatial_chain_rnea << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 44.610450 125.307995 455.194044 390.432172 228 535
4 110.736292 281.287697 733.135684 659.935162 814 1199
8 327.683529 568.351715 1344.003282 1184.813279 1972 2527
16 832.753634 1127.410681 2534.364961 2331.013088 4288 5183
32 1739.139717 2342.401182 4863.704511 4455.617382 8920 10495
EOD
$spatial_chain_crba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 23.939189 100.053969 306.261077 438.866269 82 333
4 60.221235 235.111643 524.127524 815.119342 428 998
8 231.255308 580.029648 1019.661388 1667.686539 1856 2892
16 1275.085997 1510.438214 2233.038476 3823.592504 6800 8936
32 5015.270436 4650.380287 5290.133970 9303.211995 25040 30048
EOD
$spatial_chain_aba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 56.906719 287.577468 500.619149 795.613531 332 1122
4 193.961584 647.503735 838.954451 1511.178919 1596 2874
8 879.019425 1386.258741 1746.266895 3095.680149 4483 6378
16 2067.175929 2803.512943 3795.527021 7198.976974 10257 13386
32 4518.684440 5900.185556 10245.638374 21986.102872 21805 27402
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
plot $planar_chain_rnea using 1:2 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_rnea using 1:2 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_rnea using 1:3 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_rnea using 1:3 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial', $planar_chain_rnea using 1:4 with linespoints lc rgb '#7570b3' dt 1 pt 7 ps 0.5 title 'mujoco planar', $spatial_chain_rnea using 1:4 with linespoints lc rgb '#7570b3' dt 2 pt 7 ps 0.5 title 'mujoco spatial', $planar_chain_rnea using 1:5 with linespoints lc rgb '#e7298a' dt 1 pt 7 ps 0.5 title 'kdl planar', $spatial_chain_rnea using 1:5 with linespoints lc rgb '#e7298a' dt 2 pt 7 ps 0.5 title 'kdl spatial'
set title 'crba: time per call'
set ylabel 'ns'
plot $planar_chain_crba using 1:2 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_crba using 1:2 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_crba using 1:3 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_crba using 1:3 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial', $planar_chain_crba using 1:4 with linespoints lc rgb '#7570b3' dt 1 pt 7 ps 0.5 title 'mujoco planar', $spatial_chain_crba using 1:4 with linespoints lc rgb '#7570b3' dt 2 pt 7 ps 0.5 title 'mujoco spatial', $planar_chain_crba using 1:5 with linespoints lc rgb '#e7298a' dt 1 pt 7 ps 0.5 title 'kdl planar', $spatial_chain_crba using 1:5 with linespoints lc rgb '#e7298a' dt 2 pt 7 ps 0.5 title 'kdl spatial'
set title 'aba: time per call'
set ylabel 'ns'
plot $planar_chain_aba using 1:2 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_aba using 1:2 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_aba using 1:3 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_aba using 1:3 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial', $planar_chain_aba using 1:4 with linespoints lc rgb '#7570b3' dt 1 pt 7 ps 0.5 title 'mujoco planar', $spatial_chain_aba using 1:4 with linespoints lc rgb '#7570b3' dt 2 pt 7 ps 0.5 title 'mujoco spatial', $planar_chain_aba using 1:5 with linespoints lc rgb '#e7298a' dt 1 pt 7 ps 0.5 title 'kdl planar', $spatial_chain_aba using 1:5 with linespoints lc rgb '#e7298a' dt 2 pt 7 ps 0.5 title 'kdl spatial'
set title 'rnea: operations per call'
set ylabel 'add, mul, div, neg, sin, cos'
plot $planar_chain_rnea using 1:6 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_rnea using 1:6 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_rnea using 1:7 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_rnea using 1:7 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial'
set title 'crba: operations per call'
set ylabel 'add, mul, div, neg, sin, cos'
plot $planar_chain_crba using 1:6 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_crba using 1:6 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_crba using 1:7 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_crba using 1:7 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial'
set title 'aba: operations per call'
set ylabel 'add, mul, div, neg, sin, cos'
plot $planar_chain_aba using 1:6 with linespoints lc rgb '#1b9e77' dt 1 pt 7 ps 0.5 title 'generated planar', $spatial_chain_aba using 1:6 with linespoints lc rgb '#1b9e77' dt 2 pt 7 ps 0.5 title 'generated spatial', $planar_chain_aba using 1:7 with linespoints lc rgb '#d95f02' dt 1 pt 7 ps 0.5 title 'runtime planar', $spatial_chain_aba using 1:7 with linespoints lc rgb '#d95f02' dt 2 pt 7 ps 0.5 title 'runtime spatial'
unset multiplot
