#!/usr/bin/env bash
# The budget's goal in the mean of per-normal relative errors (docs/budget.md, "In mean-rel, with
# the fit to the metric"): with `--error-metric mean-rel --sh-fit metric --max-lights 4` each of
# the eight blender-data HDRIs and the five probes of ../shared/data (grace's run is in
# envmap_budget_fit_test.sh) is within 1% at no more shader cost than 5 bands of pure SH (129
# operations), measured at the 1030 validation normals (none of them among the 518 fit
# normals). No tolerance beyond the goal's own 1%. The budget's choice (the cheapest
# configuration meeting 1%) measured 0.60-0.97% (ennis 0.97% at 3 + 3, courtyard 0.96% at
# 3 + 1), so a small change of the fit may change which configuration is chosen; what this
# holds is that one within 129 operations meets 1% (the least within that cost measured
# 0.15-0.88%).
# Slow (1.2 CPU-min; 80-110 s wall at load 3-5): the 1024x512 maps' brute force and the fits.
# shellcheck disable=SC2016  # $vars in the single-quoted jq programs are jq's own
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
EP="$BIN/envmap-project"

# meets NAME MAP: the budget meets 1% in mean-rel within 129 operations.
meets() {
    local name=$1 map=$2
    expect_exit 0 "$name: 1% mean-rel met" -- "$EP" "$map" -o "$WORK/${name}_sh.json" \
        --max-error 0.01 --error-metric mean-rel --sh-fit metric --max-lights 4 --budget-max-bands 5 \
        --budget-normals 1024 --report "$WORK/$name.json" -q
    expect_true "$name: chosen within 129 operations (5 bands of pure SH), mean-rel <= 1%" -- \
        jq -e '.metrics.environments[0].budget | .met and .metric == "mean-rel" and .normals == 1030
          and .chosen.error <= 0.01 and .chosen.cost.operations <= ([.candidates[]
          | select(.lights == 0 and .sh_bands == 5) | .cost.operations] | first)
          and .chosen.cost.operations <= 129' "$WORK/$name.json"
}

BLENDER=/usr/share/blender/datafiles/studiolights/world
for name in city courtyard forest interior night studio sunrise sunset; do
    if have_package_file "$BLENDER/$name.exr" blender-data; then meets "$name" "$BLENDER/$name.exr"; fi
done
# grace: the same command (--budget-normals 1024 is the default) with a stronger check (3 + 3
# within 1% at 108 operations) is envmap_budget_fit_test.sh's "grace mean-rel,
# --budget-max-bands 5": not run twice in the suite.
for name in ennis pisa uffizi wells; do
    if have_shared_data "probes-latlong/$name.hdr"; then
        meets "$name" "$INLIGHT_SHARED_DIR/data/probes-latlong/$name.hdr"
    fi
done
finish
