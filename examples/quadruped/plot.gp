# The feet's drift from where they touched down, and the base's height, against time, from the
# CSV that quadruped_example writes:
#   quadruped_example quadruped.csv
#   gnuplot -e "csv='quadruped.csv'; png='quadruped.png'" examples/quadruped/plot.gp
# (both names default to those).
if (!exists("csv")) csv = 'quadruped.csv'
if (!exists("png")) png = 'quadruped.png'

set terminal pngcairo size 900,700 noenhanced
set output png
set datafile separator ','
set key autotitle columnhead right center
set grid
set multiplot layout 2,1

set title 'solo12 standing on contact_dynamics: drift of the feet from where they touched down'
set ylabel 'drift (mm)'
unset xlabel
plot for [foot = 2:5] csv using 1:(1e3 * column(foot)) with lines lw 2

set title 'base height'
set ylabel 'height (mm)'
set xlabel 'time after touchdown (s)'
plot csv using 1:(1e3 * $6) with lines lw 2 notitle

unset multiplot
