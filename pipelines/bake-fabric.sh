#!/usr/bin/env bash
# bake-fabric: one fabric folder -> its bundle, verified (docs/pipelines.md).
#   pipelines/bake-fabric.sh FABRIC_DIR OUT [ID]        (binaries from ${INLIGHT_BIN:-build/bin})
# FABRIC_DIR holds fabric.toml (`bundle fabric-maps` options; relative paths are relative to
# FABRIC_DIR), material.toml (a brdf-sh-bake material), optionally brdf-sh-bake.toml (bake
# options; default configs/brdf-sh-bake.toml) and btf/ (a UBO2003-layout BTF folder).
# Each step writes OUT/work/fabrics/ID/<step>/ with its --report; the bundle goes to
# OUT/bundles/fabrics/ID/ (atomic, verified).
set -euo pipefail
if [ $# -lt 2 ]; then
    echo "usage: bake-fabric.sh FABRIC_DIR OUT [ID]" >&2
    exit 2
fi
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
FABRIC=$(cd "$1" && pwd)
mkdir -p "$2"
OUT=$(cd "$2" && pwd)
ID=${3:-$(basename "$FABRIC")}
BIN=$(cd "${INLIGHT_BIN:-$ROOT/build/bin}" && pwd)
W="$OUT/work/fabrics/$ID"
say() { echo "[bake-fabric $ID] $*" >&2; }
for f in fabric.toml material.toml; do
    if [ ! -f "$FABRIC/$f" ]; then
        echo "bake-fabric: $FABRIC/$f not found (a fabric folder needs fabric.toml and material.toml)" >&2
        exit 2
    fi
done
BRDF_CONFIG="$ROOT/configs/brdf-sh-bake.toml"
[ -f "$FABRIC/brdf-sh-bake.toml" ] && BRDF_CONFIG="$FABRIC/brdf-sh-bake.toml"
mkdir -p "$W"

# 1. Textures in the app's formats: albedo (sRGB PNG), normal map (linear PNG), thumbnail.
say "textures"
(cd "$FABRIC" && "$BIN/bundle" fabric-maps --config fabric.toml -o "$W/maps" -q \
    --report "$W/maps/report.json")

# 2. The specular lobe into an SH table over normals.
say "brdf-sh-bake ($(basename "$BRDF_CONFIG"))"
"$BIN/brdf-sh-bake" --config "$BRDF_CONFIG" --material "$FABRIC/material.toml" -o "$W/brdf/table" \
    -q --report "$W/brdf/report.json"

files=(--file "albedo=$W/maps/albedo.png" --file "normal=$W/maps/normal.png"
    --file "thumbnail=$W/maps/thumbnail.png" --file "material=$FABRIC/material.toml"
    --file "brdf_sh_table=$W/brdf/table.bin@brdf/table.bin"
    --file "brdf_sh_table_json=$W/brdf/table.json@brdf/table.json"
    --file "brdf_sh_texture=$W/brdf/table_texture.exr@brdf/table_texture.exr")

# 3. BTF components in streaming order (btf-pca, issue 10).
if [ -d "$FABRIC/btf" ]; then
    if [ -x "$BIN/btf-pca" ]; then
        say "btf-pca is built, but this pipeline does not call it yet (issue 11, phase 2): BTF skipped"
    else
        say "btf-pca is not built (issue 10): BTF components skipped"
    fi
else
    say "no btf/ folder: a BRDF-only fabric"
fi

# 4. Shaders with their uniform layout (render --export-gles, issue 8). Until the exporter lands,
#    the bundle carries brdf-sh-bake's GLSL ES lookup of the table.
if "$BIN/render" --help 2>/dev/null | grep -q -- '--export-gles'; then
    say "render --export-gles exists, but this pipeline does not call it yet (issue 11, phase 2)"
else
    say "render --export-gles is not built (issue 8): bundling the GLSL table lookup only"
fi
files+=(--file "shader_lookup=$W/brdf/table.glsl@shaders/brdf_lookup.glsl")

# 5. The bundle, then an independent verification of what was written.
name=$(jq -r --arg id "$ID" '.metrics.name | if . == "" or . == null then $id else . end' "$W/maps/report.json")
say "pack"
"$BIN/bundle" pack --kind fabric --id "$ID" --name "$name" "${files[@]}" \
    --property "tile_size_m=$(jq '.metrics.tile_size_m' "$W/maps/report.json")" \
    --property "normal_source=$(jq -r '.metrics.normal_source' "$W/maps/report.json")" \
    --property "sh_bands=$(jq '.metrics.sh_bands' "$W/brdf/report.json")" \
    --property "brdf_grid=$(jq -r '.metrics.grid' "$W/brdf/report.json")" \
    --property "brdf_model=$(jq -r '.metrics.model' "$W/brdf/report.json")" \
    --property "brdf_samples_per_normal=$(jq '.metrics.samples_per_normal' "$W/brdf/report.json")" \
    --property "brdf_max_rel_error=$(jq '.metrics.total_radiance_max_rel' "$W/brdf/report.json")" \
    -o "$OUT/bundles" -q --report "$W/pack.json"
"$BIN/bundle" verify "$OUT/bundles/fabrics/$ID" -q --report "$W/verify.json"
say "$(jq -r '.metrics | "bundle \(.bundle): \(.file_count) files, \(.total_bytes) bytes"' "$W/pack.json")"
