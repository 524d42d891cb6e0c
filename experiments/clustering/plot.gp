# Clustering: links and time against triangles (run.sh writes the data).
set datafile separator "\t"
set logscale xy
set grid
set key bottom right font ",10"
set xrange [100:3e6]
sel(m) = sprintf("< awk -F'\\t' '$1==\"%s\"' data/scaling.dat", m)
loose = "< awk -F'\\t' '$1==\"cluster-preview\"' data/scaling_loose.dat data/target.dat"
coarse = "< awk -F'\\t' '$1==\"cluster-coarse\"' data/target.dat"
do for [fmt in "png pdf"] {
  if (fmt eq "png") { set terminal pngcairo size 1700,520 enhanced font ",11" }
  else { set terminal pdfcairo size 15in,4.5in enhanced font ",10" }
  set output "figures/scaling.".fmt
  set multiplot layout 1,3 title "Rooms of N boxes (scenes/gen/many\\_objects.py), eps 0.1; preview: eps 1, --max-tighten 0; 1.2M triangles at eps 3"
  set xlabel "input triangles"
  set ylabel "links (pairs coupled)"
  plot sel("hier") using 3:4 with linespoints pt 7 title "hier", \
       sel("cluster") using 3:4 with linespoints pt 5 title "cluster, oriented", \
       sel("cluster-iso") using 3:4 with linespoints pt 9 title "cluster, iso", \
       loose using 3:4 with linespoints pt 11 title "cluster, preview (to 360k)", \
       coarse using 3:4 with points pt 13 ps 1.5 title "cluster, eps 3, --max-tighten 0"
  set ylabel "wall time (s), 2 cores"
  plot sel("hier") using 3:7 with linespoints pt 7 title "hier", \
       sel("cluster") using 3:7 with linespoints pt 5 title "cluster, oriented", \
       sel("cluster-iso") using 3:7 with linespoints pt 9 title "cluster, iso", \
       loose using 3:7 with linespoints pt 11 title "cluster, preview (to 360k)", \
       coarse using 3:7 with points pt 13 ps 1.5 title "cluster, eps 3, --max-tighten 0", \
       "< printf '120012\\t120\\n'" using 1:2 with points pt 6 ps 2 lc rgb "red" title "target: 120k triangles in 120 s", \
       "< printf '1200012\\t60\\n'" using 1:2 with points pt 4 ps 2 lc rgb "red" title "goal: 1.2M triangles in 60 s"
  set ylabel "peak memory (GB)"
  plot sel("hier") using 3:($8/1e9) with linespoints pt 7 title "hier", \
       sel("cluster") using 3:($8/1e9) with linespoints pt 5 title "cluster, oriented", \
       sel("cluster-iso") using 3:($8/1e9) with linespoints pt 9 title "cluster, iso", \
       loose using 3:($8/1e9) with linespoints pt 11 title "cluster, preview (to 360k)", \
       coarse using 3:($8/1e9) with points pt 13 ps 1.5 title "cluster, eps 3, --max-tighten 0", \
       "< printf '120012\\t6\\n'" using 1:2 with points pt 6 ps 2 lc rgb "red" title "target: 120k triangles in 6 GB", \
       "< printf '1200012\\t8\\n'" using 1:2 with points pt 4 ps 2 lc rgb "red" title "goal: 1.2M triangles in 8 GB"
  unset multiplot
}
