#!/usr/bin/env bash
# texture-filter-table: texture filtering at one fragment per pixel against the supersampled
# real-time model, both against the path-traced truth (docs/gles.md, "Texture filtering").
#   pipelines/texture-filter-table.sh BUNDLES_DIR OUTDIR [SIZES [ENVIRONMENTS]]
#                                                       (binaries from ${INLIGHT_BIN})
# BUNDLES_DIR holds fabric bundles (pipelines/bake-fabric.sh); each is drawn as validate-pair
# draws it, and configs/scenes/patch_city.toml beside them. SIZES (default "64 128 512") are
# image sides in pixels; ENVIRONMENTS (default city forest studio, Blender's studio lights)
# lat-long maps. Truth: TABLE_SPP (default 64) samples per pixel. Writes OUTDIR/table.tsv: per
# scene, environment and size the mean relative error and mean dE2000 of the supersampled model
# (4 x 4) and of each filtering at one fragment per pixel, and the ratio of the errors.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 2 4 "BUNDLES_DIR OUTDIR [SIZES [ENVIRONMENTS]]"
BUNDLES=$(abs_dir "$1")
OUTDIR=$(out_dir "$2")
SIZES=${3:-64 128 512}
WORLD=/usr/share/blender/datafiles/studiolights/world
ENVS=${4:-$WORLD/city.exr $WORLD/forest.exr $WORLD/studio.exr}
BIN=$(tool_bin)
export INLIGHT_BIN=$BIN

row() {  # scene env size render.json
    jq -r --arg s "$1" --arg e "$2" --arg px "$3" '.metrics.realtime as $rt
        | $rt.consistent_one_fragment_per_pixel | to_entries[]
        | [$s, $e, $px, .key, $rt.ground_truth_spp, ($rt.modes.consistent.mean_rel * 1e4 | round / 1e4),
           ($rt.modes.consistent.mean_de2000 * 1e3 | round / 1e3), (.value.mean_rel * 1e4 | round / 1e4),
           (.value.mean_de2000 * 1e3 | round / 1e3), (.value.ratio_to_supersampled * 1e3 | round / 1e3)]
        | @tsv' "$4"
}
printf 'scene\tenvironment\tpx\tfiltering_1fpp\ttruth_spp\tss4_mean_rel\tss4_mean_de2000\tmean_rel\tmean_de2000\tratio\n' \
    > "$OUTDIR/table.tsv.tmp"
for px in $SIZES; do
    cfg="$OUTDIR/render-$px.toml"
    printf 'spp = %s\nwidth-px = %s\nheight-px = %s\nrt-max-bands = 3\nrt-supersample = 4\n' \
        "${TABLE_SPP:-64}" "$px" "$px" > "$cfg"
    for env in $ENVS; do
        e=$(basename "$env" .exr)
        d="$OUTDIR/patch_city-$e-$px"
        mkdir -p "$d"
        sed -e "s|^path = .*|path = \"$env\"|" -e "s|\"\.\./materials/|\"$ROOT/configs/materials/|" "$ROOT/configs/scenes/patch_city.toml" > "$d/scene.toml"
        "$BIN/render" compare "$d/scene.toml" -o "$d/render.exr" --config "$cfg" -q --report "$d/render.json"
        row patch_city "$e" "$px" "$d/render.json" >> "$OUTDIR/table.tsv.tmp"
        for b in "$BUNDLES"/*/; do
            id=$(basename "$b")
            d="$OUTDIR/$id-$e-$px"
            VALIDATE_RENDER_CONFIG=$cfg VALIDATE_MAX_ERROR=0 "$ROOT/pipelines/validate-pair.sh" \
                "$b" "$env" "$d" > /dev/null
            row "$id" "$e" "$px" "$d/render.json" >> "$OUTDIR/table.tsv.tmp"
        done
    done
done
mv "$OUTDIR/table.tsv.tmp" "$OUTDIR/table.tsv"
