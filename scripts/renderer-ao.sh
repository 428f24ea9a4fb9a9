#!/usr/bin/env bash
# The example renderer's AO pass (examples/renderer.cpp, --measure-ao) against its own
# rtcOccluded16 loop, at N = 64 and 256, in one run each: the shading points of one path per
# pixel (mirrors followed), AO by exao's batch query, by exao's single queries from the
# renderer's threads, and by the renderer's own loop of 16-ray packets. Ratios are the Embree
# loop's time over exao's (above 1: exao is faster). The instruction set is the mask kernels'
# (EngineInfo::simd; Embree picks the same best level for itself).
#   bash scripts/renderer-ao.sh build/examples/exao_renderer [WIDTH HEIGHT]
set -euo pipefail
renderer=$(realpath "${1:?usage: renderer-ao.sh EXAO_RENDERER [WIDTH HEIGHT]}")
width=${2:-640} height=${3:-360}
echo "exao_renderer --measure-ao, ${width}x${height}, $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for n in 64 256; do
  echo "--- N = $n"
  "$renderer" --measure-ao -W "$width" -H "$height" --samples "$n"
done
