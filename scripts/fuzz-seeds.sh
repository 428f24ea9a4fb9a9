#!/usr/bin/env bash
# Seed corpora for the fuzz targets: inputs written from the built-in scenes (every format and
# variant the targets read), plus the small glTF/GLB files of ../shared/scenes when it exists
# (self-contained ones only: AFL++ moves each input away from its folder, so external buffers
# would be missing). Usage: scripts/fuzz-seeds.sh SEEDS_PROGRAM OUT_FOLDER [SCENES_FOLDER]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
program="$1"
out="$2"
scenes="${3:-${EXAO_SCENES_DIR:-$here/../shared/scenes}}"
rm -rf "$out"
"$program" "$out"
if [ -d "$scenes" ]; then
  # AFL++ works best on small seeds; 64 KB keeps every mutation cheap.
  find "$scenes" -type f \( -name '*.glb' -o -path '*glTF-Embedded*' -name '*.gltf' \) -size -64k -print0 |
    while IFS= read -r -d '' f; do
      cp --no-preserve=mode "$f" "$out/gltf/real-$(basename "$(dirname "$(dirname "$f")")")-$(basename "$f")"
    done
fi
for d in "$out"/*/; do echo "seeds: $(ls "$d" | wc -l) in $d"; done
