#!/usr/bin/env bash
# validate-pair: one fabric bundle under one environment: the path-traced truth against the
# app's real-time model and its exported GLES shaders run through EGL, into OUTDIR/summary.json.
#   pipelines/validate-pair.sh FABRIC_BUNDLE ENVIRONMENT OUTDIR [RAW_BTF [WEAVE]]
#                                                                    (binaries from ${INLIGHT_BIN})
# The scene is the app's case: the fabric on the screen (z = 0, facing +z), seen along -z by an
# orthographic camera, a PATCH_WIDTH_M-wide patch (0.1 m) showing the bundle's textures tiled at
# its tile_size_m, lit by the environment (lat-long, device frame). Render options come from
# ${VALIDATE_RENDER_CONFIG:-ROOT/configs/pipelines/validate.toml}; the real-time model bakes the BRDF
# table with the bundle's grid and samples per normal, so it is the table the bundle ships.
# Two optional studies join the pair's summary:
#   - the band budget (VALIDATE_MAX_ERROR, default 0.01; 0 = off): envmap-project --max-error on
#     the environment with the bundle's BRDF table, i.e. the fewest SH bands and dominant lights
#     whose irradiance and outgoing-radiance error meet the budget (docs/budget.md);
#   - the error decomposition (VALIDATE_DECOMPOSE=1): render compare --decompose, the model's
#     error split into grid, SH truncation, fixed view and visibility (docs/render.md).
# A bundle that ships a BTF is also shaded as a BTF (render shade-btf), when RAW_BTF, the
# capture it was compressed from, is given: the woven geometry (WEAVE, default the fabric file
# the capture names) path-traced under the environment through the BTF's rectified camera is the
# truth; the raw BTF, the bundle's compressed BTF and each prefix of its stream are shaded and
# measured against it and against the raw shading (docs/pipelines.md says what each measures);
# when the bundle ships the BTF's GLES shaders (btf-gles.json), their pictures too, drawn through
# EGL at one fragment per texel (docs/btf-gles.md, "Against the truth").
# Bytes per stream prefix come from the bundle manifest; VALIDATE_BTF_SPP (default 256) and
# VALIDATE_BTF_VIEWS (a view directions file, "theta phi" in degrees a line; default the pair's
# own view, along the normal, then theta 45 phi 40 and a grazing theta 75 phi 0, to show the
# BTF's view dependence: about 0.5 s of CPU more per view and pair, docs/pipelines.md).
# Quality gate (docs/pipelines.md "Quality gate"): VALIDATE_WARN_MEAN_REL, VALIDATE_FAIL_MEAN_REL,
# VALIDATE_WARN_DE2000 and VALIDATE_FAIL_DE2000 (unset or empty = none) are render compare's
# --warn-mean-rel ... --fail-de2000 on every image the app can show (VALIDATE_GATE_MODES: its
# --gate-modes); the verdict goes into summary.json, and on FAILURE, after the summary is
# written, OUTDIR/gate_failed.json names the pair and its figures and the script exits 3.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 3 5 "FABRIC_BUNDLE ENVIRONMENT OUTDIR [RAW_BTF [WEAVE]]"
BUNDLE=$(abs_dir "$1")
ENV_MAP=$(abs_dir "$(dirname "$2")")/$(basename "$2")
OUTDIR=$(out_dir "$3")
BIN=$(tool_bin)
CONFIG=${VALIDATE_RENDER_CONFIG:-$ROOT/configs/pipelines/validate.toml}
PATCH_WIDTH_M=0.1
M="$BUNDLE/manifest.json"

# The gate's thresholds, checked before any work: numbers >= 0, warn <= fail.
gate=()
for metric in MEAN_REL:mean-rel DE2000:de2000; do
    warn_var=VALIDATE_WARN_${metric%%:*} fail_var=VALIDATE_FAIL_${metric%%:*}
    for var in "$warn_var" "$fail_var"; do
        v=${!var:-}
        [ -n "$v" ] || continue
        if ! [[ $v =~ ^([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$ ]]; then
            echo "validate-pair: $var '$v': expected a number >= 0" >&2
            exit 2
        fi
        kind=${var#VALIDATE_}
        kind=${kind%%_*}
        gate+=("--${kind,,}-${metric#*:}" "$v")
    done
    if [ -n "${!warn_var:-}" ] && [ -n "${!fail_var:-}" ] &&
        awk -v w="${!warn_var}" -v f="${!fail_var}" 'BEGIN { exit !(w + 0 > f + 0) }'; then
        echo "validate-pair: $warn_var ${!warn_var} exceeds $fail_var ${!fail_var}: the warning threshold must not be above the failure threshold" >&2
        exit 2
    fi
done
[ -n "${VALIDATE_GATE_MODES:-}" ] && gate+=(--gate-modes "$VALIDATE_GATE_MODES")
rm -f "$OUTDIR/gate_failed.json"  # a failure of an earlier run is not this run's

# The bundle is checked before anything is rendered from it.
"$BIN/bundle" verify "$BUNDLE" -q --report "$OUTDIR/verify.json"
id=$(jq -r '.id' "$M")
env_name=$(basename "$ENV_MAP")
env_name=${env_name%.*}
role() { jq -r --arg r "$1" '[.files[] | select(.role == $r)][0].path // empty' "$M"; }
albedo=$(role albedo)
normal=$(role normal)
uv=$(jq --argjson w "$PATCH_WIDTH_M" '$w / .properties.tile_size_m' "$M")
{
    echo "# validate-pair: $id under $env_name (generated)"
    echo "[environment]"
    echo "path = \"$ENV_MAP\""
    echo "[camera]"
    echo "projection = \"orthographic\""
    echo "ortho_height = 1.0"
    echo "[material.fabric]"
    echo "file = \"$BUNDLE/$(role material)\""
    echo "albedo = [1, 1, 1]"
    echo "albedo_texture = \"$BUNDLE/$albedo\""
    [ -n "$normal" ] && echo "normal_texture = \"$BUNDLE/$normal\""
    echo "uv_scale = [$uv, $uv]"
    echo "[[object]]"
    echo "name = \"fabric\""
    echo "shape = \"patch\""
    echo "material = \"fabric\""
    echo "size = [1, 1]"
} > "$OUTDIR/scene.toml"

decompose=()
[ "${VALIDATE_DECOMPOSE:-0}" = 1 ] && decompose=(--decompose)
# Exit 3 is a failed quality gate (this gate, or the config's --max-rel-error on the truth's
# noise): the outputs and report are written, so the pair is still summarised, then fails.
# The GLES column draws the bundle's variants with the texture filter they were exported with.
filter=()
index=$(role shader_index)
if [ -n "$index" ]; then
    first=$(jq -r '.variants[0].manifest // empty' "$BUNDLE/$index")
    tf=$([ -n "$first" ] && jq -r '.texture_filter // empty' "$BUNDLE/$(dirname "$index")/$first")
    [ -n "$tf" ] && filter=(--gles-texture-filter "$tf")
fi
compare_rc=0
"$BIN/render" compare "$OUTDIR/scene.toml" -o "$OUTDIR/render.exr" --config "$CONFIG" \
    "${decompose[@]}" "${gate[@]}" "${filter[@]}" --rt-grid "$(jq -r '.properties.brdf_grid' "$M")" \
    --rt-bake-samples "$(jq '.properties.brdf_samples_per_normal' "$M")" \
    -q --report "$OUTDIR/render.json" || compare_rc=$?
if [ "$compare_rc" -ne 0 ] && [ "$compare_rc" -ne 3 ]; then
    echo "validate-pair: render compare failed (exit $compare_rc; $OUTDIR/render.json)" >&2
    exit "$compare_rc"
fi

# The band budget of this environment for this fabric's table: exit 3 means no candidate meets
# it (the report then holds the least error), which is a finding, not a failure.
MAX_ERROR=${VALIDATE_MAX_ERROR:-0.01}
echo '{}' > "$OUTDIR/budget.json.tmp"
if [ "$(jq -n --argjson e "$MAX_ERROR" '$e > 0')" = true ]; then
    rc=0
    "$BIN/envmap-project" "$ENV_MAP" -o "$OUTDIR/budget_sh.json" --max-error "$MAX_ERROR" \
        --brdf-table "$BUNDLE/$(role brdf_sh_table)" --material "$BUNDLE/$(role material)" \
        -q --report "$OUTDIR/budget.json.tmp" || rc=$?
    if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
        echo "validate-pair: envmap-project --max-error failed (exit $rc)" >&2
        exit "$rc"
    fi
fi
mv "$OUTDIR/budget.json.tmp" "$OUTDIR/budget.json"

# The BTF shaded as a BTF: the bundle's btf/ files as the app receives them, with the
# bytes a client holds after each stream prefix summed from the bundle manifest (render reads
# them from streaming.tsv), shaded from 0, G, 2G, ... components (G groups: about one more
# component per group each step) and from the whole stream.
echo '{}' > "$OUTDIR/btf.json.tmp"
if [ -n "$(role btf_manifest)" ] && [ $# -ge 4 ]; then
    RAW_BTF=$(cd "$4" && pwd)
    WEAVE=${5:-$(jq -r '.fabric // empty' "$RAW_BTF/capture.json")}
    if [ ! -f "$WEAVE" ]; then
        echo "validate-pair: $RAW_BTF/capture.json: its fabric '$WEAVE' not found (give the weave file as WEAVE)" >&2
        exit 2
    fi
    S="$OUTDIR/btf-stream"
    rm -rf "$S"
    mkdir -p "$S"
    btf_dir=$(dirname "$(role btf_manifest)")
    while read -r p; do
        mkdir -p "$S/$(dirname "${p#"$btf_dir"/}")"
        cp "$BUNDLE/$p" "$S/${p#"$btf_dir"/}"
    done < <(jq -r '.files[] | select(.role | startswith("btf_")) | .path' "$M")
    # shellcheck disable=SC2016  # $base and $c are jq variables
    jq -r '([.files[] | select(.role == "btf_manifest" or .role == "btf_weights" or .role == "btf_mean")
             | .bytes] | add) as $base
           | [.files[] | select(.role == "btf_component")] | sort_by(.stream_index) as $c
           | "# components_sent\tbytes_sent (sums of the bundle manifest'"'"'s file sizes)", "0\t\($base)",
             (range(1; ($c | length) + 1) as $n | "\($n)\t\($base + ([$c[:$n][].bytes] | add))")' \
        "$M" > "$S/streaming.tsv"
    n=$(jq '[.files[] | select(.role == "btf_component")] | length' "$M")
    g=$(jq '[.files[] | select(.role == "btf_mean")] | length' "$M")
    points=$(jq -rn --argjson n "$n" --argjson g "$g" '[range(0; $n; $g), $n] | unique | join(",")')
    views=${VALIDATE_BTF_VIEWS:-$OUTDIR/btf-views.txt}
    [ -n "${VALIDATE_BTF_VIEWS:-}" ] || printf '0 0\n45 40\n75 0\n' > "$views"
    # A bundle that ships the BTF's GLES shaders (btf-gles.json): its pictures drawn through EGL at
    # its own SH bands, each prefix and the whole stream (render checks the shipped files are the
    # export it draws).
    gles=()
    if [ -s "$S/btf-gles.json" ]; then
        gles=(--gles-bands "$(jq '.matrices.bands' "$S/btf-gles.json")")
    fi
    "$BIN/render" shade-btf "$WEAVE" --btf "$RAW_BTF" --btf-compressed "$S" --shade-stream "$points" \
        --environment "$ENV_MAP" --shade-views "$views" --spp "${VALIDATE_BTF_SPP:-256}" "${gles[@]}" \
        -o "$OUTDIR/btf" -q --report "$OUTDIR/btf.json.tmp"
fi
mv "$OUTDIR/btf.json.tmp" "$OUTDIR/btf.json"

# GLES output: render compare also draws the scene with the exported shaders through
# EGL (metrics.realtime.gles): the third column, beside the CPU model and the truth.
jq -n --slurpfile r "$OUTDIR/render.json" --slurpfile b "$M" --arg env "$env_name" \
    --arg envpath "$ENV_MAP" --slurpfile budget "$OUTDIR/budget.json" --slurpfile btf "$OUTDIR/btf.json" '
    $r[0].metrics as $m | $m.realtime as $rt | $b[0] as $bundle |
    {fabric: $bundle.id, fabric_name: $bundle.name, environment: $env, environment_path: $envpath,
     bundle_bytes: $bundle.total_bytes, sh_bands_shipped: $bundle.properties.sh_bands,
     truth: {spp: $m.spp, rel_noise: $m.rel_error, render_time_s: $m.render_time_s,
             stop_reason: $m.stop_reason},
     consistent: $rt.modes.consistent, seed: $rt.modes.seed,
     gate: ($rt.gate // null), gate_error: (if $r[0].status == "quality_gate_failed" then $r[0].error else null end),
     one_fragment_per_pixel: ($rt.consistent_one_fragment_per_pixel // null),
     by_sh_bands: [$rt.consistent_by_sh_bands[] | {sh_bands, mean_rel, mean_de2000, max_de2000,
                                                    frame_time_ms}],
     gles: (if $rt.gles then
              {driver: $rt.gles.driver,
               variants: [$rt.gles.variants[] | {variant, glsl_version, mode, sh_bands, mean_rel,
                          mean_de2000, max_de2000, frame_time_ms,
                          cpu_model_fraction_within_1e_3: .["cpu_model_fraction_within_1e-3"]}]}
            else null end),
     budget: ($budget[0].metrics.environments[0].budget // null | if . then
              {max_error: .max_error, met, metric, sh_bands: .chosen.sh_bands,
               lights: .chosen.lights, error: .chosen.error, cost: .chosen.cost,
               pure_sh: ([.candidates[] | select(.lights == 0 and .meets)] | min_by(.sh_bands)
                         | if . then {sh_bands, error} else null end)} else null end),
     decomposition: ($rt.decomposition // null | if . then
              {truth_noise, visibility, fixed_view, map_discretisation, pixel_footprint,
               by_sh_bands} else null end),
     has_btf: ([$bundle.files[] | select(.role == "btf_manifest")] | length > 0),
     btf: ($btf[0].metrics.btf_shade // null | if . then
              {spp, raw_btf: $btf[0].argv[($btf[0].argv | index("--btf")) + 1],
               weave: $btf[0].argv[2], bytes_shipped: .results[0].compressed[0].stored_bytes,
               components_per_group: .results[0].compressed[0].components_per_group,
               views: [[$btf[0].outputs[] | select(.kind == "comparison") | .path | split("/") | last] as $png
                       | .results | to_entries[] | .key as $i | .value | .compressed[0] as $c |
                       {view_deg, truth_noise: .truth_rel_error, below_horizon_share,
                        compare_image: $png[$i],
                        raw: {mean_rel, mean_de2000, mean_luminance_rel_diff},
                        shipped: {components_sent: ($c.stream | last | .components_sent),
                                  bytes: $c.stored_bytes, mean_rel: $c.mean_rel,
                                  mean_de2000: $c.mean_de2000,
                                  mean_luminance_rel_diff: $c.mean_luminance_rel_diff,
                                  vs_raw_rel_rmse: $c.vs_raw.rel_rmse},
                        stream: [$c.stream[] | {components_sent, bytes_sent, mean_rel, mean_de2000,
                                                mean_luminance_rel_diff, vs_raw_rel_rmse: .vs_raw.rel_rmse}],
                        gles: [$c.gles // [] | .[] | {variant, components_sent, bytes_sent, mean_rel, mean_de2000,
                                                      mean_luminance_rel_diff,
                                                      vs_cpu_rel_rmse: .vs_cpu_compressed.rel_rmse}]}],
               gles_bands: ($btf[0].argv | index("--gles-bands") as $i | if $i then $btf[0].argv[$i + 1] | tonumber else null end)}
            else null end),
     images: {compare_consistent: "render_compare_consistent.png",
              compare_seed: "render_compare_seed.png",
              compare3_consistent: "render_compare3_es300-consistent-b3-highp.png",
              compare3_seed: "render_compare3_es300-seed-b3-highp.png"}}' > "$OUTDIR/summary.json.tmp"
mv "$OUTDIR/summary.json.tmp" "$OUTDIR/summary.json"

verdict=$(jq -r '.gate.verdict // empty' "$OUTDIR/summary.json")
[ "$verdict" = WARNING ] &&
    echo "validate-pair: $id under $env_name: quality gate WARNING ($(jq -r '.gate.decided_by' "$OUTDIR/summary.json"))" >&2
if [ "$compare_rc" -eq 3 ]; then
    jq '{fabric, environment, error: .gate_error, gate}' "$OUTDIR/summary.json" > "$OUTDIR/gate_failed.json.tmp"
    mv "$OUTDIR/gate_failed.json.tmp" "$OUTDIR/gate_failed.json"
    echo "validate-pair: $id under $env_name: quality gate failed: $(jq -r '.gate_error' "$OUTDIR/summary.json")" >&2
    exit 3
fi
