# experiments/bases: error against unknowns and time (Cornell box, against
# the Monte Carlo reference) and the manufactured case's convergence.
set terminal pngcairo size 900,600 enhanced font 'DejaVu Sans,11'
set datafile separator '\t'
set logscale xy
set grid
set key top right

set output 'figures/cornell_unknowns.png'
set title 'Cornell box: error against unknowns (reference: Monte Carlo)'
set xlabel 'unknowns (elements x basis functions)'
set ylabel 'area-weighted L1 error / mean reflected radiosity'
plot 'data/cornell.dat' using (strcol(1) eq 'p0' ? $4 : 1/0):6 with linespoints lw 2 title 'p0', \
     '' using (strcol(1) eq 'p1' ? $4 : 1/0):6 with linespoints lw 2 title 'p1', \
     '' using (strcol(1) eq 'p2' ? $4 : 1/0):6 with linespoints lw 2 title 'p2', \
     '../hierarchical/data/runs.dat' using (strcol(1) eq 'hier-error' ? $3 : 1/0):5 \
        with linespoints lw 2 dashtype 2 title 'hier p0 (leaves; experiments/hierarchical)'

set output 'figures/cornell_time.png'
set title 'Cornell box: error against wall time (2 cores), dense p0, p1, p2 and hierarchical p0'
set xlabel 'time (s)'
plot 'data/cornell.dat' using (strcol(1) eq 'p0' ? $5 : 1/0):6 with linespoints lw 2 title 'p0', \
     '' using (strcol(1) eq 'p1' ? $5 : 1/0):6 with linespoints lw 2 title 'p1', \
     '' using (strcol(1) eq 'p2' ? $5 : 1/0):6 with linespoints lw 2 title 'p2', \
     '../hierarchical/data/runs.dat' using (strcol(1) eq 'hier-error' ? $6 : 1/0):5 \
        with linespoints lw 2 dashtype 2 title 'hier p0 (experiments/hierarchical)'

set output 'figures/hier_time.png'
set title 'Cornell box: hierarchical p0, p1, p2 (eps swept) and dense, error against wall time (2 cores)'
set xlabel 'time (s)'
set ylabel 'area-weighted L1 error / mean reflected radiosity'
plot 'data/hier.dat' using (strcol(1) eq 'p0' ? $5 : 1/0):6 with linespoints lw 2 title 'hier p0', \
     '' using (strcol(1) eq 'p1' ? $5 : 1/0):6 with linespoints lw 2 title 'hier p1', \
     '' using (strcol(1) eq 'p2' ? $5 : 1/0):6 with linespoints lw 2 title 'hier p2', \
     'data/cornell.dat' using (strcol(1) eq 'p1' ? $5 : 1/0):6 with linespoints lw 1 dashtype 2 title 'dense p1', \
     '' using (strcol(1) eq 'p2' ? $5 : 1/0):6 with linespoints lw 1 dashtype 2 title 'dense p2', \
     0.0025 with lines lc rgb 'gray' title '0.25%', 0.001 with lines lc rgb 'black' title '0.1%'

set output 'figures/hier_estimate.png'
set title 'Cornell box, hierarchical: error estimate against the true worst face (Monte Carlo)'
set xlabel 'requested eps'
set ylabel 'relative to the mean reflected radiosity'
plot 'data/hier.dat' using (strcol(1) eq 'p1' ? $2 : 1/0):7 with linespoints lw 2 title 'p1 true worst face', \
     '' using (strcol(1) eq 'p1' ? $2 : 1/0):8 with linespoints lw 2 dashtype 2 title 'p1 error estimate', \
     '' using (strcol(1) eq 'p2' ? $2 : 1/0):7 with linespoints lw 2 title 'p2 true worst face', \
     '' using (strcol(1) eq 'p2' ? $2 : 1/0):8 with linespoints lw 2 dashtype 2 title 'p2 error estimate', \
     x with lines lc rgb 'gray' title 'eps'

set output 'figures/manufactured.png'
set title 'Manufactured solution (parallel plates): L2 error against elements'
set xlabel 'elements'
set ylabel 'L2 error'
plot 'data/manufactured.dat' using (strcol(1) eq 'p0' ? $3 : 1/0):5 with linespoints lw 2 title 'p0 (theory: order 1)', \
     '' using (strcol(1) eq 'p1' ? $3 : 1/0):5 with linespoints lw 2 title 'p1 (order 2)', \
     '' using (strcol(1) eq 'p2' ? $3 : 1/0):5 with linespoints lw 2 title 'p2 (order 3)', \
     'data/manufactured_hier.dat' using (strcol(1) eq 'p1' ? $3 : 1/0):5 with points pt 6 ps 1.5 title 'hier p1 (eps swept)', \
     '' using (strcol(1) eq 'p2' ? $3 : 1/0):5 with points pt 8 ps 1.5 title 'hier p2 (eps swept)'

set output 'figures/manufactured_time.png'
set title 'Manufactured solution (parallel plates): L2 error against time'
set xlabel 'time (s, 2 cores)'
set ylabel 'L2 error'
plot 'data/manufactured.dat' using (strcol(1) eq 'p0' ? $6 : 1/0):5 with linespoints lw 2 title 'dense p0', \
     '' using (strcol(1) eq 'p1' ? $6 : 1/0):5 with linespoints lw 2 title 'dense p1', \
     '' using (strcol(1) eq 'p2' ? $6 : 1/0):5 with linespoints lw 2 title 'dense p2', \
     'data/manufactured_hier.dat' using (strcol(1) eq 'p1' ? $6 : 1/0):5 with points pt 6 ps 1.5 title 'hier p1 (eps swept)', \
     '' using (strcol(1) eq 'p2' ? $6 : 1/0):5 with points pt 8 ps 1.5 title 'hier p2 (eps swept)'
