#!/usr/bin/env bash
# bake-fabric: one fabric folder -> its bundle, verified (docs/pipelines.md).
#   pipelines/bake-fabric.sh FABRIC_DIR OUT [ID [BTF_DIR]]   (binaries from ${INLIGHT_BIN:-ROOT/build/bin})
# FABRIC_DIR holds fabric.toml (`bundle fabric-maps` options; relative paths are relative to
# FABRIC_DIR), material.toml (a brdf-sh-bake material), optionally brdf-sh-bake.toml (bake and
# --gles-* export options; default configs/brdf-sh-bake.toml), btf-pca.toml (default
# configs/btf-pca.toml) and a BTF: BTF_DIR, else FABRIC_DIR/btf/ (a UBO2003-layout folder), else
# a capture made here when FABRIC_DIR has weave.toml and capture.toml (pipelines/capture-btf.sh).
# A fabric with a BTF may leave out albedo-texture: the BTF's frontal image (light and view
# along the normal, radiance under irradiance pi = albedo for a matte surface) stands in.
# Each step writes OUT/work/fabrics/ID/<step>/ with its --report; the bundle goes to
# OUT/bundles/fabrics/ID/ (atomic, verified).
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 2 4 "FABRIC_DIR OUT [ID [BTF_DIR]]"
FABRIC=$(abs_dir "$1")
ID=${3:-$(basename "$FABRIC")}
check_id "$ID"
for f in fabric.toml material.toml; do
    if [ ! -f "$FABRIC/$f" ]; then
        echo "bake-fabric: $FABRIC/$f not found (a fabric folder needs fabric.toml and material.toml)" >&2
        exit 2
    fi
done
OUT=$(out_dir "$2")
BIN=$(tool_bin)
W="$OUT/work/fabrics/$ID"
say() { echo "[bake-fabric $ID] $*" >&2; }
BRDF_CONFIG="$ROOT/configs/brdf-sh-bake.toml"
[ -f "$FABRIC/brdf-sh-bake.toml" ] && BRDF_CONFIG="$FABRIC/brdf-sh-bake.toml"
PCA_CONFIG="$ROOT/configs/btf-pca.toml"
[ -f "$FABRIC/btf-pca.toml" ] && PCA_CONFIG="$FABRIC/btf-pca.toml"
mkdir -p "$W"

# 0. The BTF, if the fabric has one (given, in the folder, or captured now).
BTF=""
if [ $# -ge 4 ]; then
    BTF=$(cd "$4" && pwd)
elif [ -d "$FABRIC/btf" ]; then
    BTF="$FABRIC/btf"
elif [ -f "$FABRIC/weave.toml" ] && [ -f "$FABRIC/capture.toml" ]; then
    say "capture (weave.toml, capture.toml)"
    INLIGHT_BIN="$BIN" "$HERE/capture-btf.sh" "$FABRIC" "$W/capture"
    BTF="$W/capture/btf"
fi

# 1. Textures in the app's formats: albedo (sRGB PNG), normal map (linear PNG), thumbnail.
say "textures"
albedo=()
if [ -n "$BTF" ] && ! grep -q '^albedo-texture' "$FABRIC/fabric.toml"; then
    frontal=$(find "$BTF" -name 'tl000 pl000 tv000 pv000.*' | head -n 1)
    if [ -z "$frontal" ]; then
        echo "bake-fabric: $BTF: no frontal image 'tl000 pl000 tv000 pv000' for the albedo" >&2
        exit 1
    fi
    albedo=(--albedo-texture "$frontal")
fi
(cd "$FABRIC" && "$BIN/bundle" fabric-maps --config fabric.toml "${albedo[@]}" -o "$W/maps" -q \
    --report "$W/maps/report.json")

# 2. The specular lobe into an SH table over normals, and its GLES shaders (every variant the
#    --gles-* options of the bake config ask for: docs/gles.md).
say "brdf-sh-bake ($(basename "$BRDF_CONFIG")) with --export-gles"
rm -rf "$W/gles"
#    The shaders bind the bundle's own albedo and normal map, tiled at the fabric's tile size
#    (a_uv in metres on the fabric).
"$BIN/brdf-sh-bake" --config "$BRDF_CONFIG" --material "$FABRIC/material.toml" -o "$W/brdf/table" \
    --export-gles "$W/gles" --gles-albedo-texture "$W/maps/albedo.png" \
    --gles-normal-texture "$W/maps/normal.png" \
    --gles-tile-size-m "$(jq '.metrics.tile_size_m' "$W/maps/report.json")" \
    -q --report "$W/brdf/report.json"

files=(--file "albedo=$W/maps/albedo.png" --file "normal=$W/maps/normal.png"
    --file "thumbnail=$W/maps/thumbnail.png" --file "material=$FABRIC/material.toml"
    --file "brdf_sh_table=$W/brdf/table.bin@brdf/table.bin"
    --file "brdf_sh_table_json=$W/brdf/table.json@brdf/table.json"
    --file "brdf_sh_texture=$W/brdf/table_texture.exr@brdf/table_texture.exr"
    --file "shader_lookup=$W/brdf/table.glsl@shaders/brdf_lookup.glsl"
    --file "shader_index=$W/gles/index.json@shaders/index.json")
variants=0
textures=()
while read -r manifest; do
    base=${manifest%.json}
    files+=(--file "shader_manifest=$W/gles/$manifest@shaders/$manifest"
        --file "shader_vertex=$W/gles/$base.vert@shaders/$base.vert"
        --file "shader_fragment=$W/gles/$base.frag@shaders/$base.frag")
    data=$(jq -r '.files.brdf_data // empty' "$W/gles/$manifest")
    [ -n "$data" ] && files+=(--file "shader_data=$W/gles/$data@shaders/$data")
    # The textures are the material's, shared by its variants: listed once.
    while read -r tex; do
        [[ " ${textures[*]} " == *" $tex "* ]] && continue
        textures+=("$tex")
        files+=(--file "shader_texture=$W/gles/$tex@shaders/$tex")
    done < <(jq -r '.files.albedo_texture // empty, .files.normal_texture // empty' "$W/gles/$manifest")
    variants=$((variants + 1))
done < <(jq -r '.variants[].manifest' "$W/gles/index.json")
say "shaders: $variants GLES variants with their uniform layouts"

# 3. BTF components in streaming order (btf-pca, docs/btf.md): the manifest, V and the group
#    means first, then every component with its position in the stream.
btf_props=()
if [ -n "$BTF" ]; then
    say "btf-pca ($(basename "$PCA_CONFIG")) on $BTF"
    rm -rf "$W/btf"
    "$BIN/btf-pca" compress "$BTF" --config "$PCA_CONFIG" -o "$W/btf" -q --report "$W/btf-pca.json"
    files+=(--file "btf_manifest=$W/btf/btf-pca.json@btf/btf-pca.json"
        --file "btf_weights=$W/btf/weights.bin@btf/weights.bin")
    while read -r mean; do
        files+=(--file "btf_mean=$W/btf/$mean@btf/$mean")
    done < <(jq -r '.groups[].mean.file' "$W/btf/btf-pca.json")
    while read -r k comp; do
        files+=(--file "btf_component=$W/btf/$comp@btf/$comp#$k")
    done < <(jq -r '. as $m | .stream | to_entries[] | "\(.key) \($m.groups[.value[0]].components[.value[1]].file)"' \
        "$W/btf/btf-pca.json")
    # The BTF's GLES shaders (docs/btf-gles.md, "In the bundle"): btf-gles.json, the shaders and
    # the lighting matrices beside btf-pca.json, at the BRDF shaders' SH bands (at most 9) and the
    # capture's irradiance; no atlases: the app assembles them from the mean and component PNGs
    # the bundle streams anyway. Only a linear-fit, 8-bit PNG folder can be drawn so.
    btf_gles_bands=""
    if jq -e '(.color_space // "linear_srgb") == "linear_srgb" and .component_format == "png"' \
        "$W/btf/btf-pca.json" >/dev/null; then
        btf_gles_bands=$(jq '[.metrics.sh_bands, 9] | min' "$W/brdf/report.json")
        rm -rf "$W/btf-gles"
        "$BIN/btf-pca" export-gles "$W/btf" -o "$W/btf-gles" --atlases none --bands "$btf_gles_bands" -q \
            --report "$W/btf-gles-export.json"
        files+=(--file "btf_gles_manifest=$W/btf-gles/btf-gles.json@btf/btf-gles.json"
            --file "btf_gles_matrices=$W/btf-gles/lighting-matrices.bin@btf/lighting-matrices.bin")
        while read -r v; do
            files+=(--file "btf_gles_vertex=$W/btf-gles/$v.vert@btf/$v.vert"
                --file "btf_gles_fragment=$W/btf-gles/$v.frag@btf/$v.frag")
        done < <(jq -r '.variants[].name' "$W/btf-gles/btf-gles.json")
        say "BTF GLES shaders: $(jq -r '[.load[] | "\(.capability): \(.variant // "none")" +
            (if .requires then " (needs GL_MAX_FRAGMENT_UNIFORM_VECTORS >= \(.requires.max_fragment_uniform_vectors))"
             else "" end)] | join("; ")' "$W/btf-gles/btf-gles.json")"
    else
        say "no BTF GLES shaders: they draw only a linear fit with 8-bit PNG components (docs/btf-gles.md)"
    fi
    btf_props=(--property "btf_rmse_linear=$(jq '.metrics.error.rmse_linear' "$W/btf-pca.json")"
        --property "btf_delta_e2000_mean=$(jq '.metrics.error.delta_e2000_mean' "$W/btf-pca.json")"
        --property "btf_size_px=$(jq -c '[.metrics.btf.width, .metrics.btf.height]' "$W/btf-pca.json")"
        --property "btf_directions=$(jq -c '[.metrics.btf.lights, .metrics.btf.views]' "$W/btf-pca.json")"
        --property "btf_raw_bytes=$(jq '.metrics.bytes.raw_8bit' "$W/btf-pca.json")")
    [ -n "$btf_gles_bands" ] && btf_props+=(--property "btf_gles_bands=$btf_gles_bands")
    say "$(jq -r '.metrics | "btf-pca: \(.btf.views) views x \(.btf.lights) lights of \(.btf.width)x\(.btf.height) px -> \(.bytes.stored) bytes, RMSE \(.error.rmse_linear)"' "$W/btf-pca.json")"
else
    say "no BTF (no btf/ folder, no weave.toml + capture.toml): a BRDF-only fabric"
fi

# 4. The bundle, then an independent verification of what was written.
name=$(jq -r --arg id "$ID" '.metrics.name | if . == "" or . == null then $id else . end' "$W/maps/report.json")
say "pack"
"$BIN/bundle" pack --kind fabric --id "$ID" --name "$name" "${files[@]}" "${btf_props[@]}" \
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
