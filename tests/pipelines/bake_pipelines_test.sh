#!/usr/bin/env bash
# bake-fabric and bake-device on small inputs: each stage's report, the bundles' contents (the
# exported GLES variants with their manifests; a captured BTF's components in its stream order,
# every hash recomputed here), a tampered shader and a reordered stream rejected;
# validate-pair + validate-report on one pair, and a captured fabric's BTF shaded as a BTF from
# every prefix of its stream (bytes from the bundle manifest, error against the raw BTF shading
# non-increasing, full rank equal to the raw shading within the reconstruction bound).
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data
make_fabric "$WORK/fab" "Tiny weave" 0.2
expect_exit 0 "bake-fabric" -- "$PIPE/bake-fabric.sh" "$WORK/fab" "$WORK/out" tiny
expect_stderr "no BTF" "says the fabric has no BTF"
expect_stderr "8 GLES variants" "says how many shader variants it bundled (ES 1.00, 3.00 x 2 modes x 2 precisions)"
B="$WORK/out/bundles/fabrics/tiny"
M="$B/manifest.json"
expect_true "fabric bundle roles" -- jq -e '([.files[].role] | unique) == ["albedo","brdf_sh_table","brdf_sh_table_json","brdf_sh_texture","material","normal","shader_data","shader_fragment","shader_index","shader_lookup","shader_manifest","shader_vertex","thumbnail"] and .version == 2' "$M"
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
for step in maps/report.json brdf/report.json pack.json verify.json; do
    expect_true "report $step ok" -- jq -e '.status == "ok"' "$WORK/out/work/fabrics/tiny/$step"
done
cp -r "$B" "$WORK/tampered"
frag=$(jq -r '[.files[] | select(.role == "shader_fragment")][0].path' "$M")
sed -i '1s/^#/X/' "$WORK/tampered/$frag"  # same size, one byte changed
expect_exit 1 "verify rejects a tampered shader" -- "$BIN/bundle" verify "$WORK/tampered"
expect_stderr "$frag: sha256 mismatch" "names the shader and the problem"

# A captured-BTF fabric (tiny.sh: 4 x 4 px, 1 spp; 3 groups of 27 views, 4 components each).
make_captured_fabric "$WORK/cap" "Captured twill"
expect_exit 0 "bake-fabric with a captured BTF" -- "$PIPE/bake-fabric.sh" "$WORK/cap" "$WORK/out" cap
expect_stderr "btf-pca: 81 views x 81 lights of 4x4 px" "says what btf-pca compressed"
C="$WORK/out/bundles/fabrics/cap"
P="$WORK/out/work/fabrics/cap/btf/btf-pca.json"
expect_true "3 groups of 27 views, 4 components each, in the bundle" -- jq -e '([.files[] | select(.role == "btf_component")] | length) == 12 and ([.files[] | select(.role == "btf_mean")] | length) == 3 and .properties.btf_directions == [81, 81]' "$C/manifest.json"
# shellcheck disable=SC2016  # $p and $m are jq variables
expect_true "stream_index k is btf-pca's k-th streamed component" -- jq -e --slurpfile p "$P" \
    '[.files[] | select(.role == "btf_component")] | sort_by(.stream_index) | map(.path) == ($p[0] as $m | $m.stream | map("btf/" + $m.groups[.[0]].components[.[1]].file))' "$C/manifest.json"
comp=$(jq -r '.files[] | select(.role == "btf_component" and .stream_index == 0) | .path' "$C/manifest.json")
expect_true "component hash is btf-pca's file's" -- test -f "$WORK/out/work/fabrics/cap/$comp" -a "$(jq -r --arg p "$comp" '.files[] | select(.path == $p) | .sha256' "$C/manifest.json")" = "$(sha256sum "$WORK/out/work/fabrics/cap/$comp" | cut -d' ' -f1)"
cp -r "$C" "$WORK/reordered"
jq '(.files[] | select(.role == "btf_component" and .stream_index < 2) | .stream_index) |= 1 - .' "$C/manifest.json" > "$WORK/reordered/manifest.json"
expect_exit 1 "verify rejects components out of the BTF's stream order" -- "$BIN/bundle" verify "$WORK/reordered"
expect_stderr "stream order" "says the stream order differs"

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
# The captured fabric's BTF shaded as a BTF (render --btf-shade from the raw capture, the bundle's
# stream prefixes beside it). Its shipped format (8-bit PNG components, 4 per group):
RAW="$WORK/out/work/fabrics/cap/capture/btf"
expect_exit 0 "validate-pair with the raw BTF" -- env VALIDATE_RENDER_CONFIG="$WORK/v.toml" VALIDATE_MAX_ERROR=0 \
    VALIDATE_BTF_SPP=16 "$PIPE/validate-pair.sh" "$C" "$HDRI_DIR/sunset.exr" "$WORK/val/pairs/cap/sunset" "$RAW"
SC="$WORK/val/pairs/cap/sunset/summary.json"
expect_true "BTF shaded from 0, 3, 6, 9, 12 components (multiples of the 3 groups) and as shipped" -- jq -e \
    '([.btf.views[0].stream[].components_sent] == [0, 3, 6, 9, 12]) and .btf.views[0].shipped.components_sent == 12 and .btf.views[0].raw.mean_de2000 > 0 and .btf.views[0].view_deg == [0, 0]' "$SC"
# The bytes per prefix are sums of the bundle manifest's sizes; btf-pca's own streaming.tsv counts
# the same files independently.
expect_true "bytes per stream prefix equal btf-pca's streaming.tsv" -- test \
    "$(jq -r '.btf.views[0].stream[] | "\(.components_sent) \(.bytes_sent)"' "$SC")" = \
    "$(awk '!/^#/ && $1 % 3 == 0 {print $1, $2}' "$WORK/out/work/fabrics/cap/btf/streaming.tsv")"
# shellcheck disable=SC2016  # jq program
expect_true "shipped bytes are the bundle's btf files" -- jq -e --slurpfile m "$C/manifest.json" \
    '.btf.bytes_shipped == ([$m[0].files[] | select(.role | startswith("btf_")) | .bytes] | add)' "$SC"

# Float components at full rank (16 per group for 4 x 4 px) from the same capture. Error against
# the raw shading: the view (0, 0) lies in one group and each prefix projects its images onto
# nested subspaces, so it cannot rise (tolerance 1e-6: float32 fold of ~16 terms, 2^-24 each).
mkdir -p "$WORK/capfull"
cp "$WORK/cap/"*.toml "$WORK/capfull/"
printf 'view-group-size = 27\ncomponents = 16\nformat = "exr-float"\n' > "$WORK/capfull/btf-pca.toml"
expect_exit 0 "bake-fabric at full rank from the same capture" -- "$PIPE/bake-fabric.sh" "$WORK/capfull" "$WORK/out" capfull "$RAW"
expect_exit 0 "validate-pair at full rank" -- env VALIDATE_RENDER_CONFIG="$WORK/v.toml" VALIDATE_MAX_ERROR=0 \
    VALIDATE_BTF_SPP=16 "$PIPE/validate-pair.sh" "$WORK/out/bundles/fabrics/capfull" "$HDRI_DIR/sunset.exr" "$WORK/valfull" "$RAW"
SF="$WORK/valfull/summary.json"
# shellcheck disable=SC2016  # jq program
expect_true "error against the raw BTF shading non-increasing over 17 prefixes" -- jq -e \
    '.btf.views[0].stream | length == 17 and ([range(1; length) as $i | .[$i].vs_raw_rel_rmse <= .[$i - 1].vs_raw_rel_rmse + 1e-6] | all)' "$SF"
# Full rank: every reconstructed value is within btf-pca's max_abs_linear of the raw one; the
# shading is a non-negative blend of the view's 81 images, so its RMSE relative to its mean is
# at most max_abs_linear / (the darkest image's mean), bounded below by sRGB-decoding each
# image's channel means (the decode is convex: Jensen), plus the fold's float32 rounding (1e-6).
dark=$(oiiotool --stats "$RAW"/tv000_pv000/*.png 2>&1 | awk '/Stats Avg/ {m = 0; for (c = 3; c <= 5; c++) {v = $c / 255; m += (v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055) ^ 2.4) / 3}; print m}' | sort -g | head -n 1)
bound=$(jq -n --argjson e "$(jq .metrics.error.max_abs_linear "$WORK/out/work/fabrics/capfull/btf-pca.json")" --argjson d "$dark" '$e / $d + 1e-6')
echo "full rank: bound $bound (darkest image mean >= $dark)"
# shellcheck disable=SC2016  # jq program
expect_true "full rank equals the raw BTF shading within the reconstruction bound" -- jq -e --argjson b "$bound" \
    '(.btf.views[0].stream | last | .components_sent == 48 and .vs_raw_rel_rmse <= $b) and .btf.views[0].stream[0].vs_raw_rel_rmse > 1000 * $b' "$SF"

expect_exit 0 "validate-report" -- "$PIPE/validate-report.sh" "$WORK/val"
expect_true "verdict and advice" -- jq -e 'map(select(.fabric == "tiny"))[0] | .verdict != null and (.advice | length) > 0' "$WORK/val/summary.json"
expect_true "report rows: GLES at the shipped bands, budget, largest error part" -- jq -e \
    'map(select(.fabric == "tiny"))[0] | .gles_shipped.sh_bands == .sh_bands_shipped and (.budget_text | test("bands \\+ [0-9] lights")) and (.largest_part | IN("grid", "sh_diffuse", "sh_specular", "fixed_view", "visibility"))' "$WORK/val/summary.json"
expect_true "Markdown summary has the GLES and budget columns" -- grep -q '| GLES dE2000 (agrees) |.*| budget | largest part |' "$WORK/val/summary.md"
for p in error_vs_sh_bands error_vs_frame_time truth_noise error_vs_bytes error_parts btf_error_vs_components btf_error_vs_bytes; do
    expect_true "plot $p is a PNG" -- bash -c "file '$WORK/val/plots/$p.png' | grep -q 'PNG image'"
done
expect_true "page links the pair's images" -- grep -q 'pairs/tiny/sunset/render_compare_consistent.png' "$WORK/val/index.html"
expect_true "page shows the BTF shading of the captured fabric" -- grep -q 'pairs/cap/sunset/btf_sunset_tv000_pv000_compare.png' "$WORK/val/index.html"
expect_true "Markdown: a BTF row and the stream table (5 prefixes)" -- test "$(grep -c '^| cap |' "$WORK/val/summary.md")" -eq 7

# bake-device on the real ROS fisheye set (skipped when ../shared is absent, failed when only
# the data set is).
DATA="${INLIGHT_SHARED_DIR:-}/data/fisheye-ros-mono"
if have_shared_data fisheye-ros-mono; then
    mkdir -p "$WORK/dev"
    printf 'inputs = ["%s"]\nboard = "8x6"\nsquare-size-m = 0.108\nfov-deg = 180\ndownscale = "100x63"\n' "$DATA" > "$WORK/dev/calibrate.toml"
    expect_exit 0 "bake-device (ROS set)" -- "$PIPE/bake-device.sh" "$WORK/dev" "$WORK/out" ros
    D="$WORK/out/bundles/devices/ros/manifest.json"
    expect_true "device bundle: maps at 800x503 and 100x63, calibration" -- jq -e \
        '([.files[] | select(.role == "directions") | .width_px] | sort == [100, 800]) and (.properties.reproj_rms_px < 1)' "$D"
fi
finish
