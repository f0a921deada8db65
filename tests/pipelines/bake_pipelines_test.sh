#!/usr/bin/env bash
# bake-fabric on small inputs: each stage's report, the bundle's contents (the exported GLES
# variants with their manifests, every hash recomputed here), a tampered shader rejected;
# validate-pair + validate-report on one pair. The captured-BTF fabric: captured_fabric_test.sh;
# bake-device: bake_device_test.sh (apart, so that each fits ctest's timeout on a loaded machine).
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data
make_fabric "$WORK/fab" "Tiny weave" 0.2
expect_exit 0 "bake-fabric" -- "$PIPE/bake-fabric.sh" "$WORK/fab" "$WORK/out" tiny
expect_stderr "no BTF" "says the fabric has no BTF"
expect_stderr "4 GLES variants" "says how many shader variants it bundled (ES 1.00, 3.00 x 2 modes, highp only by default: docs/gles.md)"
B="$WORK/out/bundles/fabrics/tiny"
M="$B/manifest.json"
expect_true "fabric bundle roles" -- jq -e '([.files[].role] | unique) == ["albedo","brdf_sh_table","brdf_sh_table_json","brdf_sh_texture","material","normal","shader_data","shader_fragment","shader_index","shader_lookup","shader_manifest","shader_texture","shader_vertex","thumbnail"] and .version == 4' "$M"
# Every exported variant is bundled with what its manifest names, and the bundle's hash of each
# is the exporter's file's, recomputed with sha256sum.
G="$WORK/out/work/fabrics/tiny/gles"
expect_true "a manifest per exported variant" -- test "$(jq '[.files[] | select(.role == "shader_manifest")] | length' "$M")" -eq "$(jq '.variants | length' "$G/index.json")"
mismatch=0
while read -r f; do
    want=$(sha256sum "$G/$f" | cut -d' ' -f1)
    got=$(jq -r --arg p "shaders/$f" '.files[] | select(.path == $p) | .sha256' "$M")
    [ "$want" = "$got" ] || { echo "hash of shaders/$f: bundle '$got', file $want"; mismatch=1; }
done < <(cd "$G" && jq -r '.variants[].manifest' index.json | while read -r v; do echo "$v"; jq -r '.files[]' "$v"; done)
expect_true "shader files hashed in the manifest as exported" -- test "$mismatch" -eq 0
expect_true "properties from the stage reports" -- jq -e '.name == "Tiny weave" and .properties.sh_bands == 3 and .properties.brdf_grid == "thetaphi:5x8" and .properties.tile_size_m == 0.05' "$M"

# What ships is reproducible: the same fabric baked again into another folder gives a
# byte-identical bundle, manifest included: no time, host or path of the run in it (each tool's
# outputs are the same for any --threads: their own tests).
expect_exit 0 "bake-fabric again" -- "$PIPE/bake-fabric.sh" "$WORK/fab" "$WORK/again" tiny
expect_true "byte-identical bundle" -- diff -r "$B" "$WORK/again/bundles/fabrics/tiny"
for step in maps/report.json brdf/report.json pack.json verify.json; do
    expect_true "report $step ok" -- jq -e '.status == "ok"' "$WORK/out/work/fabrics/tiny/$step"
done
cp -r "$B" "$WORK/tampered"
frag=$(jq -r '[.files[] | select(.role == "shader_fragment")][0].path' "$M")
sed -i '1s/^#/X/' "$WORK/tampered/$frag"  # same size, one byte changed
expect_exit 1 "verify rejects a tampered shader" -- "$BIN/bundle" verify "$WORK/tampered"
expect_stderr "$frag: sha256 mismatch" "names the shader and the problem"

mkdir -p "$WORK/nomat"
cp "$WORK/fab/fabric.toml" "$WORK/nomat/"
expect_exit 2 "bake-fabric without material.toml" -- "$PIPE/bake-fabric.sh" "$WORK/nomat" "$WORK/out2"
expect_stderr "material.toml not found" "names the missing file"

printf 'spp = 8\nwidth-px = 16\nheight-px = 16\nrt-max-bands = 4\nrt-supersample = 1\n' > "$WORK/v.toml"
expect_exit 0 "validate-pair (with the band budget and the decomposition)" -- env \
    VALIDATE_RENDER_CONFIG="$WORK/v.toml" VALIDATE_DECOMPOSE=1 VALIDATE_MAX_ERROR=0.05 "$PIPE/validate-pair.sh" \
    "$WORK/out/bundles/fabrics/tiny" "$HDRI_DIR/sunset.exr" "$WORK/val/pairs/tiny/sunset"
S="$WORK/val/pairs/tiny/sunset"
# shellcheck disable=SC2016  # $b and $r are jq variables
expect_true "pair summary carries envmap-project's budget choice" -- jq -e --slurpfile b "$S/budget.json" \
    '.budget.max_error == 0.05 and .budget.sh_bands == $b[0].metrics.environments[0].budget.chosen.sh_bands and .budget.lights == $b[0].metrics.environments[0].budget.chosen.lights and (.budget.met | type) == "boolean"' "$S/summary.json"
# shellcheck disable=SC2016
expect_true "pair summary carries render's decomposition, a part per band count" -- jq -e --slurpfile r "$S/render.json" \
    '.decomposition.visibility == $r[0].metrics.realtime.decomposition.visibility and (.decomposition.by_sh_bands | length) == 4' "$S/summary.json"
expect_true "pair summary carries the GLES column" -- jq -e '[.gles.variants[] | select(.mode == "consistent")] | length > 0' "$S/summary.json"
expect_true "pair summary: 4 band counts, seed and consistent modes" -- jq -e \
    '(.by_sh_bands | length) == 4 and .consistent.mean_de2000 > 0 and .seed.mean_de2000 > 0 and .environment == "sunset"' \
    "$WORK/val/pairs/tiny/sunset/summary.json"
expect_exit 0 "validate-report" -- "$PIPE/validate-report.sh" "$WORK/val"
expect_true "verdict and advice" -- jq -e 'map(select(.fabric == "tiny"))[0] | .verdict != null and (.advice | length) > 0' "$WORK/val/summary.json"
expect_true "report rows: GLES at the shipped bands, budget, largest error part" -- jq -e \
    'map(select(.fabric == "tiny"))[0] | .gles_shipped.sh_bands == .sh_bands_shipped and (.budget_text | test("bands \\+ [0-9] lights?: ") and (test("(^|[^0-9])1 lights") | not)) and (.largest_part | IN("grid", "sh_diffuse", "sh_specular", "fixed_view", "visibility"))' "$WORK/val/summary.json"
expect_true "Markdown summary has the GLES and budget columns" -- grep -q '| GLES dE2000 (agrees) |.*| budget | largest part |' "$WORK/val/summary.md"
for p in error_vs_sh_bands error_vs_frame_time truth_noise error_vs_bytes error_parts; do
    expect_true "plot $p is a PNG" -- bash -c "file '$WORK/val/plots/$p.png' | grep -q 'PNG image'"
done
expect_true "page links the pair's images" -- grep -q 'pairs/tiny/sunset/render_compare_consistent.png' "$WORK/val/index.html"

finish
