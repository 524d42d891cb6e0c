#!/bin/sh
# scripts/machine.sh: one line naming the machine a benchmark ran on (cores,
# processor model and family, clock): wall times depend on the processor as
# much as on the build, so a table of times says where it was measured.
cores=$(nproc)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
family=$(sed -n 's/^cpu family[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
model=$(sed -n 's/^model[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
mhz=$(sed -n 's/^cpu MHz[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1 | cut -d. -f1)
printf '%s cores, %s (family %s, model %s), %s MHz\n' "$cores" "${cpu:-unknown processor}" \
  "${family:-?}" "${model:-?}" "${mhz:-?}"
