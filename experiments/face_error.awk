# The error measure of the radiosity experiments: the relative area-weighted
# L2 difference of two per-face tables (radkit solve --out), table first and
# reference second, over three channels, emitters excluded (their radiosity
# is their emission): the faces whose reference B_r exceeds half the largest
# (in the Cornell box, the two triangles of the lamp).
# Usage: awk -F'\t' -f experiments/face_error.awk TABLE REFERENCE
FNR == 1 { file++ }
/^#/ || $1 == "face" { next }
file == 1 { a[$1] = $2; r[$1] = $3; g[$1] = $4; b[$1] = $5; next }
{ ra[$1] = $2; rr[$1] = $3; rg[$1] = $4; rb[$1] = $5 }
END {
  for (f in rr) if (rr[f] > top) top = rr[f]
  for (f in rr) {
    if (rr[f] > 0.5 * top) continue
    num += ra[f] * ((r[f]-rr[f])^2 + (g[f]-rg[f])^2 + (b[f]-rb[f])^2)
    den += ra[f] * (rr[f]^2 + rg[f]^2 + rb[f]^2)
  }
  printf "%.6e", (den > 0 ? sqrt(num / den) : 0) }
