#!/usr/bin/env bash
# Regenerates lights/*.json, the light presets facetool ships, from Poly Haven's CC0 HDR maps.
# usage: scripts/make-lights.sh HDRI_DIR [FACETOOL]   (HDRI_DIR holds <name>_1k.hdr; the maps are
# not in the repository: polyhaven.com/hdris, 1k .hdr). Each map's SH light (`light from-envmap`,
# unclamped, unrotated) is written to lights/<name>.json; the file names its map, not its path.
set -euo pipefail
hdri_dir=${1:?usage: scripts/make-lights.sh HDRI_DIR [FACETOOL]}
root=$(cd "$(dirname "$0")/.." && pwd)
facetool=$(realpath "${2:-$root/build/bin/facetool}")
maps=(moonless_golf pedestrian_overpass quarry_01 royal_esplanade venice_sunset)
mkdir -p "$root/lights"
cd "$hdri_dir"
for name in "${maps[@]}"; do
  [ -f "${name}_1k.hdr" ] || { echo "make-lights: ${hdri_dir}/${name}_1k.hdr is missing (download it from polyhaven.com)" >&2; exit 1; }
  "$facetool" light from-envmap "${name}_1k.hdr" -o "$root/lights/$name.json" >/dev/null
done
echo "wrote ${#maps[@]} light files into $root/lights"
