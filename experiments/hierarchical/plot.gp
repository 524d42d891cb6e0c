# Hierarchical vs dense radiosity on the Cornell box (run.sh writes the data).
set datafile separator "\t"
set logscale xy
set grid
set key bottom left font ",10"
set format y "10^{%L}"
sel(m) = sprintf("< awk -F'\\t' '$1==\"%s\"' data/runs.dat", m)
# The Monte Carlo reference's own standard error (run.sh): below it, differences are noise.
refse = real(system("awk '/reference_se_l1 =/{print $4}' data/runs.dat"))
do for [fmt in "png pdf"] {
  if (fmt eq "png") { set terminal pngcairo size 1500,500 enhanced font ",11" }
  else { set terminal pdfcairo size 13in,4.3in enhanced font ",10" }
  set output "figures/hierarchical.".fmt
  set multiplot layout 1,3 title "Cornell box: hierarchical (two oracles) against dense radiosity"
  set ylabel "L1 error of face radiosity / mean reflected"
  set xlabel "wall time (s), 2 cores"
  set format x "10^{%L}"
  plot sel("dense-auto") using 6:5 with linespoints pt 7 title "dense, auto (refine 0..3)", \
       sel("dense-gauss2") using 6:5 with linespoints pt 6 title "dense, gauss:2 (refine 0..3)", \
       sel("hier-bf") using 6:5 with linespoints pt 5 title "hier, BF oracle", \
       sel("hier-error") using 6:5 with linespoints pt 9 title "hier, error oracle", \
       sel("hier-error-p1") using 6:5 with linespoints pt 11 title "hier, error, p1", \
       sel("hier-error-p2") using 6:5 with linespoints pt 13 title "hier, error, p2", \
       0.01 with lines dashtype 2 lc "black" title "1%", \
       0.005 with lines dashtype 4 lc "black" title "0.5%", \
       refse with lines dashtype 3 lc "gray" title "reference standard error"
  set xlabel "links (coupled pairs; dense: facing pairs)"
  plot sel("dense-auto") using 4:5 with linespoints pt 7 title "dense", \
       sel("hier-bf") using 4:5 with linespoints pt 5 title "hier, BF", \
       sel("hier-error") using 4:5 with linespoints pt 9 title "hier, error"
  set xlabel "elements (leaves)"
  set ylabel "links (coupled pairs)"
  set format y "10^{%L}"
  set key top left
  plot sel("dense-auto") using 3:4 with linespoints pt 7 title "dense: n^2", \
       sel("hier-bf") using 3:4 with linespoints pt 5 title "hier, BF", \
       sel("hier-error") using 3:4 with linespoints pt 9 title "hier, error"
  unset multiplot
  set output
}
