#!/usr/bin/env bash
# Installs the tools some tests need beyond the build: the Khronos glTF validator (npm package
# gltf-validator), used by scripts/validate-gltf.js to check every glTF that `exao bake` writes.
#
# Usage: scripts/install-test-tools.sh [BUILD_DIR]   (default: build/ in the repository root)
# Installs into BUILD_DIR/test-tools/ with npm (no global install, nothing outside that folder);
# the tests find it there and report themselves skipped when it is missing. Idempotent: a second
# run with the same version installed does nothing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
tools="$build/test-tools"
version="2.0.0-dev.3.10"

if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  # A fresh Debian machine has neither: Debian's own packages are enough for the validator.
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null || true
  fi
fi
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  echo "install-test-tools: node and npm are needed for the glTF validator; the tests that use it will be skipped" >&2
  exit 0
fi
installed="$(node -e "try{console.log(require('$tools/node_modules/gltf-validator/package.json').version)}catch(e){}" 2>/dev/null || true)"
if [ "$installed" = "$version" ]; then
  exit 0
fi
mkdir -p "$tools"
# A package.json of its own keeps npm from walking up into the repository.
[ -f "$tools/package.json" ] || echo '{"name":"exao-test-tools","private":true}' > "$tools/package.json"
npm install --prefix "$tools" --no-audit --no-fund --loglevel=error "gltf-validator@$version"
