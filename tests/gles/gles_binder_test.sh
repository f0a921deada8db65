#!/usr/bin/env bash
# An app binds an export from its manifest alone (docs/gles.md, "What the app binds"):
# tests/gles/binder (EGL + GLES + nlohmann-json, no inlight code) binds every variant render
# export-gles writes for patch_city (ES 1.00 and 3.00; SH in uniforms and in both lighting
# textures; the BRDF table as uniforms, RGBA32F and wrapped RGBA8 textures; with and without a
# light; the bilinear and the trilinear texture filter, whose texture file is the mip atlas), draws the manifest's patch with its camera, applies the manifest's 8-bit step and must
# match the project's harness image of the same draw within one code on every value; then the same
# for brdf-sh-bake's export (a fabric bundle's shaders) on a stated quad. A manifest missing a
# field the binder needs makes it fail, naming the field.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
SRC="${INLIGHT_SOURCE_DIR:?}"
BINDER="$TBIN/inlight_gles_binder"
HARNESS="$TBIN/inlight_gles_harness_image"

if have_package_file /usr/share/blender/datafiles/studiolights/world/city.exr blender-data &&
    have_package_file /usr/share/blender/scripts/addons/archimesh/images/fabric_diffuse.png blender-data; then
    # patch_city at 24 x 24 pixels (the patch fills the view); the material path made absolute.
    PX=24
    sed -e "s|\"../materials/|\"$SRC/configs/materials/|" -e "s/^width_px = .*/width_px = $PX/" \
        -e "s/^height_px = .*/height_px = $PX/" "$SRC/configs/scenes/patch_city.toml" > "$WORK/city.toml"
    # thetaphi:9x32: 864 texels at 3 bands, too many for ES 3.00 uniforms at 4 bands (RGBA32F
    # texture) and wider than ES 2.0's 64 (wrapped RGBA8); 64 samples per normal keep it fast
    # (the comparison is of two draws of the same table, not of the table's accuracy).
    GRID=thetaphi:9x32
    SAMPLES=64
    BANDS=4
    # Lighting files: 2 bands (fewer than any variant: the manifest's zero padding) without a
    # light, and the same with one light of flux 3 and 2 degrees radius.
    cat > "$WORK/sh2.json" <<'EOF'
{ "format": "inlight.sh_coefficients", "version": 1, "sh_bands": 2, "channels": ["r", "g", "b"],
  "coefficients": [[1.2, 1.0, 0.8], [0.1, 0.05, 0.02], [0.4, 0.35, 0.3], [-0.05, 0.0, 0.05]] }
EOF
    jq '. + {lights: [{direction: [0.0, 0.6, 0.8], flux: [3.0, 2.5, 2.0], angular_radius_deg: 2.0}]}' \
        "$WORK/sh2.json" > "$WORK/lit.json"
    # Each export: folder, lighting file, grid, bands, GL_MAX_TEXTURE_SIZE (0 = each version's
    # minimum), further options. gt: the trilinear filter, whose 768 x 512 atlas of the 512 x 512
    # texture (42x minified at 24 px) needs a device limit above ES 2.0's minimum of 64.
    EXPORTS=("g $WORK/sh2.json $GRID $BANDS 0" "gl $WORK/lit.json $GRID $BANDS 0 --gles-lighting $WORK/lit.json"
             "go $WORK/sh2.json octa:5 3 0 --gles-versions 300 --gles-modes consistent"
             "gt $WORK/sh2.json octa:5 3 2048 --gles-texture-filter trilinear")
    for x in "${EXPORTS[@]}"; do
        read -r dir lighting grid bands mts extra <<< "$x"
        # shellcheck disable=SC2086  # extra: further options, split on purpose
        expect_exit 0 "render export-gles of patch_city ($dir: $grid, $bands bands ${extra:-})" -- \
            "$R" export-gles "$WORK/city.toml" -o "$WORK/$dir" --grid "$grid" --bake-samples "$SAMPLES" \
            --gles-max-bands "$bands" --gles-max-texture-size "$mts" $extra
    done
    expect_exit 1 "the trilinear atlas above ES 2.0's minimum texture size is refused" -- \
        "$R" export-gles "$WORK/city.toml" -o "$WORK/gx" --grid octa:5 --bake-samples "$SAMPLES" \
        --gles-texture-filter trilinear
    expect_stderr "mip atlas is 768x512 texels" "the refusal names the atlas' size"
    expect_stderr "GL_MAX_TEXTURE_SIZE = 64" "and the limit"
    T="$WORK/gt/satin-es100-consistent-b3-highp-trilinear.json"
    expect_true "a trilinear manifest names the atlas file, its size, its 10 levels and the derivatives extension" -- jq -e \
        '(.files.albedo_texture == "satin.albedo.mip.rgba8") and (.texture_filter == "trilinear")
         and (.textures[0] | .width == 768 and .height == 512 and (.mip.levels | length) == 10
              and .mip.levels[1] == {level: 1, x: 512, y: 0, width: 256, height: 256})
         and (.gl_limits_needed.requires | map(startswith("GL_OES_standard_derivatives")) | any)' "$T"
    expect_true "the atlas file is 768 x 512 x 4 bytes" -- bash -c "test \$(stat -c %s '$WORK/gt/satin.albedo.mip.rgba8') -eq 1572864"
    expect_true "the albedo texture's file is written beside the manifests, width x height x 4 bytes" -- bash -c \
        "test \$(stat -c %s '$WORK/g/satin.albedo.rgba8') -eq \
         \$(jq '.textures[0] | .width * .height * 4' '$WORK/g/satin-es300-consistent-b3-highp.json')"
    expect_true "every uniform has a value or a source, every texture a file or a source" -- jq -e \
        '[.uniforms[] | has("value") or has("source")] + [.textures[] | (.file != null) or has("source")] | all' \
        "$WORK/gl/satin-es100-consistent-b4-l1-highp.json"
    expect_true "the layouts covered: uniform array, RGBA32F and wrapped RGBA8 tables; SH textures of both kinds" -- \
        bash -c "jq -r '.brdf_table.layout + \" \" + .lighting_layout + \" \" + (.brdf_table.wrapped | tostring)' \
                 '$WORK'/{g,gl,go}/satin-*-consistent-*.json | sort -u | tr '\n' ';' |
                 grep -qx 'rgba32f_texture uniform_array false;rgba8_texture rgba8_texture_16bit true;rgba8_texture uniform_array true;uniform_array uniform_array false;'"
    for x in "${EXPORTS[@]}"; do
        read -r dir lighting grid bands mts _ <<< "$x"
        for manifest in "$WORK/$dir"/satin-*.json; do
            v=$(basename "$manifest" .json)
            if ! "$HARNESS" "$WORK/city.toml" "$WORK/$dir" "$v" "$lighting" "$WORK/$dir-$v.ref.ppm" "$grid" "$SAMPLES" \
                "$bands" "$PX" "$mts" > "$WORK/harness.log" 2>&1; then
                fail "$v: harness image: $(cat "$WORK/harness.log")"
                continue
            fi
            expect_exit 0 "$v ($dir): the binder's 8-bit image within one code of the harness's" -- \
                "$BINDER" "$manifest" --lighting "$lighting" -o "$WORK/$dir-$v.ppm" --reference "$WORK/$dir-$v.ref.ppm"
            grep -h "worst" "$WORK/stdout" | sed 's/^/    /'
        done
    done
    expect_exit 0 "index.json's load choice for ES 3.0 binds as its manifest" -- \
        "$BINDER" "$WORK/gl/index.json" --lighting "$WORK/lit.json" -o "$WORK/load.ppm" \
        --reference "$WORK/gl-satin-es300-consistent-b4-l1-highp.ref.ppm"

    # It can fail: a manifest without u_albedo's value, without the albedo texture's file, without
    # the 8-bit step; a trilinear one whose level lies outside its atlas, or that requires an
    # extension the context lacks. Each: manifest @ jq edit @ what fails @ what the error names.
    M="$WORK/g/satin-es100-consistent-b3-highp.json"
    BROKEN=("$M@(.uniforms[] | select(.name == \"u_albedo\")) |= del(.value)@a uniform without value or source@uniform u_albedo has neither 'value' nor 'source'"
            "$M@(.textures[] | select(.uniform == \"u_albedo_texture\")) |= del(.file)@a texture without its file@texture u_albedo_texture has neither 'file' nor 'source'"
            "$M@del(.output.encoding_8bit)@a manifest without the 8-bit step@missing field 'output.encoding_8bit.steps'"
            "$T@.textures[0].mip.levels[9].x = 768@a mip level outside the atlas@mip level"
            "$T@.gl_limits_needed.requires += [\"GL_OES_no_such_extension (a test)\"]@a required extension the context lacks@lacks GL_OES_no_such_extension")
    for i in "${!BROKEN[@]}"; do
        IFS='@' read -r manifest edit what error <<< "${BROKEN[$i]}"
        jq "$edit" "$manifest" > "$(dirname "$manifest")/broken$i.json"
        expect_exit 1 "$what fails the binder" -- \
            "$BINDER" "$(dirname "$manifest")/broken$i.json" --lighting "$WORK/sh2.json" -o "$WORK/x.ppm"
        expect_stderr "$error" "the error names it"
    done
    # And a wrong binding is seen: L_10 (the z band) negated moves the image by more than a code.
    jq '.coefficients[2] |= map(-.)' "$WORK/sh2.json" > "$WORK/other.json"
    expect_exit 1 "the comparison sees a different lighting" -- \
        "$BINDER" "$M" --lighting "$WORK/other.json" -o "$WORK/x.ppm" --reference "$WORK/g-satin-es100-consistent-b3-highp.ref.ppm"
fi

# A bundle's shaders: brdf-sh-bake --export-gles, as pipelines/bake-fabric.sh places them in a
# fabric bundle. Their manifests have no scene, so the binder draws the quad it states
# (--quad: binder.cpp quad_vertices()) and the harness draws the same quad with gles::draw.
B="$BIN/brdf-sh-bake"
SATIN="$SRC/configs/materials/satin-ggx.toml"
jq -n '{format: "inlight.sh_coefficients", version: 1, sh_bands: 2, channels: ["r", "g", "b"],
        coefficients: [[1.2, 1.0, 0.8], [0.1, 0.05, 0.02], [0.4, 0.35, 0.3], [-0.05, 0.0, 0.05]]}' > "$WORK/sh2b.json"
expect_exit 0 "brdf-sh-bake --export-gles (a bundle's shaders)" -- "$B" --material "$SATIN" --grid thetaphi:9x32 \
    --sh-bands 4 --samples 64 -o "$WORK/b/satin" --export-gles "$WORK/b/gles" --gles-max-bands 4 -q
for manifest in "$WORK"/b/gles/satin-*.json; do
    v=$(basename "$manifest" .json)
    if ! "$HARNESS" --table "$WORK/b/satin.bin" "$SATIN" "$WORK/b/gles" "$v" "$WORK/sh2b.json" "$WORK/b/$v.ref.ppm" 24 \
        > "$WORK/harness.log" 2>&1; then
        fail "$v: harness image: $(cat "$WORK/harness.log")"
        continue
    fi
    expect_exit 0 "$v (brdf-sh-bake): the binder's 8-bit image within one code of the harness's" -- \
        "$BINDER" "$manifest" --lighting "$WORK/sh2b.json" --quad 24 -o "$WORK/b/$v.ppm" --reference "$WORK/b/$v.ref.ppm"
    grep -h "worst" "$WORK/stdout" | sed 's/^/    /'
done
expect_exit 1 "without a scene or --quad the binder has nothing to draw" -- \
    "$BINDER" "$WORK/b/gles/satin-es300-consistent-b3-highp.json" --lighting "$WORK/sh2b.json" -o "$WORK/x.ppm"
expect_stderr "missing field 'scene'" "the error names the scene"
finish
