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
        '(.files.albedo_texture == "satin.albedo.mip.png") and (.texture_filter == "trilinear")
         and (.textures[0] | .width == 768 and .height == 512 and (.mip.levels | length) == 10
              and .mip.levels[1] == {level: 1, x: 512, y: 0, width: 256, height: 256})
         and (.gl_limits_needed.requires | map(startswith("GL_OES_standard_derivatives")) | any)' "$T"
    expect_true "the atlas file is an 8-bit RGBA PNG of 768 x 512" -- bash -c \
        "file -b '$WORK/gt/satin.albedo.mip.png' | grep -qF 'PNG image data, 768 x 512, 8-bit/color RGBA'"
    expect_true "the albedo texture's file is written beside the manifests, an 8-bit RGBA PNG of width x height" -- bash -c \
        "file -b '$WORK/g/satin.albedo.png' | grep -qF \"PNG image data, \$(jq -r '.textures[0] | \"\\(.width) x \\(.height)\"' \
         '$WORK/g/satin-es300-consistent-b3-highp.json'), 8-bit/color RGBA\""
    expect_true "every uniform has a value or a source, every texture a file or a source" -- jq -e \
        '[.uniforms[] | has("value") or has("source")] + [.textures[] | (.file != null) or has("source")] | all' \
        "$WORK/gl/satin-es100-consistent-b4-l1-highp.json"
    expect_true "the layouts covered: uniform array, RGBA32F and wrapped RGBA8 tables; SH textures of both kinds" -- \
        bash -c "jq -r '.brdf_table.layout + \" \" + .lighting_layout + \" \" + (.brdf_table.wrapped | tostring)' \
                 '$WORK'/{g,gl,go}/satin-*-consistent-*.json | sort -u | tr '\n' ';' |
                 grep -qx 'rgba32f_texture uniform_array false;rgba8_texture rgba8_texture_16bit true;rgba8_texture uniform_array true;uniform_array uniform_array false;'"
    for x in "${EXPORTS[@]}"; do
        read -r dir lighting grid bands mts _ <<< "$x"
        # The harness draws every variant of the export in one process ('%': the variant's name).
        variants=$(for m in "$WORK/$dir"/satin-*.json; do basename "$m" .json; done | paste -sd,)
        if ! "$HARNESS" "$WORK/city.toml" "$WORK/$dir" "$variants" "$lighting" "$WORK/$dir-%.ref.ppm" "$grid" "$SAMPLES" \
            "$bands" "$PX" "$mts" > "$WORK/harness.log" 2>&1; then
            fail "$dir: harness images: $(cat "$WORK/harness.log")"
            continue
        fi
        for manifest in "$WORK/$dir"/satin-*.json; do
            v=$(basename "$manifest" .json)
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
# A built fabric bundle's shaders (pipelines/bake-fabric.sh: brdf-sh-bake --export-gles with
# the bundle's own albedo and normal map at the fabric's tile size), bound from the bundle folder
# as the app downloads it: every variant of its index, textures decoded from the bundle's PNGs.
VELVET="$SRC/samples/catalog/fabrics/archimesh-velvet"
if have_package_file /usr/share/blender/scripts/addons/archimesh/images/fabric_diffuse.png blender-data; then
    expect_exit 0 "bake-fabric archimesh-velvet (a bundle whose shaders bind its textures)" -- \
        env INLIGHT_BIN="$BIN" "$SRC/pipelines/bake-fabric.sh" "$VELVET" "$WORK/bf"
    BUNDLE="$WORK/bf/bundles/fabrics/archimesh-velvet"
    expect_true "the bundle's shaders bind its albedo and normal map (role shader_texture)" -- jq -e \
        '[.files[] | select(.role == "shader_texture") | .path] == ["shaders/table.albedo.mip.png", "shaders/table.normal.mip.png"]' \
        "$BUNDLE/manifest.json"
    TILE=$(jq '.properties.tile_size_m' "$BUNDLE/manifest.json")
    while read -r manifest; do
        v=${manifest%.json}
        if ! "$HARNESS" --table "$BUNDLE/brdf/table.bin" "$BUNDLE/material.toml" "$BUNDLE/shaders" "$v" \
            "$WORK/sh2b.json" "$WORK/bf/$v.ref.ppm" 48 "$BUNDLE/albedo.png" "$BUNDLE/normal.png" "$TILE" \
            > "$WORK/harness.log" 2>&1; then
            fail "$v: harness image: $(cat "$WORK/harness.log")"
            continue
        fi
        expect_exit 0 "$v (the bundle's): the binder's 8-bit image within one code of the harness's" -- \
            "$BINDER" "$BUNDLE/shaders/$manifest" --lighting "$WORK/sh2b.json" --quad 48 -o "$WORK/bf/$v.ppm" \
            --reference "$WORK/bf/$v.ref.ppm"
        grep -h "worst" "$WORK/stdout" | sed 's/^/    /'
    done < <(jq -r '.variants[].manifest' "$BUNDLE/shaders/index.json")
    # What validation grades is what ships: validate-pair's scene (pipelines/validate-pair.sh: the
    # bundle's material, albedo [1, 1, 1] times albedo.png, normal.png, an orthographic camera
    # along -z), exported by render export-gles with the bundle's grid and samples per normal, as
    # render compare's GLES column does, gives the bundle's shader files byte for byte (sources,
    # BRDF data, textures; the material named as the bundle's, "table", so the names agree).
    uv=$(jq '0.1 / .properties.tile_size_m' "$BUNDLE/manifest.json")
    printf '%s\n' "[environment]" "path = \"/usr/share/blender/datafiles/studiolights/world/city.exr\"" \
        "[camera]" "projection = \"orthographic\"" "ortho_height = 1.0" "[material.table]" \
        "file = \"$BUNDLE/material.toml\"" "albedo = [1, 1, 1]" "albedo_texture = \"$BUNDLE/albedo.png\"" \
        "normal_texture = \"$BUNDLE/normal.png\"" "uv_scale = [$uv, $uv]" "[[object]]" "name = \"fabric\"" \
        "shape = \"patch\"" "material = \"table\"" "size = [1, 1]" > "$WORK/bf/scene.toml"
    expect_exit 0 "render export-gles of validate-pair's scene with the bundle's table options" -- \
        "$R" export-gles "$WORK/bf/scene.toml" -o "$WORK/bf/validated" -q \
        --grid "$(jq -r '.properties.brdf_grid' "$BUNDLE/manifest.json")" \
        --bake-samples "$(jq '.properties.brdf_samples_per_normal' "$BUNDLE/manifest.json")" \
        --gles-versions "$(jq -r '[.variants[].variant.glsl_version | rtrimstr(" es")] | unique | join(",")' \
            "$BUNDLE/shaders/index.json")" --gles-texture-filter "$(jq -r '.texture_filter' "$BUNDLE/shaders/$v.json")" \
        --gles-max-texture-size "$(jq -r '.gl_limits_needed.limits_given.max_texture_size' "$BUNDLE/shaders/$v.json")"
    differ=0 compared=0
    while read -r f; do
        compared=$((compared + 1))
        cmp -s "$BUNDLE/shaders/$f" "$WORK/bf/validated/$f" || { echo "    differs: $f"; differ=1; }
    done < <(jq -r '.files[] | select(.role == "shader_vertex" or .role == "shader_fragment" or
                    .role == "shader_data" or .role == "shader_texture") | .path | ltrimstr("shaders/")' \
                "$BUNDLE/manifest.json")
    expect_true "the validated shaders, their data and textures are the bundle's, byte for byte ($compared files)" -- \
        test "$differ" -eq 0 -a "$compared" -ge 5
    # The texture is bound, not ignored: the normal map's bytes in place of the albedo's move the
    # image by more than a code.
    cp -r "$BUNDLE/shaders" "$WORK/bf/swapped"
    cp "$BUNDLE/shaders/table.normal.mip.png" "$WORK/bf/swapped/table.albedo.mip.png"
    expect_exit 1 "another albedo texture is seen by the comparison" -- \
        "$BINDER" "$WORK/bf/swapped/$v.json" --lighting "$WORK/sh2b.json" --quad 48 -o "$WORK/x.ppm" \
        --reference "$WORK/bf/$v.ref.ppm"
else
    skip "blender-data's fabric texture is absent: no fabric bundle to bind"
fi

expect_exit 1 "without a scene or --quad the binder has nothing to draw" -- \
    "$BINDER" "$WORK/b/gles/satin-es300-consistent-b3-highp.json" --lighting "$WORK/sh2b.json" -o "$WORK/x.ppm"
expect_stderr "missing field 'scene'" "the error names the scene"
finish
