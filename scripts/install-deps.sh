#!/usr/bin/env bash
# Installs exao's build and test dependencies from Debian bookworm's packages.
# Idempotent: apt-get skips what is already installed. Run as root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libembree-dev libtbb-dev libglm-dev libopenexr-dev libtinygltf-dev nlohmann-json3-dev
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libpng-dev libcli11-dev
  libdraco-dev libmeshoptimizer-dev
  draco gltfpack  # command-line encoders: the tests make Draco and meshopt files with them
  libgtest-dev libgmock-dev libbenchmark-dev
  time  # GNU time: scripts/bench-scale.sh's peak memory
)

bash "$(dirname "${BASH_SOURCE[0]}")/install-missing-packages.sh" "${packages[@]}"
