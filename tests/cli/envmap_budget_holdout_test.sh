#!/usr/bin/env bash
# envmap-project --max-error holds on normals it never saw: the plain command's choice, scored
# again by --holdout-normals on 2000 normals of a turned Fibonacci set (none of them scored or
# fitted on), stays within the budget. The three maps are those whose choices missed 1% at 2000
# normals when the budget scored on 134 (docs/budget.md, "What the plain command guarantees").
# shellcheck disable=SC2016  # $vars in the single-quoted jq programs are jq's own
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
EP="$BIN/envmap-project"
MK="$TBIN/inlight_make_test_image"

# Options are checked before any work.
"$MK" "$WORK/sky.exr" 64 32 1 40 30 300
for bad in "--budget-margin nan" "--budget-margin 0.5" "--budget-margin -0.1" "--holdout-normals -1"; do
    # shellcheck disable=SC2086  # the option and its value are two words
    expect_exit 2 "$bad refused" -- "$EP" "$WORK/sky.exr" -o "$WORK/bad.json" --max-error 0.01 $bad
    expect_stderr "${bad%% *}" "the message names ${bad%% *}"
    expect_true "nothing written for $bad" -- test ! -e "$WORK/bad.json"
done

# holdout_case NAME MAP [OPTIONS...]: the plain command (+ OPTIONS) with 2000 held-out normals.
holdout_case() {
    local name=$1 map=$2
    shift 2
    expect_exit 0 "$name: budget met" -- "$EP" "$map" -o "$WORK/${name}_sh.json" --max-error 0.01 \
        --holdout-normals 2000 --report "$WORK/$name.json" -q "$@"
    expect_true "$name: scored within the margin's limit, on 1030 normals" -- jq -e '.metrics.environments[0].budget
        | .met and .normals == 1030 and .chosen.error <= .scored_limit
          and .scored_limit == .max_error * (1 - .scoring_margin)' "$WORK/$name.json"
    # The goal itself, on normals the choice was neither scored nor fitted on.
    expect_true "$name: within 1% on 2000 held-out normals" -- jq -e '.metrics.environments[0].budget
        | .holdout.normals == 2000 and .holdout.error <= .max_error' "$WORK/$name.json"
}

STUDIO=/usr/share/blender/datafiles/studiolights/world/studio.exr
NIGHT=/usr/share/blender/datafiles/studiolights/world/night.exr
if have_package_file "$STUDIO" blender-data; then
    holdout_case studio "$STUDIO"
    holdout_case night_meanrel "$NIGHT" --error-metric mean-rel --sh-fit metric --max-lights 4
fi
if have_shared_data probes-latlong/ennis.hdr; then
    holdout_case ennis "$INLIGHT_SHARED_DIR/data/probes-latlong/ennis.hdr"
fi
finish
