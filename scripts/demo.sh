#!/bin/sh
# make demo: the Cornell box solved by dense and by hierarchical Galerkin
# radiosity (images, the figures of the runs, the adaptive mesh), then the 1D
# model problem of the notes at a few n (a table of its errors and a
# convergence plot).
set -eu
RADKIT=${1:-build/radkit}
out=build/demo
mkdir -p "$out"

REFINE=${REFINE:-3}
echo "radkit demo 1: the Cornell box, dense Galerkin radiosity (--refine $REFINE)"
"$RADKIT" solve scenes/cornell/cornell.obj --refine "$REFINE" --png "$out/cornell.png" \
    --ply "$out/cornell.ply" --stats "$out/cornell.json" --out "$out/cornell.tsv"
awk -F' = ' '/^# (faces|elements|rule|solver|pairs|pairs_not_facing|pairs_occlusion_tested|rays|kernel_evals|solver_residual|time_[a-z]+_s|memory_peak_bytes|effect_[a-z_]+) = /{
  printf "  %-24s %s\n", substr($1, 3), $2 }' "$out/cornell.tsv" | grep -v '_reason'
echo "  image: $out/cornell.png   mesh: $out/cornell.ply   stats: $out/cornell.json"
echo "  per-face radiosity: $out/cornell.tsv"
echo
echo "radkit demo 1b: the same box by hierarchical radiosity (--method hier --eps 0.01)"
"$RADKIT" solve scenes/cornell/cornell.obj --method hier --eps 0.01 --png "$out/cornell_hier.png" \
    --ply "$out/cornell_hier.ply" --stats "$out/cornell_hier.json" --out "$out/cornell_hier.tsv"
"$RADKIT" solve scenes/cornell/cornell.obj --method hier --eps 0.1 --png "$out/cornell_hier_mesh.png" \
    --edges --quiet --out /dev/null
awk -F' = ' '/^# (oracle|eps|elements|links|links_partial|links_blocked|rounds|iterations|error_estimate|error_estimate_l1|error_target_met|kernel_evals|time_[a-z]+_s) = /{
  printf "  %-24s %s\n", substr($1, 3), $2 }' "$out/cornell_hier.tsv"
echo "  image: $out/cornell_hier.png   adaptive mesh (eps 0.1): $out/cornell_hier_mesh.png"
echo
echo "radkit demo 1c: both against the committed Monte Carlo reference (radkit compare;"
echo "errors relative to the mean reflected radiosity: area-weighted L1 and worst face)"
for run in cornell cornell_hier; do
  "$RADKIT" compare scenes/cornell/cornell.obj "$out/$run.tsv" experiments/reference/data/cornell.tsv |
    awk -F' = ' -v run="$run" '/^# error_l1 = /{ l1 = $2 } /^# error_worst = /{ w = $2 }
      END { printf "  %-14s L1 %.3e   worst face %.3e\n", run, l1, w }'
done
echo
echo "radkit demo 2: the 1D model problem y = f + K y (papers/galerkin-1d.md)"
echo "exact Galerkin solutions (closed-form assembly) against the exact solution;"
echo "residual = Galerkin residual recomputed from the definitions alone"
echo
printf '%-5s %-3s %6s %12s %12s %12s %12s %10s\n' problem basis n err_l2 err_linf err_nodal residual seconds
for problem in seed exp; do
  for basis in p0 p1; do
    dat="$out/${problem}_${basis}.dat"
    printf 'n\th\terr_l2\terr_linf\n' > "$dat"
    for n in 4 16 64 256 1024; do
      "$RADKIT" galerkin1d --n "$n" --problem "$problem" --basis "$basis" |
        awk -F' = ' -v n="$n" -v p="$problem" -v b="$basis" -v dat="$dat" '
          /^# /{ v[substr($1, 3)] = $2 }
          END {
            printf "%-7s %-5s %6d %12.3e %12.3e %12.3e %12.3e %10.4f\n", p, b, n, v["err_l2"],
                   v["err_linf"], v["err_nodal"], v["galerkin_residual"], v["assemble_s"] + v["solve_s"]
            printf "%d\t%.17g\t%s\t%s\n", n, 1.0 / n, v["err_l2"], v["err_linf"] >> dat }'
    done
  done
done

gnuplot <<GP
set terminal pngcairo size 900,650 enhanced font ",11"
set output "$out/convergence_1d.png"
set logscale xy
set format xy "10^{%L}"
set grid
set key top left
set xlabel "h = 1/n"
set ylabel "L2 error"
set title "1D model problem: Galerkin L2 error (exact assembly)"
plot "$out/exp_p0.dat" using 2:3 skip 1 with linespoints title "exp, P0", \
     "$out/exp_p1.dat" using 2:3 skip 1 with linespoints title "exp, P1", \
     "$out/seed_p0.dat" using 2:3 skip 1 with linespoints title "seed, P0 (y = x)", \
     1.5*x with lines dashtype 2 lc "black" title "slope 1 (guide)", 0.02*x**2 with lines dashtype 3 lc "black" title "slope 2 (guide)"
GP
echo
echo "seed, P1 is exact (y = x lies in the P1 space): its errors are round-off."
echo "plot: $out/convergence_1d.png"
echo "full study: make experiments (figures in experiments/convergence_1d/figures/)"
