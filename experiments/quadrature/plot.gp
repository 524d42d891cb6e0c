# Error of each form-factor scheme against `exact` vs kernel evaluations and
# vs time, one panel per configuration.  Reads cfg_*.dat (run.sh).
cfgs = "far near edge45 edge90 edge135 vertex touching coincident"
titles = "'disjoint, far (d = 4)' 'disjoint, near (d = 0.2)' 'edge-adjacent, 45 deg' 'edge-adjacent, 90 deg' 'edge-adjacent, 135 deg' 'vertex-adjacent' 'near-touching (gap 1e-4)' 'near-coincident (gap 1e-2)'"

do for [out in "png pdf"] {
  do for [xv in "evals seconds"] {
    if (out eq "png") { set terminal pngcairo size 1400,700 font ",9" } else { set terminal pdfcairo size 14in,7in font ",9" }
    set output sprintf("errors_%s.%s", xv eq "evals" ? "evals" : "time", out)
    set multiplot layout 2,4 title sprintf("Relative error of F_{12} against the exact reference vs %s (one thread)", xv eq "evals" ? "kernel evaluations" : "seconds per pair")
    set logscale xy
    set format y "10^{%L}"
    set format x "10^{%L}"
    set yrange [1e-17:1e7]
    set grid
    set key top right font ",7" samplen 2 maxrows 4 width -2
    col = (xv eq "evals") ? 3 : 4
    do for [i=1:8] {
      set title word(titles, i)
      set xlabel (xv eq "evals" ? "evaluations" : "seconds")
      set ylabel "relative error"
      f = sprintf("cfg_%s.dat", word(cfgs, i))
      plot f index 2 using col:6 with linespoints pt 7 ps 0.5 title "gauss:P", \
           f index 3 using col:6 with linespoints pt 5 ps 0.5 title "analytic:P", \
           f index 4 using col:6 with linespoints pt 9 ps 0.6 title "ss:N", \
           f index 0 using col:6 with points pt 2 ps 1.5 title "vertex (notes)", \
           f index 1 using col:6 with points pt 3 ps 1.5 title "centroid", \
           f index 5 using col:6 with points pt 6 ps 1.5 lc rgb "black" title "exact", \
           f index 6 using col:6 with points pt 4 ps 1.5 lc rgb "red" title "auto (1e-3, 1e-6, 1e-9)", \
           1e-6 with lines dt 2 lc rgb "gray" notitle
    }
    unset multiplot
    unset output
  }
}
