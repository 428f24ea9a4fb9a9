#!/usr/bin/env bash
# Installs the dependencies, builds exao and its tests (Release, warnings as errors) and runs
# them with CTest. Benchmarks are built and smoke-run only; `exao bench` measures speed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DEXAO_WERROR=ON
cmake --build "$here/build" -j2
bash "$here/scripts/install-test-tools.sh" "$here/build"
ctest --test-dir "$here/build" --output-on-failure -j2
