#!/usr/bin/env bash
# The README's viewer pictures, in a real glTF viewer (three.js in headless Chromium,
# scripts/viewer-shot.js): CesiumMilkTruck before and after `exao bake --texture --ground`, and
# Duck baked on its own stacked UVs (--uv file) and on a generated set (--uv auto).
#
# Usage: scripts/viewer-pictures.sh [BUILD_DIR] [SCENES_DIR]
#   (defaults: build/ and ../shared/scenes beside the repository)
# Needs a built exao (BUILD_DIR/cli/exao). Installs, once: Debian's chromium with apt-get (as
# root, when missing) and three + playwright-core from the npm registry into BUILD_DIR/tools/viewer
# (nothing global, nothing at build time). Writes docs/truck-viewer.png and docs/duck-viewer.png
# and leaves the bakes in BUILD_DIR/tools/viewer/out/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
scenes="${2:-$here/../shared/scenes}"
tools="$build/tools/viewer"
three_version="0.160.0"
playwright_version="1.49.1"

truck="$scenes/CesiumMilkTruck/glTF/CesiumMilkTruck.gltf"
duck="$scenes/Duck/glTF-Binary/Duck.glb"
for f in "$truck" "$duck"; do
  [ -f "$f" ] || { echo "viewer-pictures: $f not found (pass the scenes folder)" >&2; exit 1; }
done
[ -x "$build/cli/exao" ] || { echo "viewer-pictures: $build/cli/exao not found: build exao first" >&2; exit 1; }

if ! command -v chromium >/dev/null; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium >/dev/null
  else
    echo "viewer-pictures: chromium is needed (apt-get install chromium)" >&2
    exit 1
  fi
fi
for tool in node npm; do
  command -v "$tool" >/dev/null || { echo "viewer-pictures: $tool is needed (apt-get install nodejs npm)" >&2; exit 1; }
done

mkdir -p "$tools/out"
# A package.json of its own keeps npm from walking up into the repository.
[ -f "$tools/package.json" ] || echo '{"name":"exao-viewer-tools","private":true}' > "$tools/package.json"
installed="$(node -e "try{console.log(require('$tools/node_modules/three/package.json').version+' '+require('$tools/node_modules/playwright-core/package.json').version)}catch(e){}" 2>/dev/null || true)"
if [ "$installed" != "$three_version $playwright_version" ]; then
  npm install --prefix "$tools" --no-audit --no-fund --loglevel=error "three@$three_version" "playwright-core@$playwright_version"
fi

# The bake: per texel at 512^2, with --uv auto (the truck's glass and trim have no UV area) and
# a ground plane for the contact shadow under the wheels.
"$build/cli/exao" bake "$truck" --texture 512 -n 128 --ground --preview '' -o "$tools/out/truck-ao.glb"

node "$here/scripts/viewer-shot.js" --modules "$tools" --out "$here/docs/truck-viewer.png" --width 1600 --height 640 \
  --view 40,18 --label "CesiumMilkTruck as it comes" --label "after exao bake --texture 512 --ground" \
  "$truck" "$tools/out/truck-ao.glb"

"$build/cli/exao" bake "$duck" --texture 512 -n 128 --uv file --preview '' -o "$tools/out/duck-file.glb"
"$build/cli/exao" bake "$duck" --texture 512 -n 128 --preview '' -o "$tools/out/duck-auto.glb"
node "$here/scripts/viewer-shot.js" --modules "$tools" --out "$here/docs/duck-viewer.png" --width 1500 --height 600 \
  --view 60,10 --label "Duck as it comes" --label "baked on its own UVs (--uv file)" --label "baked with --uv auto" \
  "$duck" "$tools/out/duck-file.glb" "$tools/out/duck-auto.glb"
