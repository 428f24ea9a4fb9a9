#!/usr/bin/env bash
# Installs what the Python module (python/) and the Blender add-on (blender/) need, from Debian
# bookworm's packages: pybind11 2.10, numpy and pytest for the system Python 3.11 (/usr/bin/python3),
# and Blender 3.4, which runs that same Python; xvfb and xauth give Blender a display without a
# GPU (xvfb-run, Mesa's llvmpipe) for scripts/blender-viewport-shot.py's viewport screenshot.
# Idempotent; run as root.
set -euo pipefail

packages=(python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest blender xvfb xauth)

bash "$(dirname "${BASH_SOURCE[0]}")/install-missing-packages.sh" "${packages[@]}"
