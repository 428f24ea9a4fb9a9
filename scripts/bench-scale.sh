#!/usr/bin/env bash
# The scale benchmark (issue 21): a generated bumpy terrain (scripts/make-terrain.py) at 0.5M,
# 2M, 8M and 32M triangles in binary PLY; per size the load time (exao info), and for
# `exao query --method bvh` and `--method embree` on the same 20,000 receivers (r = 2%, N = 128)
# the load, build and AO times and the peak resident memory. Writes a markdown table and a
# log-log plot (SVG) of time and memory against triangles. Not a test: timings, on whatever
# else the machine runs.
#
#   scripts/bench-scale.sh [--exao PATH] [--sizes "0.5 2 8 32"] [--out PREFIX] [--work DIR] [--threads T]
#
# Writes PREFIX.md and PREFIX.svg (default: DIR/scale, beside the terrains; docs/scale.md quotes a
# run and explains it, so the script never overwrites it). A size whose expected peak (200 bytes a
# triangle: both methods peak at 140-160 on the terrains) is more than half of MemAvailable is
# skipped (the machine is shared), and the table says so.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
exao="$root/build/cli/exao"
sizes="0.5 2 8 32"
work="${TMPDIR:-/tmp}/exao-bench-scale"
out=""
threads=0
while [ $# -gt 0 ]; do
  case "$1" in
    --exao) exao="$2"; shift 2 ;;
    --sizes) sizes="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    *) echo "bench-scale.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -x "$exao" ] || { echo "bench-scale.sh: $exao: not built (cmake --build build --target exao)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench-scale.sh: /usr/bin/time: missing (scripts/install-deps.sh installs GNU time)" >&2; exit 1; }
[ -n "$out" ] || out="$work/scale"
mkdir -p "$work" "$(dirname "$out")"

# The mask kernels' instruction set: the best this CPU runs (the engine's own choice, cpuid).
isa=scalar
for level in sse4_2:sse4 avx2:avx2 avx512f:avx512; do grep -qw "${level%%:*}" /proc/cpuinfo && isa=${level##*:}; done
points="$work/points.txt"
results="$work/results.tsv"
printf 'triangles\tfile_mb\tinfo_s\tinfo_mb\tmethod\tload_s\tbuild_s\tao_s\twall_s\tpeak_mb\n' > "$results"
skipped=()

# run LABEL CMD...: the command's stdout in $work/LABEL.out, "wall peak_kb" in $work/LABEL.time.
run() {
  local label="$1"; shift
  /usr/bin/time -f '%e %M' -o "$work/$label.time" "$@" > "$work/$label.out"
}

for m in $sizes; do
  n=$(python3 -c "import math; print(round(math.sqrt($m * 1e6 / 2)))")
  triangles=$((2 * n * n))
  available_kb=$(awk '/MemAvailable/ {print $2}' /proc/meminfo)
  if [ $((triangles * 200 / 1024)) -gt $((available_kb / 2)) ]; then
    echo "bench-scale.sh: ${m}M triangles: skipped, about $((triangles * 200 / 1048576)) MB needed, $((available_kb / 1024)) MB available" >&2
    skipped+=("$m")
    continue
  fi
  ply="$work/terrain-$n.ply"
  [ -s "$ply" ] || python3 "$root/scripts/make-terrain.py" "$n" "$ply"
  [ -s "$points" ] || python3 "$root/scripts/make-terrain.py" 1 "$work/unused.ply" --points 20000 "$points"
  file_mb=$(python3 -c "import os; print(round(os.path.getsize('$ply') / 1e6, 1))")
  echo "== ${m}M triangles ($triangles, $file_mb MB)" >&2
  run "info-$n" "$exao" info "$ply"
  read -r info_s info_kb < "$work/info-$n.time"
  for method in bvh embree; do
    run "$method-$n" "$exao" query "$ply" --points "$points" -r 2% -n 128 -j "$threads" --method "$method" -o "$work/ao-$method-$n.txt"
    read -r wall_s peak_kb < "$work/$method-$n.time"
    load_s=$(sed -n 's/.*loaded in \([0-9.]*\) s.*/\1/p' "$work/$method-$n.out")
    build_s=$(sed -n 's/.*prepared in \([0-9.]*\) s.*/\1/p' "$work/$method-$n.out")
    ao_s=$(sed -n "s/.*$method: \([0-9.]*\) s (.*/\1/p" "$work/$method-$n.out")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$triangles" "$file_mb" "$info_s" $((info_kb / 1024)) "$method" \
      "$load_s" "$build_s" "$ao_s" "$wall_s" $((peak_kb / 1024)) >> "$results"
    echo "   $method: load $load_s s, build $build_s s, AO $ao_s s, wall $wall_s s, peak $((peak_kb / 1024)) MB" >&2
  done
  # bvh may differ from Embree on a few grazing rays (DESIGN.md 8.3): count the receivers.
  differ=$(paste -d' ' "$work/ao-bvh-$n.txt" "$work/ao-embree-$n.txt" | awk '$1 != $2' | wc -l)
  echo "   bvh and embree AO: $differ of $(wc -l < "$points") receivers differ" >&2
done

python3 "$root/scripts/scale_plot.py" "$results" "$out.md" "$out.svg" "$(nproc)" "$isa" "${skipped[*]:-}"
echo "-> $out.md, $out.svg" >&2
