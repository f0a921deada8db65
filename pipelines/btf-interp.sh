#!/usr/bin/env bash
# Angular interpolation and compressed-BTF shading measured where the truth is known
# (docs/btf-interpolation.md). Captures a fabric's UBO2003 BTF (float EXR) and three pair sets
# rendered directly (configs/btf/interp-{offgrid,beyond,ongrid}-pairs.txt, another seed), compresses
# the BTF with btf-pca, interpolates every pair from the raw and the compressed BTF with both
# schemes and prints the errors; then shades raw and compressed under environments against the
# path-traced truth. Steps whose output exists are skipped.
#   pipelines/btf-interp.sh [BUILD] [OUT] [SIZE_PX] [SPP] [FABRIC] [COMPONENTS] [TRUTH_SPP] [ENV...]
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
BUILD=${1:-$ROOT/build}
OUT=${2:-out/btf-interp}
SIZE=${3:-64}
SPP=${4:-8}
FABRIC=${5:-$ROOT/configs/fabrics/wool-twill.toml}
C=${6:-16}
TSPP=${7:-128}
shift $(( $# < 7 ? $# : 7 ))
R="$BUILD/bin/render"
P="$BUILD/bin/btf-pca"
CAP=(--width-px "$SIZE" --height-px "$SIZE" --spp "$SPP" --btf-format exr --threads 2 -q)
mkdir -p "$OUT"
[ -s "$OUT/grid/capture.json" ] ||
    "$R" capture-btf "$FABRIC" -o "$OUT/grid" "${CAP[@]}" --seed 1 --report "$OUT/grid.json"
for s in offgrid beyond ongrid; do
    [ -s "$OUT/$s/capture.json" ] || "$R" capture-btf "$FABRIC" -o "$OUT/$s" \
        --btf-pairs "$ROOT/configs/btf/interp-$s-pairs.txt" "${CAP[@]}" --seed 2 --report "$OUT/$s.json"
done
for c in "$C" 4; do
    [ -s "$OUT/pca$c/btf-pca.json" ] ||
        "$P" compress "$OUT/grid" -o "$OUT/pca$c" -k 3 -c "$c" --report "$OUT/pca$c.json" -q
done
echo "| data | scheme | pairs | MAE Lab | mean dE2000 | RMSE 8-bit | rel. RMSE | error of the image mean | pairs moved onto the dome |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for src in grid "pca$C"; do
    for scheme in nearest thesis delaunay; do
        for s in offgrid beyond ongrid; do
            r="$OUT/i-$src-$scheme-$s"
            [ -s "$r.json" ] || "$P" interpolate "$OUT/$src" --pairs "$ROOT/configs/btf/interp-$s-pairs.txt" \
                --scheme "$scheme" --truth "$OUT/$s" -o "$r" --report "$r.json" -q
            jq -r --arg src "$src" --arg s "$s" '.metrics.interpolation as $m | $m.mean_errors as $e |
                "| \($src) | \($m.scheme) | \($s) (\($m.pairs)) | \($e.mae_lab * 100 | round / 100) | \($e.delta_e2000_mean * 100 | round / 100) | \($e.rmse_rgb8 * 100 | round / 100) | \($e.rel_rmse * 1000 | round / 1000) | \($e.mean_rel_diff * 1000 | round / 10)% | \($m.pairs_outside_measured_region) |"' "$r.json"
        done
    done
done
W=/usr/share/blender/datafiles/studiolights/world
ENVS=("$@")
[ ${#ENVS[@]} -gt 0 ] || ENVS=("$W/city.exr" "$W/forest.exr")
args=()
for e in "${ENVS[@]}"; do args+=(--environment "$e"); done
[ -s "$OUT/shade.json" ] || "$R" shade-btf "$FABRIC" --btf "$OUT/grid" --btf-compressed "$OUT/pca$C" \
    --btf-compressed "$OUT/pca4" "${args[@]}" -o "$OUT/shade" --spp "$TSPP" --threads 2 --report "$OUT/shade.json" -q
echo
echo "| environment | view (deg) | BTF | stored MiB | mean rel. error vs truth | mean dE2000 vs truth | mean luminance vs truth | rel. RMSE vs raw BTF |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
jq -r '.metrics.btf_shade.results[] | . as $r | ($r.environment | split("/") | last) as $env |
    "| \($env) | \($r.view_deg[0]), \($r.view_deg[1]) | raw | - | \($r.mean_rel * 1000 | round / 1000) | \($r.mean_de2000 * 100 | round / 100) | \($r.mean_luminance_rel_diff * 1000 | round / 10)% | 0 |",
    ($r.compressed[] | "| \($env) | \($r.view_deg[0]), \($r.view_deg[1]) | C = \(.components_per_group | max) | \(.stored_bytes / 1048576 * 100 | round / 100) | \(.mean_rel * 1000 | round / 1000) | \(.mean_de2000 * 100 | round / 100) | \(.mean_luminance_rel_diff * 1000 | round / 10)% | \(.vs_raw.rel_rmse * 1000 | round / 1000) |")' "$OUT/shade.json"
# Views between the measured ones under the first environment: the BTF's views blended four ways.
echo
echo "| view blend | view (deg) | mean rel. error vs truth | mean dE2000 vs truth | mean luminance vs truth |"
echo "| --- | --- | --- | --- | --- |"
for blend in "--view-neighbours 1" "--view-neighbours 3" "--view-interp thesis" "--view-interp delaunay"; do
    tag=${blend// /_}
    # shellcheck disable=SC2086  # $blend is an option and its value
    [ -s "$OUT/views$tag.json" ] || "$R" shade-btf "$FABRIC" --btf "$OUT/grid" --environment "${ENVS[0]}" $blend \
        --shade-views "$ROOT/configs/btf/interp-shade-views.txt" -o "$OUT/views$tag" --spp "$TSPP" --threads 2 \
        --report "$OUT/views$tag.json" -q
    jq -r --arg b "$blend" '.metrics.btf_shade.results[] |
        "| \($b) | \(.view_deg[0]), \(.view_deg[1]) | \(.mean_rel * 1000 | round / 1000) | \(.mean_de2000 * 100 | round / 100) | \(.mean_luminance_rel_diff * 1000 | round / 10)% |"' "$OUT/views$tag.json"
done
# The compressed BTF as a client holds it while components arrive: stream prefixes under the
# first environment (k = 3: 27 groups, so 27 n components is about n per group).
echo
echo "| view (deg) | components sent | MiB sent | mean rel. error vs truth | mean dE2000 vs truth | mean luminance vs truth | rel. RMSE vs raw BTF |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
[ -s "$OUT/stream.json" ] || "$R" shade-btf "$FABRIC" --btf "$OUT/grid" --btf-compressed "$OUT/pca$C" \
    --shade-stream 0,27,54,108,216,432 --environment "${ENVS[0]}" -o "$OUT/stream" --spp "$TSPP" --threads 2 \
    --report "$OUT/stream.json" -q
jq -r '.metrics.btf_shade.results[] | . as $r | $r.compressed[0].stream[] |
    "| \($r.view_deg[0]), \($r.view_deg[1]) | \(.components_sent) | \(.bytes_sent / 1048576 * 100 | round / 100) | \(.mean_rel * 1000 | round / 1000) | \(.mean_de2000 * 100 | round / 100) | \(.mean_luminance_rel_diff * 1000 | round / 10)% | \(.vs_raw.rel_rmse * 1000 | round / 1000) |"' "$OUT/stream.json"
