#!/usr/bin/env bash
# Installs the dependencies, builds exao and its tests (Release, warnings as errors) and runs
# them with CTest. Benchmarks are built and smoke-run only; `exao bench` measures speed.
# Then, unless --quick is given: the whole suite again under ASan + UBSan (build-sanitize/,
# scripts/test-sanitize.sh) and every fuzz campaign for FUZZ_SECONDS (default 60 here) each,
# failing on any crash (build-fuzz/, scripts/fuzz.sh). As root it installs SLURM
# (scripts/install-slurm.sh) so that the scheduler test (tests/slurm_shards.sh) runs.
# CI runs all three: about 40 minutes on 2 cores once the packages are installed (plain build +
# tests ~9 min, sanitizer build + tests ~23, fuzzing ~8).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
quick=0
[ "${1:-}" = "--quick" ] && quick=1
bash "$here/scripts/install-deps.sh"
bash "$here/scripts/install-python.sh"  # the Python module and Blender add-on tests
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DEXAO_WERROR=ON
cmake --build "$here/build" -j2
bash "$here/scripts/install-test-tools.sh" "$here/build"
# SLURM for the sharded bake on a real scheduler (ctest's slurm_shards): the test starts its own
# one-node cluster and reports itself skipped where SLURM cannot be installed (not root).
if [ "$(id -u)" = 0 ]; then bash "$here/scripts/install-slurm.sh"; fi
ctest --test-dir "$here/build" --output-on-failure -j2
if [ "$quick" = 0 ]; then
  bash "$here/scripts/test-sanitize.sh"
  bash "$here/scripts/fuzz.sh" "${FUZZ_SECONDS:-60}"
fi
