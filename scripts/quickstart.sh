#!/usr/bin/env bash
# Installs the dependencies, builds exao (Release, portable: the kernels pick the CPU's instruction set at run time) and runs the main job on the
# built-in room: bakes AO into it (room.glb, with a preview room-preview.png) and renders it from
# its camera (ao.exr, ao.png), all in the current folder. Safe to run again.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release
# exao_api: libexao.so, so that `cmake --install build` works right after (README)
cmake --build "$here/build" -j2 --target exao exao_api
"$here/build/cli/exao" bake
"$here/build/cli/exao" render -o ao.exr --png ao.png
# The Python module (`import exao` in /usr/bin/python3 and Debian's Blender) and the Blender add-on zip.
bash "$here/scripts/install-python.sh"
cmake -S "$here" -B "$here/build"  # finds pybind11 and numpy now
cmake --build "$here/build" -j2 --target _exao exao_blender_addon
cmake --install "$here/build" --component python
/usr/bin/python3 -c "import exao; print('import exao:', exao.Scene.open('room'))"
