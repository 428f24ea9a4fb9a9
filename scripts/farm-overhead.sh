#!/usr/bin/env bash
# The cost of sharding (docs/farm.md): one render of Conference against the same render in
# SHARDS parts run one after another, plus the merge, in CPU seconds (user + system, so that a
# busy machine does not skew it) and wall seconds, and the check that the merged files are the
# same bytes. "fixed" is an empty part (--shard 0/65536): reading the scene, building the BVH and
# the primary rays, with no AO.
#   bash scripts/farm-overhead.sh build/cli/exao [WIDTH HEIGHT SAMPLES SHARDS]
set -euo pipefail
exao=$(realpath "${1:?usage: farm-overhead.sh EXAO [WIDTH HEIGHT SAMPLES SHARDS]}")
width=${2:-640} height=${3:-480} samples=${4:-256} shards=${5:-4}
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scene="${EXAO_SCENES_DIR:-$here/../shared/scenes}/Conference/conference.obj"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
view=(--eye -900,350,-950 --target 600,150,300 --fov 70 -W "$width" -H "$height" -n "$samples")
timed() {  # LABEL COMMAND...: prints "LABEL wall cpu"
  local label=$1; shift
  /usr/bin/time -f "$label %e %U %S" "$@" > /dev/null 2> "$work/time" || { cat "$work/time"; exit 1; }
  tail -n 1 "$work/time" | awk '{printf "%-8s %8.2f s wall %8.2f s cpu\n", $1, $2, $3 + $4}'
}
mkdir -p "$work/one" "$work/parts" "$work/fixed"
echo "Conference, ${width}x${height}, N=$samples, $shards shards, $(nproc) cores"
(cd "$work/one" && timed one "$exao" render "$scene" "${view[@]}" -o ao.exr --png ao.png)
(cd "$work/fixed" && timed fixed "$exao" render "$scene" "${view[@]}" -o ao.exr --png ao.png --shard 0/65536)
cd "$work/parts"
for ((k = 0; k < shards; ++k)); do
  timed "shard$k" "$exao" render "$scene" "${view[@]}" -o ao.exr --png ao.png --shard "$k/$shards"
done
timed merge "$exao" merge ao.exr.part-*-of-*.exao -o ao.exr
cmp ao.exr ../one/ao.exr && cmp ao.png ../one/ao.png && echo "merged output: identical to the one run"
