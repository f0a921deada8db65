#!/usr/bin/env bash
# A captured-BTF fabric through bake-fabric and validate-pair (its own test: the capture and the
# BTF shading take a while on a loaded machine): its components in the bundle in btf-pca's
# stream order (hashes recomputed here), a reordered stream rejected; its BTF shaded as a BTF
# from every prefix of the stream (bytes from the bundle manifest, error against the raw BTF
# shading non-increasing, full rank equal to the raw shading within the reconstruction bound);
# the report's BTF table and plots.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data

# A captured-BTF fabric (tiny.sh: 4 x 4 px, 1 spp; 3 groups of 27 views), here with float
# components at full rank (16 per group for 4 x 4 px), so the stream ends at the raw BTF up to
# float32 rounding and every bound below is exact; the shipped 8-bit format is the demo's.
make_captured_fabric "$WORK/cap" "Captured twill"
printf 'view-group-size = 27\ncomponents = 16\nformat = "exr-float"\n' > "$WORK/cap/btf-pca.toml"
expect_exit 0 "bake-fabric with a captured BTF" -- "$PIPE/bake-fabric.sh" "$WORK/cap" "$WORK/out" cap
expect_stderr "btf-pca: 81 views x 81 lights of 4x4 px" "says what btf-pca compressed"
C="$WORK/out/bundles/fabrics/cap"
P="$WORK/out/work/fabrics/cap/btf/btf-pca.json"
expect_true "3 groups of 27 views, 16 components each, in the bundle" -- jq -e '([.files[] | select(.role == "btf_component")] | length) == 48 and ([.files[] | select(.role == "btf_mean")] | length) == 3 and .properties.btf_directions == [81, 81]' "$C/manifest.json"
# shellcheck disable=SC2016  # $p and $m are jq variables
expect_true "stream_index k is btf-pca's k-th streamed component" -- jq -e --slurpfile p "$P" \
    '[.files[] | select(.role == "btf_component")] | sort_by(.stream_index) | map(.path) == ($p[0] as $m | $m.stream | map("btf/" + $m.groups[.[0]].components[.[1]].file))' "$C/manifest.json"
comp=$(jq -r '.files[] | select(.role == "btf_component" and .stream_index == 0) | .path' "$C/manifest.json")
expect_true "component hash is btf-pca's file's" -- test -f "$WORK/out/work/fabrics/cap/$comp" -a "$(jq -r --arg p "$comp" '.files[] | select(.path == $p) | .sha256' "$C/manifest.json")" = "$(sha256sum "$WORK/out/work/fabrics/cap/$comp" | cut -d' ' -f1)"
cp -r "$C" "$WORK/reordered"
jq '(.files[] | select(.role == "btf_component" and .stream_index < 2) | .stream_index) |= 1 - .' "$C/manifest.json" > "$WORK/reordered/manifest.json"
expect_exit 1 "verify rejects components out of the BTF's stream order" -- "$BIN/bundle" verify "$WORK/reordered"
expect_stderr "stream order" "says the stream order differs"
expect_true "float components: no BTF GLES shaders in the bundle" -- jq -e '[.files[] | select(.role | startswith("btf_gles"))] == []' "$C/manifest.json"
# The same capture as 8-bit PNG components (the shipped format; 4 components: two atlas slabs, so
# ES 1.00 needs 19 fragment uniform vectors, more than ES 2.0 guarantees): the bundle carries the
# BTF's GLES shaders beside btf-pca.json, without atlases.
make_fabric "$WORK/png" "PNG twill" 0.3
printf 'view-group-size = 27\ncomponents = 4\nformat = "png"\n' > "$WORK/png/btf-pca.toml"
expect_exit 0 "bake-fabric with the capture as PNG components" -- \
    "$PIPE/bake-fabric.sh" "$WORK/png" "$WORK/out" png "$WORK/out/work/fabrics/cap/capture/btf"
expect_stderr "BTF GLES shaders: OpenGL ES 3.0 or later: btf-es300-highp; OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH: btf-es100-highp (needs GL_MAX_FRAGMENT_UNIFORM_VECTORS >= 19)" \
    "says which variant each GL capability loads"
PM="$WORK/out/bundles/fabrics/png/manifest.json"
PG="$WORK/out/work/fabrics/png/btf-gles"
# shellcheck disable=SC2016  # $g is a jq variable
expect_true "btf-gles.json, 2 variants' shaders and the matrices under btf/, found by role; no atlas" -- jq -e \
    '.version == 4 and .properties.btf_gles_bands == 3
     and ([.files[] | select(.role == "btf_gles_manifest") | .path] == ["btf/btf-gles.json"])
     and ([.files[] | select(.role == "btf_gles_vertex" or .role == "btf_gles_fragment") | .path] | sort)
         == ["btf/btf-es100-highp.frag", "btf/btf-es100-highp.vert", "btf/btf-es300-highp.frag", "btf/btf-es300-highp.vert"]
     and ([.files[] | select(.role == "btf_gles_matrices") | .path] == ["btf/lighting-matrices.bin"])
     and ([.files[] | select(.path | test("atlas"))] == [])' "$PM"
mismatch=0
for f in btf-gles.json btf-es300-highp.vert btf-es300-highp.frag btf-es100-highp.vert btf-es100-highp.frag lighting-matrices.bin; do
    want=$(sha256sum "$PG/$f" | cut -d' ' -f1)
    got=$(jq -r --arg p "btf/$f" '.files[] | select(.path == $p) | .sha256' "$PM")
    [ "$want" = "$got" ] || { echo "hash of btf/$f: bundle '$got', file $want"; mismatch=1; }
done
expect_true "BTF GLES files hashed in the manifest as exported" -- test "$mismatch" -eq 0
# shellcheck disable=SC2016  # $m is a jq variable
expect_true "every atlas channel's source is a mean or component PNG of the bundle" -- jq -e --slurpfile m "$PM" \
    '([.textures.groups[].channels[].file | select(. != null) | "btf/" + .] | unique)
     == ([$m[0].files[] | select(.role == "btf_mean" or .role == "btf_component") | .path] | unique)
     and .textures.atlas_files == false and ([.textures.groups[].file] | unique) == [null]' "$PG/btf-gles.json"
expect_true "the matrices divide by the capture's irradiance" -- test \
    "$(jq '.matrices.irradiance_w_m2' "$PG/btf-gles.json")" = "$(jq '.irradiance_w_m2' "$WORK/out/work/fabrics/cap/capture/btf/capture.json")"
# The bundle's own btf/ exports to the same bytes (the export reads the bundled PNGs).
expect_exit 0 "export-gles of the bundle's btf/" -- "$BIN/btf-pca" export-gles "$WORK/out/bundles/fabrics/png/btf" \
    -o "$WORK/png-again" --atlases none --bands 3 \
    --irradiance-w-m2 "$(jq '.irradiance_w_m2' "$WORK/out/work/fabrics/cap/capture/btf/capture.json")"
expect_true "same files" -- diff -r "$PG" "$WORK/png-again"
cp -r "$WORK/out/bundles/fabrics/png" "$WORK/png-cut"
rm "$WORK/png-cut/btf/btf-es100-highp.frag"
# shellcheck disable=SC2016  # $f and $b are jq variables
jq --arg f btf/btf-es100-highp.frag '([.files[] | select(.path == $f) | .bytes] | add) as $b
    | .files |= map(select(.path != $f)) | .total_bytes -= $b' "$PM" > "$WORK/png-cut/manifest.json"
expect_exit 1 "verify rejects a bundle missing a BTF shader" -- "$BIN/bundle" verify "$WORK/png-cut"
expect_stderr "btf/btf-gles.json: variants\\[0\\].fragment_shader: 'btf/btf-es100-highp.frag' is not in the bundle" "names the missing shader"

printf 'spp = 8\nwidth-px = 16\nheight-px = 16\nrt-max-bands = 4\nrt-supersample = 1\n' > "$WORK/v.toml"

# The BTF shaded as a BTF (render shade-btf from the raw capture, the bundle's stream prefixes
# 0, 3, ..., 48 beside it: multiples of the 3 groups).
RAW="$WORK/out/work/fabrics/cap/capture/btf"
expect_exit 0 "validate-pair with the raw BTF" -- env VALIDATE_RENDER_CONFIG="$WORK/v.toml" VALIDATE_MAX_ERROR=0 \
    VALIDATE_BTF_SPP=16 "$PIPE/validate-pair.sh" "$C" "$HDRI_DIR/sunset.exr" "$WORK/val/pairs/cap/sunset" "$RAW"
SC="$WORK/val/pairs/cap/sunset/summary.json"
expect_true "BTF shaded from 17 stream prefixes and as shipped, at the pair's view" -- jq -e \
    '([.btf.views[0].stream[].components_sent] == [range(0; 49; 3)]) and .btf.views[0].shipped.components_sent == 48 and .btf.views[0].raw.mean_de2000 > 0 and .btf.views[0].view_deg == [0, 0]' "$SC"
# The bytes per prefix are sums of the bundle manifest's sizes; btf-pca's own streaming.tsv counts
# the same files independently.
expect_true "bytes per stream prefix equal btf-pca's streaming.tsv" -- test \
    "$(jq -r '.btf.views[0].stream[] | "\(.components_sent) \(.bytes_sent)"' "$SC")" = \
    "$(awk '!/^#/ && $1 % 3 == 0 {print $1, $2}' "$WORK/out/work/fabrics/cap/btf/streaming.tsv")"
# shellcheck disable=SC2016  # jq program
expect_true "shipped bytes are the bundle's btf files" -- jq -e --slurpfile m "$C/manifest.json" \
    '.btf.bytes_shipped == ([$m[0].files[] | select(.role | startswith("btf_")) | .bytes] | add)' "$SC"
expect_true "shaded at the default views: the pair's (0, 0), the oblique (45, 40) and the grazing (75, 0)" -- jq -e \
    '[.btf.views[].view_deg] == [[0, 0], [45, 40], [75, 0]] and ([.btf.views[].compare_image] | unique | length) == 3' "$SC"
# At each view (all are capture views, taken whole: --view-neighbours 1):
# Error against the raw shading: the view lies in one group and each prefix projects its images
# onto nested subspaces, so it cannot rise (tolerance 1e-6: float32 fold of ~16 terms, 2^-24 each).
# Full rank: every reconstructed value is within btf-pca's max_abs_linear of the raw one; the
# shading is a non-negative blend of the view's 81 images, so its RMSE relative to its mean is
# at most max_abs_linear / (the darkest image's mean), bounded below by sRGB-decoding each
# image's channel means (the decode is convex: Jensen), plus the fold's float32 rounding (1e-6).
max_abs=$(jq .metrics.error.max_abs_linear "$WORK/out/work/fabrics/cap/btf-pca.json")
for v in 0 1 2; do
    view=$(jq -r ".btf.views[$v].view_deg | \"tv\(.[0] + 1000 | tostring | .[1:])_pv\(.[1] + 1000 | tostring | .[1:])\"" "$SC")
    # shellcheck disable=SC2016  # jq program
    expect_true "$view: error against the raw BTF shading non-increasing over the 17 prefixes" -- jq -e --argjson v "$v" \
        '.btf.views[$v].stream | ([range(1; length) as $i | .[$i].vs_raw_rel_rmse <= .[$i - 1].vs_raw_rel_rmse + 1e-6] | all)' "$SC"
    dark=$(oiiotool --stats "$RAW/$view"/*.png 2>&1 | awk '/Stats Avg/ {m = 0; for (c = 3; c <= 5; c++) {v = $c / 255; m += (v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055) ^ 2.4) / 3}; print m}' | sort -g | head -n 1)
    bound=$(jq -n --argjson e "$max_abs" --argjson d "$dark" '$e / $d + 1e-6')
    echo "$view full rank: bound $bound (darkest image mean >= $dark)"
    # shellcheck disable=SC2016  # jq program
    expect_true "$view: full rank equals the raw BTF shading within the reconstruction bound" -- jq -e --argjson b "$bound" --argjson v "$v" \
        '(.btf.views[$v].stream | last | .components_sent == 48 and .vs_raw_rel_rmse <= $b) and .btf.views[$v].stream[0].vs_raw_rel_rmse > 1000 * $b' "$SC"
done

expect_exit 0 "validate-report" -- "$PIPE/validate-report.sh" "$WORK/val"
for p in btf_error_vs_components btf_error_vs_bytes; do
    expect_true "plot $p is a PNG" -- bash -c "file '$WORK/val/plots/$p.png' | grep -q 'PNG image'"
done
expect_true "page shows the BTF shading of the captured fabric" -- grep -q 'pairs/cap/sunset/btf_sunset_tv000_pv000_compare.png' "$WORK/val/index.html"
expect_true "page shows the oblique view too" -- grep -q 'pairs/cap/sunset/btf_sunset_tv045_pv040_compare.png' "$WORK/val/index.html"
expect_true "Markdown: a BTF row, the stream table (17 prefixes) and the view table (3 views)" -- test "$(grep -c '^| cap |' "$WORK/val/summary.md")" -eq 22
expect_true "Markdown says which views were shaded" -- grep -q 'at each of these views: theta 0, phi 0 deg; theta 45, phi 40 deg; theta 75, phi 0 deg' "$WORK/val/summary.md"
finish
