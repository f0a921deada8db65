#!/usr/bin/env bash
# envmap-project --max-error on real maps: the extracted lights fitted by least squares against the
# brute-force irradiance (--light-fit-normals, docs/budget.md "The fit") meet 1% with one light over
# 3 bands where the extracted region's cap and 5 bands of pure SH do not, and grace with two
# (figures: docs/budget/tradeoff.md).
# shellcheck disable=SC2016  # $vars in the single-quoted jq programs are jq's own
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
EP="$BIN/envmap-project"

# budget_case NAME MAP: one light (an exact cap) over at most 5 bands, fitted and as found.
budget_case() {
    local name=$1 map=$2
    expect_exit 0 "$name: 1% met with the fitted light" -- "$EP" "$map" -o "$WORK/${name}_sh.json" \
        --max-error 0.01 --max-lights 1 --budget-max-bands 5 --light-shading cap --report "$WORK/$name.json" -q
    expect_true "$name: one fitted light over 3 bands, within 1%" -- jq -e '.metrics.environments[0].budget
        | .met and .chosen.lights == 1 and .chosen.sh_bands == 3 and .chosen.lights_fitted
          and .chosen.error <= 0.01 and .chosen.cost.operations <= ([.candidates[]
          | select(.lights == 0 and .sh_bands == 5) | .cost.operations] | first)' "$WORK/$name.json"
    expect_true "$name: the output holds the fitted light" -- jq -e --slurpfile r "$WORK/$name.json" \
        '(.lights | length) == 1 and .lights[0].angular_radius_deg
          == ($r[0].metrics.environments[0].budget.candidates[] | select(.lights == 1 and .sh_bands == 3)
              | .light_set[0].angular_radius_deg)' "$WORK/${name}_sh.json"
    expect_exit 0 "$name: the region's cap as found" -- "$EP" "$map" \
        -o "$WORK/${name}_region.json" --max-error 0.01 --max-lights 1 --budget-max-bands 5 \
        --light-fit-normals 0 --light-shading cap --report "$WORK/${name}_r.json" -q
    expect_true "$name: as found, nothing within 5 bands' cost meets 1% (region cap + 3 bands, pure 5 bands)" -- \
        jq -e '.metrics.environments[0].budget.candidates
          | ([.[] | select(.lights == 0 and .sh_bands == 5) | .cost.operations] | first) as $cap
          | [.[] | select(.cost.operations <= $cap) | .error > 0.01] | all' "$WORK/${name}_r.json"
}

if have_shared_data probes-latlong/ennis.hdr; then
    budget_case ennis "$INLIGHT_SHARED_DIR/data/probes-latlong/ennis.hdr"
fi
SUNRISE=/usr/share/blender/datafiles/studiolights/world/sunrise.exr
if have_package_file "$SUNRISE" blender-data; then
    budget_case sunrise "$SUNRISE"
fi

# A room lit by two windows: two smooth-cap lights over 3 bands meet 1% within 5 bands' cost
# (2 x 18 + 54 = 90 operations); as exact caps (2 x 48 + 54 = 150) the same two lights cost more.
INTERIOR=/usr/share/blender/datafiles/studiolights/world/interior.exr
if have_package_file "$INTERIOR" blender-data; then
    expect_exit 0 "interior: 1% met with two smooth-cap lights" -- "$EP" "$INTERIOR" -o "$WORK/int_sh.json" \
        --max-error 0.01 --max-lights 2 --budget-max-bands 5 --report "$WORK/int.json" -q
    expect_true "interior: two lights over 3 bands at 90 operations, within 1%" -- jq -e '.metrics.environments[0].budget
        | .met and .light_shading == "smooth-cap" and .chosen.lights == 2 and .chosen.sh_bands == 3
          and .chosen.cost.operations == 90 and .chosen.error <= 0.01' "$WORK/int.json"
    expect_true "interior: the lights file says how to shade them" -- \
        jq -e '[.lights[] | .irradiance == "smooth-cap" and .fitted] | length == 2 and all' "$WORK/int_sh.json"
    expect_exit 0 "interior: exact caps" -- "$EP" "$INTERIOR" -o "$WORK/int_cap.json" --light-shading cap \
        --max-error 0.01 --max-lights 2 --budget-max-bands 5 --report "$WORK/int_cap_r.json" -q
    expect_true "interior: as exact caps nothing within 5 bands' cost meets 1%" -- \
        jq -e '.metrics.environments[0].budget.candidates
          | ([.[] | select(.lights == 0 and .sh_bands == 5) | .cost.operations] | first) as $cap
          | [.[] | select(.cost.operations <= $cap) | .error > 0.01] | all' "$WORK/int_cap_r.json"
fi

# grace (a cathedral: a wide skylight, two lamps side by side, further windows): 1% within the
# cost of 5 bands of pure SH. Scored on the default 1030 normals, two smooth-cap lights over 3
# bands (90 operations) meet it with the margin (0.956% against the 0.975% limit; docs/budget.md,
# "What the plain command guarantees"); the three-light candidate still needs its third light to
# start from a region beyond the three strongest (docs/budget.md, "Where the fit starts").
if have_shared_data probes-latlong/grace.hdr; then
    expect_exit 0 "grace: 1% met" -- "$EP" "$INLIGHT_SHARED_DIR/data/probes-latlong/grace.hdr" \
        -o "$WORK/grace_sh.json" --max-error 0.01 --budget-max-bands 5 --report "$WORK/grace.json" -q
    expect_true "grace: 2 smooth-cap lights over 3 bands (90 operations <= 129), within the margin's limit" -- \
        jq -e '.metrics.environments[0].budget | .met and .chosen.lights == 2 and .chosen.sh_bands == 3
          and .chosen.cost.operations == 90 and .chosen.error <= .scored_limit and .scored_limit < .max_error' "$WORK/grace.json"
    expect_true "grace: the third light started from a region beyond the three strongest" -- \
        jq -e '.metrics.environments[0].budget.candidates[] | select(.lights == 3 and .sh_bands == 3)
          | .start_regions | max >= 3' "$WORK/grace.json"
fi
# The mean of per-normal relative errors (--error-metric mean-rel): ennis with the projected SH
# misses 1% within 5 bands' cost (3 lights + 3 bands: 1.42%); with the coefficients, fluxes and
# light geometry fitted to that metric (--sh-fit metric; same coefficients, same shader) the
# same 108 operations meet it, measured at the validation normals (not the fit normals).
if have_shared_data probes-latlong/ennis.hdr; then
    ENNIS="$INLIGHT_SHARED_DIR/data/probes-latlong/ennis.hdr"
    expect_exit 3 "ennis mean-rel: projected SH miss 1% within 5 bands" -- "$EP" "$ENNIS" \
        -o "$WORK/ennis_mr_p.json" --max-error 0.01 --error-metric mean-rel --budget-max-bands 5 \
        --report "$WORK/ennis_mr_p_r.json" -q
    expect_true "ennis mean-rel, projection: nothing within 129 operations meets 1%" -- \
        jq -e '.metrics.environments[0].budget | .sh_fit == "projection" and ([.candidates[]
          | select(.cost.operations <= 129) | .irradiance.mean_rel > 0.01] | all)' "$WORK/ennis_mr_p_r.json"
    expect_exit 0 "ennis mean-rel: met with --sh-fit metric" -- "$EP" "$ENNIS" \
        -o "$WORK/ennis_mr_f.json" --max-error 0.01 --error-metric mean-rel --sh-fit metric \
        --budget-max-bands 5 --report "$WORK/ennis_mr_f_r.json" -q
    expect_true "ennis mean-rel, metric fit: 3 lights + 3 bands (108 operations), fitted, within 1%" -- \
        jq -e '.metrics.environments[0].budget | .met and .sh_fit == "metric" and .chosen.sh_fitted
          and .chosen.lights == 3 and .chosen.sh_bands == 3 and .chosen.cost.operations == 108
          and .chosen.error <= 0.01' "$WORK/ennis_mr_f_r.json"
fi
# uffizi (a gallery lit from a wide skylight): in mean-rel the projected SH need 7 bands; with
# --sh-fit metric the start pool also takes regions down to 0.3% of the flux, and three fitted
# lights over 3 bands meet 1% at 108 operations (docs/budget/mean-rel/tradeoff.md).
if have_shared_data probes-latlong/uffizi.hdr; then
    UFFIZI="$INLIGHT_SHARED_DIR/data/probes-latlong/uffizi.hdr"
    expect_exit 0 "uffizi mean-rel: met with --sh-fit metric" -- "$EP" "$UFFIZI" \
        -o "$WORK/uffizi_mr.json" --max-error 0.01 --error-metric mean-rel --sh-fit metric \
        --budget-max-bands 5 --report "$WORK/uffizi_mr_r.json" -q
    expect_true "uffizi mean-rel, metric fit: within 1% at no more than 5 bands' cost" -- \
        jq -e '.metrics.environments[0].budget | .met and .chosen.lights == 3 and .chosen.sh_bands == 3
          and .chosen.cost.operations == 108 and .chosen.error <= 0.01' "$WORK/uffizi_mr_r.json"
fi
# grace in mean-rel (--sh-fit metric, --max-lights 4), at the validation normals: three fitted
# lights over 3 bands meet 1% (108 operations, under the 129 of 5 bands of pure SH), two of them
# split from the zenith skylight's light (its region index twice), and four over 3 bands too
# (126). Before (docs/budget.md, "Where the fit starts"): 3 + 3 at 1.44-1.54% and 4 + 3 at
# 1.06% or 0.52% depending only on --budget-max-bands (the projection's band count moves the
# fit's start by rounding: the starts compared by the projection RMS, no split). Now both band
# counts give 0.73% and 0.50%; tolerance 0.1 points between them: under half the smaller margin
# to 1% (0.27 points), ten times the spread measured over fit-normal counts 512-1024 (<= 0.01).
if have_shared_data probes-latlong/grace.hdr; then
    GRACE="$INLIGHT_SHARED_DIR/data/probes-latlong/grace.hdr"
    for bands in 3 5; do
        expect_exit 0 "grace mean-rel, --budget-max-bands $bands: met" -- "$EP" "$GRACE" \
            -o "$WORK/grace_mr$bands.json" --max-error 0.01 --error-metric mean-rel --sh-fit metric \
            --max-lights 4 --budget-max-bands "$bands" --report "$WORK/grace_mr${bands}_r.json" -q
        expect_true "grace mean-rel, --budget-max-bands $bands: 3 lights + 3 bands (108 operations), one split, within 1%" -- \
            jq -e '.metrics.environments[0].budget | .met and .sh_fit == "metric" and .chosen.lights == 3
              and .chosen.sh_bands == 3 and .chosen.cost.operations == 108 and .chosen.error <= 0.01
              and ([.candidates[] | select(.lights == 3 and .sh_bands == 3) | .start_regions
                    | (unique | length) < length] | all)' "$WORK/grace_mr${bands}_r.json"
        expect_true "grace mean-rel, --budget-max-bands $bands: 4 lights + 3 bands (126 operations) within 1%" -- \
            jq -e '[.metrics.environments[0].budget.candidates[] | select(.lights == 4 and .sh_bands == 3)
              | .cost.operations == 126 and .irradiance.mean_rel <= 0.01] | all and length == 1' \
            "$WORK/grace_mr${bands}_r.json"
    done
    for k in 3 4; do
        expect_true "grace mean-rel: $k + 3 agrees within 0.1 points whatever the largest band count" -- \
            jq -e -n --argjson k "$k" --slurpfile a "$WORK/grace_mr3_r.json" --slurpfile b "$WORK/grace_mr5_r.json" '
              [$a[0], $b[0] | .metrics.environments[0].budget.candidates[]
               | select(.lights == $k and .sh_bands == 3) | .irradiance.mean_rel] | (.[0] - .[1]) | fabs <= 0.001'
    done
fi
finish
