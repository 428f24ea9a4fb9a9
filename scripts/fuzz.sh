#!/usr/bin/env bash
# Fuzzes every loader with AFL++ for a bounded time and fails on any crash (README, "Fuzzing").
#   bash scripts/fuzz.sh [SECONDS_PER_CAMPAIGN]      (default 120; FUZZ_SECONDS also sets it)
# Seven campaigns, two at a time: glTF/GLB; OBJ, PLY, OFF, STL; receivers as text and as PLY.
# The targets (tests/fuzz/) are built in build-fuzz/ with AFL++'s GCC wrapper and ASan+UBSan, so
# a memory error is a crash too. Findings stay in build-fuzz/findings/<campaign>/default/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-${FUZZ_SECONDS:-120}}"
build="$here/build-fuzz"

# AFL++ from Debian. Its GCC plugin (afl-g++-fast) refuses Debian's own GCC 12 ("incompatible
# versions") and clang 14 cannot compile std::expected with libstdc++ 12, so the targets use
# afl-g++: GCC with AFL++'s assembler-level edge instrumentation and its fork server.
if ! dpkg-query -W -f='${Status}' afl++ 2>/dev/null | grep -q "install ok installed"; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends afl++
fi

export AFL_USE_ASAN=1 AFL_USE_UBSAN=1 AFL_QUIET=1
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DEXAO_FUZZ=ON -DEXAO_BUILD_TESTS=OFF \
  -DEXAO_BUILD_BENCHMARKS=OFF -DCMAKE_C_COMPILER=afl-gcc -DCMAKE_CXX_COMPILER=afl-g++ >/dev/null
cmake --build "$build" -j2 --target exao_fuzz_gltf exao_fuzz_soup exao_fuzz_points exao_fuzz_seeds
unset AFL_USE_ASAN AFL_USE_UBSAN AFL_QUIET

bash "$here/scripts/fuzz-seeds.sh" "$build/tests/fuzz/exao_fuzz_seeds" "$build/seeds"

# Containers have no CPU frequency governor and may send core dumps to a pipe: neither matters
# for a bounded run. UBSan must abort for AFL++ to see a crash; ASan's options are AFL++'s own.
export AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1 AFL_NO_AFFINITY=1
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1"
export ASAN_OPTIONS="abort_on_error=1:symbolize=0:detect_leaks=0:allocator_may_return_null=1"

# campaign = target:extension:seed folder
campaigns=(gltf:gltf:gltf soup:obj:obj soup:ply:ply soup:off:off soup:stl:stl points:txt:points-txt points:ply:points-ply)
failed=0
mkdir -p "$build/findings"
printf '%-12s %10s %8s %8s %8s %8s\n' campaign execs exec/s corpus crashes hangs
# The campaigns run two at a time, one core each (AFL_NO_AFFINITY): half the wall time of one
# after another on CI's two cores.
campaign() {
  local target ext seeds name findings
  IFS=: read -r target ext seeds <<<"$1"
  name="$target-$ext"
  findings="$build/findings/$name"
  rm -rf "$findings" "$findings.failed"
  # -t: an input that runs for 5 s is a hang (class 2 of issue 16 was one); -m none: ASan
  # reserves terabytes of address space.
  afl-fuzz -i "$build/seeds/$seeds" -o "$findings" -e "$ext" -V "$seconds" -t 5000 -m none \
    -- "$build/tests/fuzz/exao_fuzz_$target" @@ >"$build/afl-$name.log" 2>&1 || touch "$findings.failed"
}
running=0
for c in "${campaigns[@]}"; do
  campaign "$c" &
  running=$((running + 1))
  if [ $((running % 2)) -eq 0 ]; then wait; fi
done
wait

for c in "${campaigns[@]}"; do
  IFS=: read -r target ext seeds <<<"$c"
  name="$target-$ext"
  findings="$build/findings/$name"
  if [ -e "$findings.failed" ]; then
    echo "afl-fuzz failed for $name:"; tail -20 "$build/afl-$name.log"; failed=1; continue
  fi
  stats="$findings/default/fuzzer_stats"
  get() { awk -F' *: *' -v k="$1" '$1 == k { print $2 }' "$stats"; }
  crashes=$(find "$findings/default/crashes" -name 'id:*' 2>/dev/null | wc -l)
  hangs=$(find "$findings/default/hangs" -name 'id:*' 2>/dev/null | wc -l)
  printf '%-12s %10s %8s %8s %8s %8s\n' "$name" "$(get execs_done)" "$(get execs_per_sec)" "$(get corpus_count)" "$crashes" "$hangs"
  if [ "$crashes" -gt 0 ]; then
    failed=1
    for f in "$findings"/default/crashes/id:*; do
      echo "crash: $f"
      cp "$f" "$build/crash.$ext"
      ASAN_OPTIONS=detect_leaks=0 "$build/tests/fuzz/exao_fuzz_$target" "$build/crash.$ext" 2>&1 | tail -25 || true
      break
    done
  fi
  # A hang under AFL++'s load may be only slow: it fails the run if it still takes 30 s alone.
  for f in "$findings"/default/hangs/id:*; do
    [ -e "$f" ] || continue
    cp "$f" "$build/hang.$ext"
    rc=0
    timeout 30 "$build/tests/fuzz/exao_fuzz_$target" "$build/hang.$ext" >/dev/null 2>&1 || rc=$?
    if [ "$rc" -eq 124 ]; then
      echo "hang: $f (over 30 s alone)"
      failed=1
    fi
  done
done
exit $failed
