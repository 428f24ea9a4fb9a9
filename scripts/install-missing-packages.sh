#!/usr/bin/env bash
# Installs those of the given Debian packages that are not installed yet: one apt-get update
# and one install for all of them, nothing at all when every one is there (so the scripts that
# call it are idempotent and cheap to run again). For scripts/install-deps.sh and
# scripts/install-python.sh. Run as root.
#
# Usage: scripts/install-missing-packages.sh PACKAGE...
set -euo pipefail

missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
