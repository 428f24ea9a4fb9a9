#!/usr/bin/env bash
# The whole test suite again, built with AddressSanitizer and UndefinedBehaviorSanitizer
# (EXAO_SANITIZE=ON, no recovery: any report fails its test) in a second build folder,
# build-sanitize/. scripts/test.sh runs it after the plain suite. Benchmarks are not built: they
# are never tests, and the plain build already smoke-runs them. Nor is the Python module: a
# sanitized extension cannot load into a plain python3 (the runtime must come first), and the
# plain suite already runs its tests and the Blender add-on's.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$here/build-sanitize"
bash "$here/scripts/install-deps.sh"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DEXAO_SANITIZE=ON -DEXAO_WERROR=ON \
  -DEXAO_BUILD_BENCHMARKS=OFF -DEXAO_BUILD_PYTHON=OFF
cmake --build "$build" -j2
# The glTF validator of the plain build serves this one too (scripts/install-test-tools.sh).
if [ -d "$here/build/test-tools" ] && [ ! -e "$build/test-tools" ]; then
  ln -s "$here/build/test-tools" "$build/test-tools"
else
  bash "$here/scripts/install-test-tools.sh" "$build"
fi
# Leaks count too (LeakSanitizer runs at every test program's exit).
export ASAN_OPTIONS="detect_leaks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir "$build" --output-on-failure -j2
