# What radkit's accuracy is worth (run.sh writes the data).
set datafile separator "\t"
set logscale xy
set grid
set format xy "10^{%L}"
cor(m) = sprintf("< awk -F'\\t' '$1==\"%s\"' data/cornell.dat", m)
fur(m) = sprintf("< awk -F'\\t' '$3==\"%s\" && $4 > 0' data/furnaces.dat", m)
do for [fmt in "png pdf"] {
  if (fmt eq "png") { set terminal pngcairo size 1400,600 enhanced font ",11" }
  else { set terminal pdfcairo size 12in,5in enhanced font ",10" }
  set output "figures/accuracy.".fmt
  set multiplot layout 1,2 title "Hierarchical radiosity: requested eps, reported estimate and error"
  set xlabel "requested eps"
  set ylabel "relative to the mean reflected radiosity"
  set title "Cornell box against the Monte Carlo reference (error oracle)"
  set key top left font ",10"
  plot cor("hier-error") using 2:5 with linespoints pt 5 lc 1 title "estimate, worst face", \
       cor("hier-error") using 2:3 with linespoints pt 4 lc 1 dashtype 2 title "error, worst face", \
       cor("hier-error") using 2:6 with linespoints pt 7 lc 2 title "estimate, L1", \
       cor("hier-error") using 2:4 with linespoints pt 6 lc 2 dashtype 2 title "error, L1", \
       x with lines lc "black" dashtype 3 title "= eps"
  set title "Every run: the error against the estimate (below the line: the bound holds)"
  set xlabel "error estimate (worst face)"
  set ylabel "error (worst face)"
  set key bottom right font ",10"
  plot cor("hier-error") using 5:3 with points pt 5 title "Cornell, error oracle", \
       cor("hier-bf") using 5:3 with points pt 9 title "Cornell, BF oracle", \
       fur("hier") using 6:4 with points pt 7 title "furnaces, hier defaults", \
       fur("hier-eps0.01") using 6:4 with points pt 6 title "furnaces, hier eps 0.01", \
       x with lines lc "black" dashtype 3 title "error = estimate"
  unset multiplot
  set output
}
