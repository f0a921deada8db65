#!/usr/bin/env bash
# The sample pipeline on real data: every stage writes $OUT/<step>/ with its own --report.
#   pipelines/demo.sh [OUT]       (binaries from ${INLIGHT_BIN:-ROOT/build/bin})
set -euo pipefail
OUT=${1:-out}
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
BIN=$(tool_bin)
HDRI_DIR=/usr/share/blender/datafiles/studiolights/world
mkdir -p "$OUT"
# Everything the demo prints also goes to $OUT/demo.txt: the README points there instead of
# copying figures that would go stale as the code changes.
exec > >(tee "$OUT/demo.txt")
tee_pid=$!

if [ ! -d "$HDRI_DIR" ]; then
    echo "demo: $HDRI_DIR not found: run 'make deps' (Debian package blender-data)" >&2
    exit 1
fi

# 1. Environments to SH: the app's 3 bands, plus 9 bands validated against brute force so the
#    report shows the irradiance error for every band count 1..9.
"$BIN/envmap-project" "$HDRI_DIR"/*.exr -o "$OUT/envmap/sh3" --sh-bands 3 -q \
    --config "$ROOT/configs/envmap-project.toml" --report "$OUT/envmap/sh3_report.json"
"$BIN/envmap-project" "$HDRI_DIR"/*.exr -o "$OUT/envmap/sh9" --sh-bands 9 --validate -q \
    --config "$ROOT/configs/envmap-project.toml" --report "$OUT/envmap/sh9_report.json"
if [ -d "$SHARED/data/probes-latlong" ]; then
    "$BIN/envmap-project" "$SHARED"/data/probes-latlong/*.hdr -o "$OUT/envmap/probes" --sh-bands 9 \
        --validate -q --report "$OUT/envmap/probes_report.json"
fi

echo
echo "envmap-project: irradiance error of the SH approximation vs brute force (mean/max relative)"
printf '%-12s %9s %10s %17s %17s %17s\n' map peak time_ms "3 bands" "5 bands" "9 bands"
for r in "$OUT"/envmap/sh9_report.json "$OUT"/envmap/probes_report.json; do
    [ -f "$r" ] || continue
    jq -r '.metrics.environments[] |
        [(.path | split("/") | last | split(".") | first), (.peak_value | floor),
         (.project_time_s * 1000 | . * 10 | round / 10),
         (.validation.error_by_sh_bands["3"] | "\(.mean_rel * 1e4 | round / 1e4)/\(.max_rel * 1e4 | round / 1e4)"),
         (.validation.error_by_sh_bands["5"] | "\(.mean_rel * 1e4 | round / 1e4)/\(.max_rel * 1e4 | round / 1e4)"),
         (.validation.error_by_sh_bands["9"] | "\(.mean_rel * 1e4 | round / 1e4)/\(.max_rel * 1e4 | round / 1e4)")]
        | @tsv' "$r" | while IFS=$'\t' read -r name peak ms e3 e5 e9; do
        printf '%-12s %9s %10s %17s %17s %17s\n' "$name" "$peak" "$ms" "$e3" "$e5" "$e9"
    done
done

# 2. The fabric's specular lobe into an SH table over normals (the app's lookup), with its
#    integration, interpolation and truncation errors against a converged reference.
"$BIN/brdf-sh-bake" --config "$ROOT/configs/brdf-sh-bake.toml" \
    --material "$ROOT/configs/materials/satin-ggx.toml" -o "$OUT/brdf/satin" -q \
    --export-gles "$OUT/gles/satin" --gles-versions 300 --report "$OUT/brdf/satin_report.json"
"$BIN/brdf-sh-bake" --config "$ROOT/configs/brdf-sh-bake-report.toml" \
    --material "$ROOT/configs/materials/report-cook-torrance.toml" -o "$OUT/brdf/report_ct" -q \
    --export-gles "$OUT/gles/report_ct" --report "$OUT/brdf/report_ct_report.json"
echo
echo "brdf-sh-bake: table errors (relative to the largest exact radiance of each test lighting)"
printf '%-10s %-15s %-15s %9s %12s %14s %11s\n' table grid integrator bake_ms integration interpolation truncation
for r in "$OUT"/brdf/*_report.json; do
    jq -r '[(input_filename | split("/") | last | sub("_report.json"; "")), .metrics.grid,
            .metrics.integrator, (.metrics.bake_time_s * 1000 | round),
            (.metrics.integration_radiance_max_rel * 1e4 | round / 1e4),
            (.metrics.interpolation_radiance_max_rel * 1e4 | round / 1e4),
            (.metrics.truncation_radiance_max_rel * 1e4 | round / 1e4)] | @tsv' "$r" |
        while IFS=$'\t' read -r name grid integ ms e_int e_interp e_trunc; do
            printf '%-10s %-15s %-15s %9s %12s %14s %11s\n' "$name" "$grid" "$integ" "$ms" "$e_int" "$e_interp" "$e_trunc"
        done
done

# (satin's thetaphi:9x32 table is a 96-texel-wide texture, more than the 64 texels every ES 2.0
# device must offer, so it gets GLSL ES 3.00 only; the report's 5x5 table gets both.)
echo "GLES shaders (consistent and seed, highp; docs/gles.md says which to load) with their manifests:"
echo "  $OUT/gles/satin/index.json (ES 3.00), $OUT/gles/report_ct/index.json (ES 1.00 and 3.00),"
echo "  $OUT/gles/patch_city/index.json (docs/gles.md)"

# 3. Ground truth against the app's real-time model (CPU) and its exported GLES shaders run
#    through EGL: the satin patch under the city HDRI, three columns.
"$BIN/render" compare "$ROOT/configs/scenes/patch_city.toml" -o "$OUT/render/patch_city.exr" \
    --spp 256 -q --report "$OUT/render/patch_city_report.json"
"$BIN/render" export-gles "$ROOT/configs/scenes/patch_city.toml" -o "$OUT/gles/patch_city" -q \
    --report "$OUT/render/patch_city_gles_report.json"
echo
echo "render: the app's real-time model against the path-traced ground truth (patch_city)"
jq -r '"  ground truth: \(.metrics.spp) spp, relative noise \(.metrics.rel_error * 1e4 | round / 1e4), \(.metrics.rays_per_s / 1e6 * 100 | round / 100) Mrays/s",
       "  consistent mode, 3 bands: mean rel error \(.metrics.realtime.modes.consistent.mean_rel * 1e4 | round / 1e4), mean dE2000 \(.metrics.realtime.modes.consistent.mean_de2000 * 100 | round / 100)",
       "  seed mode (the report'"'"'s shader): mean rel error \(.metrics.realtime.modes.seed.mean_rel * 1e4 | round / 1e4), mean dE2000 \(.metrics.realtime.modes.seed.mean_de2000 * 100 | round / 100)",
       "  side by side: '"$OUT"'/render/patch_city_compare_consistent.png",
       "  GLES on \(.metrics.realtime.gles.driver):",
       (.metrics.realtime.gles.variants[] | "    \(.variant): mean rel error \(.mean_rel * 1e4 | round / 1e4), mean dE2000 \(.mean_de2000 * 100 | round / 100), \(.["cpu_model_fraction_within_1e-3"] * 1000 | round / 10)% of pixels within 1e-3 of the CPU model, \(.frame_time_ms * 10 | round / 10) ms/frame"),
       "  truth | CPU model | GLES | error: '"$OUT"'/render/patch_city_compare3_es300-consistent-b3-highp.png"' "$OUT/render/patch_city_report.json"

# 4. Camera to lighting on real photographs (when ../shared/data is present).
if [ -d "$SHARED/data/fisheye-ros-mono" ]; then
    echo
    INLIGHT_BIN="$BIN" INLIGHT_SHARED_DIR="$SHARED" "$HERE/calibrate_ros.sh" "$OUT/calibrate_ros"
fi

# 5. The sample catalogue (samples/catalog: fabrics from blender-data's woven texture, a
#    captured-BTF wool twill, the ROS fisheye as a device) into verified bundles, the SQLite catalogue and the validation report
#    of every fabric under the eight HDRIs, through the Snakemake workflow (progress: "N of M
#    steps"). Rerunning it rebuilds only what changed.
echo
echo "bake-catalog: samples/catalog -> $OUT/catalog (Snakemake; per-job logs in $OUT/catalog/logs)"
INLIGHT_BIN="$BIN" INLIGHT_SHARED_DIR="$SHARED" "$HERE/bake-catalog.sh" "$ROOT/samples/catalog" \
    "$OUT/catalog" 2>&1 | grep --line-buffered -E "steps \(|skipped|Nothing to be done|Error|error" || true
if [ ! -s "$OUT/catalog/validate/index.html" ]; then
    echo "demo: bake-catalog failed; see $OUT/catalog/logs/" >&2
    exit 1
fi
echo
echo "bundles (catalog.sqlite):"
sqlite3 -separator '  ' "$OUT/catalog/bundles/catalog.sqlite" \
    "SELECT 'device', id, total_bytes || ' bytes', file_count || ' files', '', '' FROM devices
     UNION ALL SELECT 'fabric', id, total_bytes || ' bytes', file_count || ' files',
       shader_variants || ' GLES variants (' || shader_bytes || ' bytes)',
       CASE WHEN btf_components > 0 THEN 'BTF: ' || btf_components || ' components streamed ('
            || btf_bytes || ' bytes)' ELSE 'no BTF' END FROM fabrics"
echo
echo "validation: $(jq -r 'group_by(.verdict) | map("\(length) \(.[0].verdict)") | join(", ")' \
    "$OUT/catalog/validate/summary.json") of $(jq length "$OUT/catalog/validate/summary.json") fabric x environment pairs"
grep -E '^\| (fabric|---|[a-z])' "$OUT/catalog/validate/summary.md" | cut -d'|' -f2-7 | sed 's/|$//' | sed -n '1,12p'
echo "  ... all pairs, images and plots: $OUT/catalog/validate/index.html"
# The captured fabrics' BTFs as the phone draws them: the bundles' BTF GLES shaders through EGL
# against the path-traced weave (docs/btf-gles.md, "Against the truth").
if grep -q '^The BTF as the phone draws it' "$OUT/catalog/validate/summary.md"; then
    echo
    echo "BTF fabrics as the phone draws them (the bundle's BTF GLES shaders, EGL), over the environments:"
    awk '/^The BTF as the phone draws it/ {on = 1} on && /^\|/ {print} on && /^$/ && seen {exit} on && /^\|/ {seen = 1}' \
        "$OUT/catalog/validate/summary.md" | cut -d'|' -f2-4,6-10 | sed 's/|$//'
fi

echo
echo "demo: outputs and reports in $OUT/; this summary in $OUT/demo.txt"
exec >&-
wait "$tee_pid"
