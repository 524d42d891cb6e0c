# Figures of the 1D convergence study; reads data/*.dat and slopes.gp (run.sh).
load 'slopes.gp'
set datafile separator "\t"
set datafile commentschars "#"
set key autotitle columnhead
set logscale xy
set format y "10^{%L}"
set format x "10^{%L}"
set grid
set key bottom right font ",9" spacing 1.1

assemblies = "exact midpoint gauss2 gauss4 gausssplit2"
names = "exact midpoint gauss:2 gauss:4 gauss-split:2"
quantities = "l2 linf coef"
qtitle(q) = (q eq "l2") ? "L2 error" : (q eq "linf") ? "L-infinity error" : "max coefficient error vs exact assembly"
qcol(q) = (q eq "l2") ? 3 : (q eq "linf") ? 4 : 6
val(name) = value(name)
legend(p, b, a, q) = sprintf("%s: %s", word(names, a), value(sprintf("s_%s_%s_%s_%s", p, b, word(assemblies, a), q)))
file(p, b, a) = sprintf("data/%s_%s_%s.dat", p, b, word(assemblies, a))
pos(x) = (x > 1e-300) ? x : NaN

do for [fmt in "png pdf"] {
  do for [p in "seed exp"] {
    do for [b in "p0 p1"] {
      if (fmt eq "png") {
        set terminal pngcairo size 1400,1000 enhanced font ",11"
      } else {
        set terminal pdfcairo size 11in,8in enhanced font ",10"
      }
      set output sprintf("figures/%s_%s.%s", p, b, fmt)
      set multiplot layout 2,2 title sprintf("1D model problem '%s', basis %s: convergence and cost", p, b)
      do for [q in quantities] {
        set title qtitle(q)
        set xlabel "h = 1/n"
        set ylabel "error"
        first = (q eq "coef") ? 2 : 1
        plot for [a=first:5] file(p, b, a) using 2:(pos(column(qcol(q)))) with linespoints linetype a title legend(p, b, a, q)
      }
      set title "what accuracy costs: L2 error vs assembly + solve time (n >= 64)"
      set xlabel "seconds"
      plot for [a=1:5] file(p, b, a) using ($1 >= 64 ? pos($11) : NaN):(pos($3)) with linespoints linetype a title word(names, a)
      unset multiplot
      set output
    }
  }
}
