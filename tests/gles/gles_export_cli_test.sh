#!/usr/bin/env bash
# GLES export through brdf-sh-bake --export-gles and render export-gles: usage errors before any work, every variant's
# files and index, sources that pass glslangValidator, manifests naming the scene's textures.
# shellcheck source=tests/cli/lib.sh
# shellcheck disable=SC2016  # jq programs name jq variables ($f, $r) in single quotes
source "$(dirname "$0")/../cli/lib.sh"
B="$BIN/brdf-sh-bake"
R="$BIN/render"
SRC="${INLIGHT_SOURCE_DIR:?}"
SATIN="$SRC/configs/materials/satin-ggx.toml"
BAKE=(--material "$SATIN" --grid octa:5 --sh-bands 3 --samples 256)

expect_exit 2 "an unknown GLSL version is a usage error" -- \
    "$B" "${BAKE[@]}" -o "$WORK/a" --export-gles "$WORK/g" --gles-versions 100,200
expect_exit 2 "more lighting bands than the table has is a usage error" -- \
    "$B" "${BAKE[@]}" -o "$WORK/a" --export-gles "$WORK/g" --gles-max-bands 4
expect_exit 2 "an unknown texture filter is a usage error" -- \
    "$B" "${BAKE[@]}" -o "$WORK/a" --export-gles "$WORK/g" --gles-texture-filter nearest
expect_stderr "--gles-texture-filter" "the error names the option"
expect_true "nothing written by a usage error" -- test ! -e "$WORK/g"

expect_exit 0 "brdf-sh-bake --export-gles" -- \
    "$B" "${BAKE[@]}" -o "$WORK/satin" --export-gles "$WORK/g" --report "$WORK/b.json"
# 2 versions x 2 modes at 3 bands, highp only: mediump is exported only on request.
expect_true "index lists 4 highp variants" -- \
    jq -e '[.variants[].variant.precision] == ["highp", "highp", "highp", "highp"]' "$WORK/g/index.json"
expect_true "report lists the export's files" -- \
    jq -e '[.outputs[] | select(.kind == "gles_export")] | length == 17' "$WORK/b.json"
expect_true "index names the variant to load per capability, none without highp" -- jq -e \
    '[.load.satin[].variant] == ["satin-es300-consistent-b3-highp", "satin-es100-consistent-b3-highp", null]' \
    "$WORK/g/index.json"
# Textures for the shaders (a fabric bundle's albedo.png and normal.png): 8-bit images only, read
# byte for byte, with the tile size making a_uv metres. Bad ones are usage errors before the bake.
"$TBIN/inlight_make_test_image" "$WORK/albedo.png" 5 3 0.5
"$TBIN/inlight_make_test_image" "$WORK/albedo.exr" 5 3 0.5
expect_exit 2 "a float albedo texture is a usage error (the shaders bind 8-bit texels)" -- \
    "$B" "${BAKE[@]}" -o "$WORK/t" --export-gles "$WORK/gt" --gles-albedo-texture "$WORK/albedo.exr"
expect_stderr "--gles-albedo-texture: $WORK/albedo.exr has 32-bit float samples" "the error names the option, file and depth"
expect_exit 2 "a missing normal map is a usage error" -- \
    "$B" "${BAKE[@]}" -o "$WORK/t" --export-gles "$WORK/gt" --gles-normal-texture "$WORK/none.png"
expect_exit 2 "a NaN tile size is a usage error" -- \
    "$B" "${BAKE[@]}" -o "$WORK/t" --export-gles "$WORK/gt" --gles-tile-size-m nan
expect_exit 2 "textures without --export-gles are a usage error" -- \
    "$B" "${BAKE[@]}" -o "$WORK/t" --gles-albedo-texture "$WORK/albedo.png"
printf '\x89PNG\r\n\x1a\nnot really a png' > "$WORK/garbage.png"
expect_exit 1 "a garbage PNG normal map is a runtime error before the bake" -- \
    "$B" "${BAKE[@]}" -o "$WORK/t" --export-gles "$WORK/gt" --gles-normal-texture "$WORK/garbage.png"
expect_stderr "garbage.png" "the error names the file"
expect_true "nothing written by those errors" -- test ! -e "$WORK/gt" -a ! -e "$WORK/t.bin"
expect_exit 0 "brdf-sh-bake with the bundle's textures" -- "$B" "${BAKE[@]}" -o "$WORK/t" --export-gles "$WORK/gt" \
    --gles-albedo-texture "$WORK/albedo.png" --gles-normal-texture "$WORK/albedo.png" --gles-tile-size-m 0.05 \
    --gles-versions 100
expect_true "its manifests bind both textures from their files, a_uv in metres, u_uv_scale = 1 / tile, the texture as the albedo" -- jq -e \
    '([.textures[] | select(.uniform != "u_brdf_texture") | [.uniform, .file, .width, .height]] ==
      [["u_albedo_texture", "t.albedo.png", 5, 3], ["u_normal_texture", "t.normal.png", 5, 3]]) and
     ((.attributes[] | select(.name == "a_uv") | .units) == "m") and
     ((.uniforms[] | select(.name == "u_uv_scale") | .value) == [20, 20]) and
     ((.uniforms[] | select(.name == "u_albedo") | .value) == [1, 1, 1])' \
    "$WORK/gt/t-es100-consistent-b3-highp.json"
expect_true "the texture's PNG holds the input's codes (8-bit RGBA, code 128 = 0.5)" -- bash -c \
    "file -b '$WORK/gt/t.albedo.png' | grep -q '5 x 3, 8-bit/color RGBA'"
expect_exit 0 "mediump on request" -- "$B" "${BAKE[@]}" -o "$WORK/satin_m" --export-gles "$WORK/gm" \
    --gles-precisions highp,mediump --gles-modes consistent
expect_true "the mediump variant is named for ES 2.0 without highp, not validated" -- jq -e \
    '.load.satin_m[2].variant == "satin_m-es100-consistent-b3-mediump" and .load.satin_m[2].validated == false' \
    "$WORK/gm/index.json"
for f in "$WORK"/g/*.vert "$WORK"/g/*.frag; do
    glslangValidator "$f" > "$WORK/glslang.log" 2>&1 || fail "$f: $(cat "$WORK/glslang.log")"
done
pass "every exported source passes glslangValidator"
expect_true "ES 1.00 table is RGBA8 within 16 uniform vectors" -- jq -e \
    '.brdf_table.layout == "rgba8_texture" and .gl_limits_needed.max_fragment_uniform_vectors == 16' \
    "$WORK/g/satin-es100-consistent-b3-highp.json"
expect_true "RGBA8 data is width x height x 4 bytes" -- bash -c "test \$(stat -c %s '$WORK/g/satin-es100-consistent-b3-highp.brdf.bin') -eq \
    \$(jq '.textures[0].width * .textures[0].height * 4' '$WORK/g/satin-es100-consistent-b3-highp.json')"

# Dominant lights: a lighting file from envmap-project --max-error (a sky of 1 with a
# one-pixel sun of 30,000), exported into the consistent variants and compared in render.
EP="$BIN/envmap-project"
"$TBIN/inlight_make_test_image" "$WORK/sun.exr" 256 128 1 40 40 30000
expect_exit 0 "envmap-project extracts the sun" -- "$EP" "$WORK/sun.exr" -o "$WORK/sun_sh.json" --max-error 0.01 -q
expect_exit 1 "a missing lighting file names the option's file" -- \
    "$B" "${BAKE[@]}" -o "$WORK/l" --export-gles "$WORK/gl" --gles-lighting "$WORK/none.json"
expect_stderr "none.json" "the error names the lighting file"
expect_true "nothing written by a bad lighting file" -- test ! -e "$WORK/gl"
expect_exit 0 "brdf-sh-bake --gles-lighting" -- "$B" "${BAKE[@]}" -o "$WORK/lit" --export-gles "$WORK/gl" \
    --gles-lighting "$WORK/sun_sh.json" --gles-precisions highp --report "$WORK/bl.json"
expect_true "consistent variants shade the light, seed variants none" -- jq -e \
    '[.variants[].name] == ["lit-es100-consistent-b3-l1-highp", "lit-es100-seed-b3-highp",
                           "lit-es300-consistent-b3-l1-highp", "lit-es300-seed-b3-highp"]' "$WORK/gl/index.json"
# 9 + 1 + 2 + 6 = 18 vectors all in uniforms: the table's scale and offset (6) move into its
# texture, the cheapest arrangement that fits (the lighting's texture would cost 4 fetches per
# coefficient, the scale/offset texels 2).
expect_true "ES 1.00 with a light fits the ES 2.0 minimum through the table texture's scale/offset" -- jq -e \
    '.lighting_layout == "uniform_array" and .gl_limits_needed.max_fragment_uniform_vectors == 12
     and .brdf_table.scale_offset.scale_texel == 75' \
    "$WORK/gl/lit-es100-consistent-b3-l1-highp.json"
expect_true "the manifest binds the file's light (direction, sin alpha, E_perp)" -- jq -e --slurpfile f "$WORK/sun_sh.json" \
    '(.uniforms[] | select(.name == "u_light_direction") | .value | length == 4) and
     (.uniforms[] | select(.name == "u_light_irradiance") | .value[0] > 0.99 * $f[0].lights[0].flux[0]) and
     .lights.lobe.model == "ggx"' "$WORK/gl/lit-es300-consistent-b3-l1-highp.json"
expect_true "the lighting file is a recorded input" -- \
    jq -e '[.inputs[].path | select(endswith("sun_sh.json"))] | length == 1' "$WORK/bl.json"
expect_exit 0 "ES 1.00 above 3 bands is exported (lighting texture)" -- "$B" --material "$SATIN" --grid octa:5 \
    --sh-bands 5 --samples 256 -o "$WORK/b5" --export-gles "$WORK/gl5" --gles-versions 100 --gles-max-bands 5 \
    --gles-modes consistent --gles-precisions highp
expect_true "ES 1.00 at 4 and 5 bands" -- jq -e '[.variants[].name] == ["b5-es100-consistent-b3-highp",
    "b5-es100-consistent-b4-highp", "b5-es100-consistent-b5-highp"]' "$WORK/gl5/index.json"
# Above 5 bands the table's scale and offset (2 x 9 vectors at 6 bands) move into its texture too.
expect_exit 0 "ES 1.00 at 6 bands fits the ES 2.0 minimum" -- "$B" --material "$SATIN" --grid octa:5 \
    --sh-bands 6 --samples 256 -o "$WORK/b6" --export-gles "$WORK/gl6" --gles-versions 100 --gles-max-bands 6 \
    --gles-modes consistent --gles-precisions highp
expect_true "its lighting and the table's scale/offset are in textures: 1 uniform vector" -- jq -e \
    '.lighting_layout == "rgba8_texture_16bit" and .gl_limits_needed.max_fragment_uniform_vectors == 1
     and .brdf_table.scale_offset.scale_texel == 225 and (.brdf_table.scale_offset.scale | length) == 36
     and ([.uniforms[].name] | index("u_brdf_scale") == null)' "$WORK/gl6/b6-es100-consistent-b6-highp.json"
# More than 64 x 64 texels (thetaphi:17x64 at 4 bands: 256 x 17 = 4352): refused at the ES 2.0
# minimum with the reason, laid out within the device's GL_MAX_TEXTURE_SIZE when it is given.
BIG=(--material "$SATIN" --grid thetaphi:17x64 --sh-bands 4 --samples 16 --gles-max-bands 4
     --gles-modes consistent --gles-precisions highp)
expect_exit 1 "a table above 64 x 64 texels is refused at the ES 2.0 minimum" -- \
    "$B" "${BIG[@]}" -o "$WORK/big" --export-gles "$WORK/glb" --gles-versions 100
expect_stderr "needs 4352 texels" "the refusal names the texels needed"
expect_stderr "= 64x64 holds" "the refusal names the limit"
expect_true "the refusal comes before the bake" -- bash -c "! grep -q 'bake done' '$WORK/stderr'"
expect_true "nothing exported by the refusal" -- test ! -e "$WORK/glb/index.json"
expect_exit 2 "a GL_MAX_TEXTURE_SIZE below the ES 3.0 minimum for ES 3.00 variants is a usage error" -- \
    "$B" "${BIG[@]}" -o "$WORK/big" --export-gles "$WORK/glb" --gles-max-texture-size 1024
expect_exit 0 "the device's GL_MAX_TEXTURE_SIZE 2048 lays it out" -- \
    "$B" "${BIG[@]}" -o "$WORK/big" --export-gles "$WORK/glb" --gles-max-texture-size 2048
expect_true "ES 1.00 and 3.00 keep the natural 256 x 17 rows, recorded with the limit given" -- jq -e -s \
    'map((.textures[] | select(.uniform == "u_brdf_texture") | .width == 256 and .height == 17)
         and .gl_limits_needed.limits_given.max_texture_size == 2048) | length == 2 and all' \
    "$WORK/glb/big-es100-consistent-b4-highp.json" "$WORK/glb/big-es300-consistent-b4-highp.json"
expect_exit 0 "satin on thetaphi:9x32 (96 texels wide) exports ES 1.00" -- "$B" --material "$SATIN" \
    --grid thetaphi:9x32 --sh-bands 3 --samples 256 -o "$WORK/wide" --export-gles "$WORK/glw" --gles-versions 100
expect_true "its table wraps into 64 x 14 texels" -- jq -e \
    '.textures[] | select(.uniform == "u_brdf_texture") | .width == 64 and .height == 14' \
    "$WORK/glw/wide-es100-consistent-b3-highp.json"
for f in "$WORK"/gl/*.frag "$WORK"/gl5/*.frag "$WORK"/gl6/*.frag "$WORK"/glw/*.frag "$WORK"/glb/*.frag; do
    glslangValidator "$f" > "$WORK/glslang.log" 2>&1 || fail "$f: $(cat "$WORK/glslang.log")"
done
pass "every source with lights passes glslangValidator"
cat > "$WORK/sun_scene.toml" <<'TOML'
[environment]
path = "sun.exr"
# Charlie sheen: the lobe with the shader's own pow and exp (the bake above is GGX).
[camera]
width_px = 16
height_px = 16
ortho_height = 0.9
[material.velvet]
specular = "charlie"
alpha = 0.4
sheen_color = [0.9, 0.7, 0.6]
albedo = [0.4, 0.3, 0.3]
[[object]]
shape = "patch"
material = "velvet"
TOML
expect_exit 0 "render compare --rt-lighting: the GLES column with the file's light" -- "$R" compare "$WORK/sun_scene.toml" \
    -o "$WORK/s.exr" --spp 16 --seed 3 --rt-max-bands 3 --rt-bake-samples 256 --rt-supersample 1 \
    --rt-lighting "$WORK/sun_sh.json" --report "$WORK/s.json"
expect_true "ES 1.00 and 3.00 variants with the light match the CPU model on >= 99.9% of pixels" -- jq -e \
    '[.metrics.realtime.gles.variants[] | select(.lights == 1) | .["cpu_model_fraction_within_1e-3"] >= 0.999]
     | length == 2 and all' "$WORK/s.json"
# Each variant is held to the CPU model of its own data (ES 1.00 reads the table quantised to 16
# bits, which moves its error against the truth by ~1e-3 of itself); 1e-3: the per-pixel agreement.
expect_true "GLES with the light equals its CPU model's lit error against the truth" -- jq -e \
    '[.metrics.realtime.gles.variants[] | select(.lights == 1) |
     . as $v | ($v.mean_rel - $v.cpu_model_vs_truth.mean_rel) | fabs < 1e-3 * $v.mean_rel] | length == 2 and all' "$WORK/s.json"
# The same model over the same pixels: only the order of a sum may differ (1e-9 of the value).
expect_true "the float ES 3.00 variant's CPU model is the lit CPU model of the report" -- jq -e \
    '.metrics.realtime as $r | [$r.gles.variants[] | select(.lights == 1 and .glsl_version == "300") |
     (.cpu_model_vs_truth.mean_rel - $r.lighting_file.with_lights.mean_rel) | fabs < 1e-9 * $r.lighting_file.with_lights.mean_rel] | length == 1 and all' "$WORK/s.json"
expect_true "three-way PNG with the light written" -- test -s "$WORK/s_compare3_es300-consistent-b3-l1-highp-file.png"
# Every option is checked before any work: 8 lights need 1 + 2 x 8 = 17 fragment uniform vectors
# in ES 1.00, above the ES 2.0 minimum of 16, so render refuses them before it renders or bakes
# (as brdf-sh-bake does before its bake).
jq '.lights = [limit(8; repeat(.lights[0]))]' "$WORK/sun_sh.json" > "$WORK/sun8.json"
expect_exit 1 "render refuses an ES 1.00 variant with 8 lights" -- "$R" export-gles "$WORK/sun_scene.toml" \
    -o "$WORK/gf" --gles-lighting "$WORK/sun8.json" --gles-versions 100 \
    --gles-modes consistent --gles-precisions highp --report "$WORK/f.json"
expect_stderr "^render: error: GLES export velvet-es100-consistent-b3-l8-highp: needs 17 fragment uniform vectors" \
    "the refusal names the variant and the vectors needed"
expect_stderr "GL_MAX_FRAGMENT_UNIFORM_VECTORS is 16" "the refusal names the limit"
expect_true "the refusal comes before the bakes" -- \
    jq -e '.exit_code == 1 and (.stage_time_s | keys == ["load scene"])' "$WORK/f.json"
expect_true "nothing written by the refusal" -- \
    test ! -e "$WORK/gf"

# render: the scene's materials, with the albedo texture's size in the manifest.
if [ -e /usr/share/blender/datafiles/studiolights/world/city.exr ]; then
    expect_exit 0 "render export-gles" -- "$R" export-gles "$SRC/configs/scenes/patch_city.toml" \
        -o "$WORK/rg" --bake-samples 256 --gles-precisions highp --gles-modes consistent --report "$WORK/r.json"
    expect_true "render exports 2 variants of satin" -- \
        jq -e '[.variants[].name] == ["satin-es100-consistent-b3-highp", "satin-es300-consistent-b3-highp"]' \
        "$WORK/rg/index.json"
    expect_true "the albedo texture and its size are in the manifest" -- jq -e \
        '.textures[] | select(.uniform == "u_albedo_texture") | .width == 512 and .color_space == "srgb"' \
        "$WORK/rg/satin-es300-consistent-b3-highp.json"
    expect_true "report metrics count the variants" -- jq -e '.metrics.gles_export.variants == 2' "$WORK/r.json"
    # render compare's GLES column on the textured patch (sRGB albedo tiled 2x2): the scene
    # drawn through EGL equals the CPU model on >= 99.9% of pixels within 1e-3 (the issue's
    # criterion), for ES 1.00 and 3.00, consistent at 3 and 4 bands and seed.
    expect_exit 0 "render compare with the GLES column" -- "$R" compare "$SRC/configs/scenes/patch_city.toml" \
        -o "$WORK/c.exr" --spp 4 --width-px 24 --height-px 24 --rt-max-bands 4 \
        --rt-bake-samples 256 --rt-grid octa:9 --report "$WORK/c.json"
    expect_true "6 GLES variants compared" -- jq -e '.metrics.realtime.gles.variants | length == 6' "$WORK/c.json"
    expect_summary_number "summary: a GLES variant's mean relative error is the report's" \
        "render: GLES es300-seed-b3-highp vs path-traced truth: mean relative error ([0-9.e+-]+)," "$WORK/c.json" \
        '.metrics.realtime.gles.variants[] | select(.variant == "es300-seed-b3-highp") | .mean_rel'
    expect_true "every variant matches the CPU model on >= 99.9% of pixels" -- jq -e \
        '[.metrics.realtime.gles.variants[] | .["cpu_model_fraction_within_1e-3"] >= 0.999] | all' "$WORK/c.json"
    expect_true "GLES error against the truth is reported" -- jq -e \
        '[.metrics.realtime.gles.variants[] | (.mean_rel | type == "number") and (.mean_de2000 | type == "number")] | all' "$WORK/c.json"
    expect_true "three-way PNG written" -- test -s "$WORK/c_compare3_es300-seed-b3-highp.png"
else
    echo "note: blender-data city.exr absent: render export-gles not run"
fi
finish
