$planar_chain_rnea << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 20.595469 126.452832 486.295604 406.346854 59 535
4 37.245220 271.727506 734.764323 675.215236 158 1199
8 70.180831 560.738980 1389.496682 1264.187478 377 2527
16 147.831343 1120.559818 2690.752932 2398.781515 794 5183
32 292.874441 2254.535859 5103.996610 4902.117876 1649 10495
EOD
$planar_chain_crba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 13.188407 96.690364 314.686737 465.048374 12 333
4 28.444647 235.216263 555.518901 867.717017 53 998
8 66.569096 606.552647 1052.167354 1787.182429 211 2892
16 205.484176 1592.883138 2263.071608 3935.296231 813 8936
32 1024.983944 4811.114361 5601.195177 10325.108952 3227 30048
EOD
$planar_chain_aba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 25.812122 279.011052 514.588943 858.174615 84 1124
4 64.139726 648.374296 893.793978 1637.035797 296 2878
8 175.071449 1403.672936 1715.001586 3183.966192 743 6386
16 380.970972 2887.064946 3925.217242 7477.354506 1620 13402
32 851.890421 5962.170456 11426.717781 21697.094818 3375 27434
EOD
$spatial_chain_rnea << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 42.776958 124.961722 484.816207 413.245147 221 535
4 102.548011 267.630977 785.612259 701.703054 805 1199
8 369.926190 555.940232 1382.820595 1312.282879 1954 2527
16 856.362116 1138.184670 2692.218179 2499.555271 4252 5183
32 1816.615982 2300.712481 5375.586633 4787.183614 8848 10495
EOD
$spatial_chain_crba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 25.405498 95.644738 327.881539 461.262723 81 333
4 63.567089 228.987998 541.969913 864.550063 420 998
8 226.325019 586.625340 1067.917164 1822.279340 1835 2892
16 1312.275707 1593.950573 2295.813961 3994.210583 6753 8936
32 5027.906129 4845.474718 5641.866509 10600.521737 24941 30048
EOD
$spatial_chain_aba << EOD
# links generated runtime mujoco kdl ops_generated ops_runtime
2 54.738268 290.667584 526.701326 844.160407 325 1124
4 666.433393 648.060966 903.193855 1606.888400 1583 2878
8 1164.331003 1399.743077 1724.656565 3222.399405 4458 6386
16 2158.010631 2816.714287 3834.654913 7485.200810 10208 13402
32 4861.850000 6020.596928 10861.552684 22833.405084 21708 27434
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
