# docs/solvers_time_objective.png from docs/solvers_time_objective.dat (run from docs/:
# gnuplot ../bench/solvers_time_objective.gp). Relative gap to exact + 1e-6 against wall seconds,
# both on log axes, one point per (problem size, solver).
set terminal pngcairo size 760,460 font ",10"
set output "solvers_time_objective.png"
set logscale xy
set xlabel "wall seconds (2 threads)"
set ylabel "relative gap to exact + 1e-6"
set key outside right
set grid
sizes = "100k 685k 3M"
plot for [i = 1:3] "solvers_time_objective.dat" \
     using ((strcol(1) eq word(sizes, i)) ? $3 : NaN):4:(strcol(2)) \
     with labels point pt 7 ps 1.3 lc i tc lt i offset char 1,0.5 left title word(sizes, i)
