#!/usr/bin/env bash
# CLI behaviour of render: help, exit codes, scene-file errors, reports, stop rules, quality
# gate, and bit-identical EXR pixels (and file bytes) for --threads 1 and 2.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
SRC=${INLIGHT_SOURCE_DIR:?}
SCENES="$SRC/configs/scenes"
FURNACE="$SCENES/sphere_furnace.toml"
SMALL=(--width-px 16 --height-px 16)

expect_exit 0 "trace --help" -- "$R" trace --help
expect_true "--help shows an example" -- grep -q "Example:" "$WORK/stdout"
expect_true "--help gives units" -- grep -q -- "--time-budget-s" "$WORK/stdout"
expect_exit 2 "unknown flag is a usage error" -- "$R" trace "$FURNACE" -o "$WORK/x.exr" --frobnicate
expect_exit 2 "missing scene file is a usage error" -- "$R" trace "$WORK/none.toml" -o "$WORK/x.exr"
expect_exit 2 "spp 0 is a usage error" -- "$R" trace "$FURNACE" -o "$WORK/x.exr" --spp 0
expect_exit 2 "unknown sampler is a usage error" -- "$R" trace "$FURNACE" -o "$WORK/x.exr" --sampler halton
expect_exit 2 "one scramble group is a usage error" -- "$R" trace "$FURNACE" -o "$WORK/x.exr" --scramble-groups 1
expect_exit 0 "independent sampler" -- "$R" trace "$FURNACE" -o "$WORK/i.exr" "${SMALL[@]}" --spp 8 \
    --sampler independent --report "$WORK/i.json"
expect_true "report names the sampler" -- jq -e '.metrics.sampler == "independent"' "$WORK/i.json"
expect_exit 0 "adaptive sampling" -- "$R" trace "$FURNACE" -o "$WORK/a.exr" "${SMALL[@]}" --spp 16 \
    --adaptive --adaptive-min-spp 8 --report "$WORK/a.json"
expect_true "adaptive: mean spp within the budget, reported" -- \
    jq -e '.metrics.adaptive and .metrics.mean_spp <= 17 and .metrics.max_pixel_spp >= 8' "$WORK/a.json"
expect_exit 2 "adaptive-min-spp 1 is a usage error" -- "$R" trace "$FURNACE" -o "$WORK/x.exr" --adaptive-min-spp 1

# White furnace through the tool: every pixel is 1 within noise; the report carries the figures.
expect_exit 0 "furnace" -- "$R" trace "$FURNACE" -o "$WORK/f.exr" "${SMALL[@]}" --spp 256 --report "$WORK/f.json"
# The console summary (docs/report.md): samples, time and noise as in the report.
expect_summary_number "summary: spp is the report's" "render: path traced: ([0-9]+) spp in" "$WORK/f.json" '.metrics.spp'
expect_summary_number "summary: render time is the report's" "spp in ([0-9.e+-]+) s" "$WORK/f.json" '.metrics.render_time_s'
expect_summary_number "summary: relative noise is the report's" "relative noise ([0-9.e+-]+) " "$WORK/f.json" '.metrics.rel_error'
for key in spp rays samples rays_per_s samples_per_s render_time_s rel_error stop_reason; do
    jq -e ".metrics | has(\"$key\")" "$WORK/f.json" >/dev/null || fail "report lacks metrics.$key"
done
pass "report has the render metrics"
expect_true "two outputs: radiance and its standard error" -- \
    jq -e '[.outputs[].kind] == ["radiance", "radiance_std_error"]' "$WORK/f.json"
expect_true "stderr image written beside the output" -- test -s "$WORK/f_stderr.exr"
expect_true "scene file recorded as input with sha256" -- jq -e '.inputs[0].sha256 | length == 64' "$WORK/f.json"
# Measured on the sphere's own pixels: the central 8x8 block of the 16x16 image lies wholly on
# the sphere (orthographic, 1.2 units high: its corners at +-0.3 reach radius 0.42 < 0.5), so
# the background (exactly 1) cannot hide an error. Each channel's mean there must be 1 within
# four standard errors of that mean, sqrt(mean sigma^2 / 64) from the standard-error image
# (~0.002 at 256 spp), plus 1e-6 for float rounding.
block_avg() { oiiotool "$1" --cut 8x8+4+4 --printstats | sed -n 's/.*Stats Avg: *//p' | awk '{print $1, $2, $3}'; }
read -r -a mean <<<"$(block_avg "$WORK/f.exr")"
oiiotool "$WORK/f_stderr.exr" --powc 2 -o "$WORK/f_var.exr"
read -r -a var <<<"$(block_avg "$WORK/f_var.exr")"
expect_true "furnace: the sphere's pixels average 1 within 4 standard errors (${mean[*]})" -- awk \
    -v m="${mean[*]}" -v v="${var[*]}" 'BEGIN { split(m, a, " "); split(v, b, " "); if (length(a) != 3) exit 1;
        for (c = 1; c <= 3; c++) { d = a[c] - 1; if (d < 0) d = -d; if (d > 4 * sqrt(b[c] / 64) + 1e-6) exit 1 } }'

# Determinism: identical pixels for 1 and 2 threads (idiff with zero tolerance).
SCENE="$SCENES/drape_velvet.toml"
if have_package_file /usr/share/blender/datafiles/studiolights/world/studio.exr blender-data; then
    expect_exit 0 "drape, 1 thread" -- "$R" trace "$SCENE" -o "$WORK/t1.exr" "${SMALL[@]}" --spp 4 --threads 1 --seed 5
    expect_exit 0 "drape, 2 threads" -- "$R" trace "$SCENE" -o "$WORK/t2.exr" "${SMALL[@]}" --spp 4 --threads 2 --seed 5
    expect_true "bit-identical radiance for 1 and 2 threads" -- idiff -fail 0 -warn 0 "$WORK/t1.exr" "$WORK/t2.exr"
    expect_true "bit-identical std error for 1 and 2 threads" -- \
        idiff -fail 0 -warn 0 "$WORK/t1_stderr.exr" "$WORK/t2_stderr.exr"
    expect_true "byte-identical files for 1 and 2 threads (no time stamp)" -- cmp "$WORK/t1.exr" "$WORK/t2.exr"
    expect_exit 0 "drape, another seed" -- "$R" trace "$SCENE" -o "$WORK/t3.exr" "${SMALL[@]}" --spp 4 --seed 6
    expect_exit 2 "another seed gives other pixels (idiff FAILURE = 2)" -- idiff -fail 0 -warn 0 "$WORK/t1.exr" "$WORK/t3.exr"
fi

# Real-time model against the path tracer: both modes, band sweep, maps and side-by-side PNGs.
if have_package_file /usr/share/blender/datafiles/studiolights/world/courtyard.exr blender-data; then
    expect_exit 0 "compare" -- "$R" compare "$SCENES/patch_report.toml" -o "$WORK/p.exr" "${SMALL[@]}" --spp 16 \
        --rt-max-bands 4 --rt-bake-samples 256 --rt-supersample 2 --report "$WORK/p.json"
    for f in rt_consistent.exr rt_seed.exr compare_consistent.png compare_seed.png relerr_seed.exr de2000_consistent.exr; do
        test -s "$WORK/p_$f" || fail "compare output p_$f missing"
    done
    pass "compare writes images, maps and PNGs"
    expect_summary_number "summary: the seed mode's mean relative error is the report's" \
        "truth \\(seed, 3 SH bands\\): mean relative error ([0-9.e+-]+)," "$WORK/p.json" '.metrics.realtime.modes.seed.mean_rel'
    expect_summary_number "summary: the consistent mode's mean Delta E 2000 is the report's" \
        "truth \\(consistent, 3 SH bands\\): .*mean Delta E 2000 ([0-9.e+-]+):" "$WORK/p.json" '.metrics.realtime.modes.consistent.mean_de2000'
    verdict=$(jq -r 'if .metrics.realtime.modes.consistent.mean_de2000 <= 1 then "below a just-noticeable difference" else "visible" end' "$WORK/p.json")
    expect_stderr "truth (consistent, 3 SH bands): .*: $verdict" "summary: the verdict follows the report's mean Delta E 2000"
    expect_true "both modes and 4 band counts in the report" -- \
        jq -e '.metrics.realtime | (.modes | has("consistent") and has("seed")) and (.consistent_by_sh_bands | length == 4)' "$WORK/p.json"
    expect_true "stated exposure and frame time" -- \
        jq -e '.metrics.realtime.exposure > 0 and .metrics.realtime.consistent_by_sh_bands[2].frame_time_ms > 0' "$WORK/p.json"
    # The PNG people look at: 16 px panels enlarged 16x to 256 px (image/figure.h) under a title and
    # captions; the three panels and the colour bar side by side (the bar's ramp and the labels are
    # checked pixel by pixel in lib/image/figure_test.cpp).
    expect_true "side-by-side PNG: three 256 px panels, labelled above" -- \
        bash -c "oiiotool --info '$WORK/p_compare_seed.png' | awk '{ w = \$3; h = \$5; sub(/,/, \"\", h); exit !(w > 3 * 256 && h > 256) }'"
    expect_true "the numeric maps keep the render's size (16 x 16)" -- \
        bash -c "oiiotool --info '$WORK/p_relerr_seed.exr' | grep -Eq '16 x +16,'"
    expect_true "the report says the compare baked its own table, and why" -- \
        jq -e '.metrics.realtime.inputs.brdf_tables.source == "baked" and (.metrics.realtime.inputs.brdf_tables.why | test("--brdf-table"))' "$WORK/p.json"

    # --brdf-table: the compare validates the user's table. Given the table brdf-sh-bake bakes
    # with the compare's own grid, samples and bands, the model's images are the same bytes as
    # the compare's own bake; another table gives other images; its bands bound the sweep.
    MAT="$SRC/configs/materials/report-cook-torrance.toml"
    expect_exit 0 "brdf-sh-bake the compare's table" -- "$BIN/brdf-sh-bake" --material "$MAT" \
        --grid octa:17 --samples 256 --sh-bands 4 -o "$WORK/t4" -q --no-reference-check
    expect_exit 0 "compare --brdf-table" -- "$R" compare "$SCENES/patch_report.toml" -o "$WORK/pt.exr" "${SMALL[@]}" \
        --spp 16 --rt-max-bands 4 --rt-supersample 2 --brdf-table "$WORK/t4.bin" --report "$WORK/pt.json"
    expect_true "the given table's model equals the compare's own bake of it (bytes)" -- \
        cmp "$WORK/p_rt_consistent.exr" "$WORK/pt_rt_consistent.exr"
    # shellcheck disable=SC2016 # $f is jq's
    expect_true "the report names the given table" -- jq -e --arg f "$WORK/t4.bin" \
        '.metrics.realtime.inputs.brdf_tables == {"source": "given", "grid": ["octa:17"], "sh_bands": [4]} and
         ([.inputs[].path] | index($f) != null)' "$WORK/pt.json"
    expect_exit 0 "brdf-sh-bake another table (3 bands, coarse grid, another view)" -- "$BIN/brdf-sh-bake" \
        --material "$MAT" --grid octa:5 --samples 256 --sh-bands 3 --view-deg 30,0 -o "$WORK/t3" -q \
        --no-reference-check
    expect_exit 0 "compare with it" -- "$R" compare "$SCENES/patch_report.toml" -o "$WORK/pc.exr" "${SMALL[@]}" \
        --spp 16 --rt-supersample 2 --brdf-table "$WORK/t3.bin" --report "$WORK/pc.json"
    expect_stderr "BRDF table 1 was baked for a view 30 deg from the camera's" "warns that the table's view is not the camera's"
    expect_true "another table gives another model image" -- bash -c "! cmp -s '$WORK/p_rt_consistent.exr' '$WORK/pc_rt_consistent.exr'"
    expect_true "the sweep stops at the table's 3 bands" -- \
        jq -e '.metrics.realtime.consistent_by_sh_bands | length == 3' "$WORK/pc.json"
    expect_exit 2 "--rt-max-bands past the table's bands" -- "$R" compare "$SCENES/patch_report.toml" -o "$WORK/px.exr" \
        "${SMALL[@]}" --spp 4 --rt-max-bands 5 --brdf-table "$WORK/t3.bin"
    expect_stderr "tables have 3 SH bands" "says the table's bands"
    expect_exit 2 "two tables for one material" -- "$R" compare "$SCENES/patch_report.toml" -o "$WORK/px.exr" \
        "${SMALL[@]}" --spp 4 --brdf-table "$WORK/t3.bin" --brdf-table "$WORK/t4.bin"
    expect_stderr "2 tables for 1 material of" "counts tables and materials (in the singular for one)"
    expect_true "refused before the render: no image" -- test ! -e "$WORK/px.exr"
    expect_exit 2 "--brdf-table with --rt-grid" -- "$R" compare "$SCENES/patch_report.toml" -o "$WORK/px.exr" \
        --brdf-table "$WORK/t3.bin" --rt-grid octa:9
fi

# Stop rules and the quality gate.
expect_exit 0 "target relative error" -- "$R" trace "$FURNACE" -o "$WORK/g.exr" "${SMALL[@]}" --spp 100000 \
    --target-rel-error 0.02 --report "$WORK/g.json"
expect_true "stopped by the target, below it" -- \
    jq -e '.metrics.stop_reason == "target_rel_error" and .metrics.rel_error <= 0.02 and .metrics.spp < 100000' "$WORK/g.json"
expect_exit 0 "time budget" -- "$R" trace "$FURNACE" -o "$WORK/b.exr" "${SMALL[@]}" --spp 1000000 \
    --time-budget-s 0.3 --report "$WORK/b.json"
expect_true "stopped by the time budget" -- jq -e '.metrics.stop_reason == "time_budget"' "$WORK/b.json"
expect_exit 3 "quality gate on relative error" -- "$R" trace "$FURNACE" -o "$WORK/q.exr" "${SMALL[@]}" --spp 2 \
    --max-rel-error 1e-6 --report "$WORK/q.json"
expect_true "gate failure reported, outputs kept" -- \
    bash -c "jq -e '.status == \"quality_gate_failed\" and .exit_code == 3' '$WORK/q.json' && test -s '$WORK/q.exr'"

# Convergence: error falls as 1/sqrt(N) with independent samples.
expect_exit 0 "convergence study" -- "$R" convergence "$FURNACE" -o "$WORK/c.exr" "${SMALL[@]}" --spp 64 \
    --sampler independent --ref-spp 1024 --report "$WORK/c.json"
expect_true "slope within 0.15 of -1/2" -- jq -e '(.metrics.convergence.slope + 0.5 | fabs) < 0.15' "$WORK/c.json"
# Against the exact image (brute-force irradiance): BSDF sampling of the furnace is exact.
expect_exit 2 "irradiance reference needs --no-jitter" -- "$R" convergence "$FURNACE" -o "$WORK/x.exr" "${SMALL[@]}" \
    --ref-irradiance
expect_exit 2 "one reference at a time" -- "$R" convergence "$FURNACE" -o "$WORK/x.exr" "${SMALL[@]}" --no-jitter \
    --ref-irradiance --ref-spp 64
expect_exit 0 "convergence against brute force" -- "$R" convergence "$FURNACE" -o "$WORK/e.exr" "${SMALL[@]}" \
    --spp 4 --no-jitter --strategy bsdf --ref-irradiance --report "$WORK/e.json"
# 1e-4: the brute force's quadrature bound (render/reference.h).
expect_true "exact render, exact reference" -- jq -e '.metrics.convergence.reference_kind == "brute_force_irradiance"
    and ([.metrics.convergence.points[].mean_rel_error] | max) < 1e-4' "$WORK/e.json"
expect_exit 0 "convergence against a file" -- "$R" convergence "$FURNACE" -o "$WORK/g.exr" "${SMALL[@]}" --spp 4 \
    --ref-image "$WORK/c.exr" --report "$WORK/g.json"
expect_true "file reference reported" -- jq -e '.metrics.convergence.reference_kind == "file"' "$WORK/g.json"
expect_exit 1 "reference of another size" -- "$R" convergence "$FURNACE" -o "$WORK/h.exr" --width-px 8 --height-px 8 \
    --ref-image "$WORK/c.exr"
expect_stderr "c.exr: reference is 16x16" "error names the reference file and both sizes"

# Scene-file errors name the file, the line, the table and the key; exit 1; no output.
sed 's/width_px = 64/widht_px = 64/' "$FURNACE" > "$WORK/typo.toml"
expect_exit 1 "unknown key in the scene" -- "$R" trace "$WORK/typo.toml" -o "$WORK/typo.exr"
expect_stderr "typo.toml:10: \[camera\] unknown key 'widht_px'" "error names file, line, table and key"
expect_true "no output after failure" -- test ! -e "$WORK/typo.exr"
sed 's/radiance = \[1, 1, 1\]/path = "nowhere.exr"/' "$FURNACE" > "$WORK/noenv.toml"
expect_exit 1 "missing environment map" -- "$R" trace "$WORK/noenv.toml" -o "$WORK/noenv.exr"
expect_stderr "nowhere.exr" "error names the missing map"

# Config files: keys are long options; CLI overrides the config.
printf 'spp = 3\nwidth-px = 8\nheight-px = 8\n' > "$WORK/cfg.toml"
expect_exit 0 "config file" -- "$R" trace "$FURNACE" -o "$WORK/k.exr" --config "$WORK/cfg.toml" --report "$WORK/k.json"
expect_true "config applied" -- jq -e '.metrics.spp == 3 and .metrics.width_px == 8' "$WORK/k.json"
expect_exit 0 "CLI overrides config" -- "$R" trace "$FURNACE" -o "$WORK/k.exr" --config "$WORK/cfg.toml" --spp 5 --report "$WORK/k.json"
expect_true "override wins" -- jq -e '.metrics.spp == 5 and .config.spp == 5' "$WORK/k.json"

finish
