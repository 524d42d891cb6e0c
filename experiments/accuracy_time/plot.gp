# Error against time and against elements for dense radiosity on the Cornell box.
set datafile separator "\t"
set logscale xy
set format y "10^{%L}"
set grid
set key top right font ",10"
set ylabel "L1 error of face radiosity / mean reflected"
# The Monte Carlo reference's own standard error (run.sh): below it, differences are noise.
refest = real(system("awk '/reference_se_l1 =/{print $4}' data/errors.dat"))
rules = system("awk -F'\\t' '!/^#/ && $1 != \"rule\" && !seen[$1]++ {printf \"%s \", $1}' data/errors.dat")
do for [fmt in "png pdf"] {
  if (fmt eq "png") { set terminal pngcairo size 1300,560 enhanced font ",11" }
  else { set terminal pdfcairo size 11in,4.7in enhanced font ",10" }
  set output "figures/accuracy_time.".fmt
  set multiplot layout 1,2 title "Cornell box, dense Galerkin radiosity: what accuracy costs"
  set xlabel "wall time (s), 2 cores"
  set format x "10^{%L}"
  plot for [r in rules] sprintf("< awk -F'\\t' '$1==\"%s\"' data/errors.dat", r) using 5:4 with linespoints title r, \
       refest with lines dashtype 2 lc "black" title "reference standard error"
  set xlabel "elements"
  set format x "%g"
  plot for [r in rules] sprintf("< awk -F'\\t' '$1==\"%s\"' data/errors.dat", r) using 3:4 with linespoints title r, \
       refest with lines dashtype 2 lc "black" title "reference standard error"
  unset multiplot
  set output
}
