#!/usr/bin/env bash
# The benchmark suite of issues 10 and 19: exao against Embree where exao's users work, one run,
# about fifteen minutes on 2 cores. Every row is a ratio to Embree (packet16) measured in the same run,
# on the same receivers and rays, with the agreement with Embree.
#
#   bash scripts/bench-suite.sh [BUILD_DIR] [OUT_DIR]     (defaults: build, BUILD_DIR/bench-suite)
#
# Needs the real scenes (../shared/scenes, or EXAO_SCENES_DIR). Writes, per workload, JSON, an
# SVG chart and a Markdown table, and OUT_DIR/suite.md: every table in one (the README's).
# Measures the build it is given: the portable one (the default CMake configuration) is what
# users get.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$build/bench-suite}"
scenes="${EXAO_SCENES_DIR:-$here/../shared/scenes}"
exao="$build/cli/exao"
conference="$scenes/Conference/conference.obj"
truck="$scenes/CesiumMilkTruck/glTF/CesiumMilkTruck.gltf"
for f in "$exao" "$conference" "$truck"; do
  [ -e "$f" ] || { echo "bench-suite: $f is missing (build exao; set EXAO_SCENES_DIR)" >&2; exit 1; }
done
mkdir -p "$out"
camera=(--eye=-900,450,-900 --target=1000,150,400 --fov 60)

run() {  # name label args...
  local name="$1" label="$2"
  shift 2
  echo "== $label" >&2
  "$exao" bench "$@" --label "$label" --json "$out/$name.json" --svg "$out/$name.svg" --markdown "$out/$name.md" \
    | tee "$out/$name.txt"
}

# auto (the default: masks under its cost model, Embree for the rest) beside bvh (the paper's
# method alone) on every row.
run pixels "Conference pixels 256x192" "$conference" "${camera[@]}" -W 256 -H 192 -n 64,128,1024 -r 1%,2%,5% \
  --methods auto,bvh,raster --masks exact --repeats 2
run vertices "Conference vertex-bake receivers" "$conference" --receivers vertices -n 128,1024 -r 1%,5% \
  --methods auto,bvh --masks exact
run texels "CesiumMilkTruck texel-bake receivers 1024^2" "$truck" --receivers texels:1024 -n 128 -r 5% \
  --methods auto,bvh --masks exact
# Cut-outs (issue 24): the built-in foliage scene (checker-alpha cards over a ground, alphaMode
# MASK), against Embree with its occlusion filter deciding the alpha of every hit.
run foliage "foliage pixels 256x192 (alpha-tested cards)" foliage -W 256 -H 192 -n 128 -r 5% \
  --methods auto,bvh --masks exact --repeats 2
# The Khronos models' vertices: receivers in dense geometry (issue 19).
khronos=()
for model in 2CylinderEngine BrainStem CesiumMilkTruck Fox; do
  file="$scenes/$model/glTF/$model.gltf"
  [ -e "$file" ] || continue
  run "vertices-$model" "$model vertex-bake receivers" "$file" --receivers vertices -n 128 -r 5% --methods auto,bvh --masks exact
  khronos+=("vertices-$model")
done

# The public API's single-point ao(), one thread, against the caller's own rtcOccluded1 and
# rtcOccluded16 loops on the same rays (tests/benchmarks/api_benchmark.cpp).
api="$build/tests/benchmarks/api_benchmark"
if [ -x "$api" ]; then
  for scene in room "$conference"; do
    tag=$(basename "$scene" .obj)
    echo "== API single points, $tag" >&2
    EXAO_BENCH_SCENE="$scene" "$api" --benchmark_filter='BM_(ExaoAo/exact|ExaoAo/auto|EmbreeOccluded1|EmbreeOccluded16)/N:(64|256)/r_permille:(10|50)/real_time/threads:1$' \
      --benchmark_min_time=0.5 --benchmark_format=json --benchmark_out="$out/api-$tag.json" --benchmark_out_format=json \
      >/dev/null
  done
fi

{
  echo "| workload | N | r | method | Mrays/s | x embree | rays agreeing | receivers identical |"
  echo "|---|---|---|---|---|---|---|---|"
  for name in pixels vertices texels foliage "${khronos[@]}"; do tail -n +3 "$out/$name.md"; done
  for json in "$out"/api-*.json; do
    [ -e "$json" ] || continue
    tag=$(basename "$json" .json)
    # items_per_second per (method, N, r): exao's exact ao() against the better caller loop.
    node -e '
      const j = require(require("path").resolve(process.argv[1])); const rate = {};
      for (const b of j.benchmarks) {
        const m = b.name.match(/^BM_(\w+?)(?:\/(exact|auto))?\/N:(\d+)\/r_permille:(\d+)/); if (!m) continue;
        const key = m[3] + "/" + m[4], name = m[1] + (m[2] ? "_" + m[2] : "");
        rate[key] = rate[key] || {}; rate[key][name] = b.items_per_second;
      }
      for (const [k, r] of Object.entries(rate)) {
        const [n, pm] = k.split("/"); const best = Math.max(r.EmbreeOccluded1 || 0, r.EmbreeOccluded16 || 0);
        for (const [label, v] of [["auto", r.ExaoAo_auto], ["bvh exact", r.ExaoAo_exact]]) {
          if (!v) continue;
          console.log(`| ${process.argv[2]} single ao() | ${n} | ${pm / 10}% | exao ${label} vs caller rtcOccluded1 ${(r.EmbreeOccluded1/1e3).toFixed(0)}k, rtcOccluded16 ${(r.EmbreeOccluded16/1e3).toFixed(0)}k points/s | ${(v*n/1e6).toFixed(1)} | **${(v/best).toFixed(2)}** (vs best loop) | | |`);
        }
      }' "$json" "${tag#api-}"
  done
} > "$out/suite.md"
echo "bench-suite: $out/suite.md" >&2
cat "$out/suite.md"
