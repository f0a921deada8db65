#!/usr/bin/env bash
# envmap-project on a fisheye camera frame (partial sphere, 8-bit through a response curve) with
# a sun that clips: the light's flux is reported as a lower bound, flagged in the report, the
# warnings and the lights file, and its value is the clipped radiance's excess over the sky times
# the sun's solid angle, derived here from the response curve and the geometry
# (docs/budget.md, "Camera frames"). Two frames: the sun inside the field, and centred on the
# rim of the field (half of it seen).
# shellcheck disable=SC2016  # $vars in the single-quoted jq programs are jq's own
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
EP="$BIN/envmap-project"
MK="$TBIN/inlight_make_test_fisheye"

# The camera: equidistant fisheye, 256 px across 180 degrees (pitch p = 90/128 deg), 0.5 s.
# Its response g(z) = 2.2 ln(z / 128) gives radiance (z / 128)^2.2 / t: the sky at code 40 is
# L_sky = 0.15477, the sun clipped at 255 reads L_clip = 9.1108 (its true radiance is higher:
# 30,000 x the sky for a real sun).
N=256 THETA_MAX=90 SKY=40 T=0.5 ALPHA=8
jq -n '{format: "inlight_response", version: 1, channels: ["r", "g", "b"],
        g: [range(3) | [range(256) | if . == 0 then (0.5 / 128 | log) * 2.2 else (. / 128 | log) * 2.2 end]]}' \
    > "$WORK/gamma.json"

# Analytic figures (jq, double precision):
#   L(z) = (z / 128)^2.2 / t; solid angle of a cap of radius alpha: 2 pi (1 - cos alpha), half of
#   it for a cap centred on the field's rim (theta_max = 90 degrees: the rim is a great circle).
#   Lower bound of the flux = (L_clip - L_sky) x the solid angle of the clipped pixels.
# Tolerances:
#   - radiances: float32 pixels, 1e-6 relative;
#   - flux against the report's own clipped-light sum (calib::radiance_from_frame, independent
#     of the extraction, same float32 solid angles summed in double): 1e-6 relative;
#   - the clipped pixels' solid angle against the cap's: pixel centres decide membership, so the
#     error is at most the band of half a pixel diagonal around the edge: perimeter x p / sqrt 2
#     over the area: 2 pi alpha (p / sqrt 2) / (pi alpha^2) = sqrt(2) p / alpha (whole cap);
#     (pi alpha + 2 alpha) (p / sqrt 2) / (pi alpha^2 / 2) = (pi + 2) sqrt(2) p / (pi alpha) for
#     the half cap (its arc plus the rim's chord);
#   - the rim light's direction: the centroid of a half disc lies 4 alpha / (3 pi) inside its
#     chord (small-angle; the spherical correction is O(alpha^2) relative, 2% of the offset at
#     8 degrees), and pixel centres move the region's centroid by at most half a pitch.
cat > "$WORK/expect.jq" <<'JQ'
def lz(z): pow(z / 128; 2.2) / $t;
def rad: . * 3.141592653589793 / 180;
(lz(255)) as $lc | (lz($sky)) as $ls | ($p | rad) as $pr | ($alpha | rad) as $a
| {l_clip: $lc, l_sky: $ls, pitch: $pr, alpha: $a,
   omega_cap: (2 * 3.141592653589793 * (1 - ($a | cos))),
   tol_cap: (1.4142135623730951 * $pr / $a),
   tol_half: ((3.141592653589793 + 2) * $pr / (1.4142135623730951 * 3.141592653589793 * $a / 2)),
   rim_offset: (4 * $a / (3 * 3.141592653589793))}
JQ
jq -n --argjson t "$T" --argjson sky "$SKY" --argjson alpha "$ALPHA" \
    --argjson p "$(jq -n "$THETA_MAX / ($N / 2)")" -f "$WORK/expect.jq" > "$WORK/expect.json"

# sun_case NAME SUN_THETA SUN_PHI OMEGA_FACTOR TOL_KEY: one frame and the checks common to both.
sun_case() {
    local name=$1 theta=$2 phi=$3 factor=$4 tol=$5 dir="$WORK/$1"
    mkdir -p "$dir"
    "$MK" "$dir" "$N" "$THETA_MAX" "$SKY" "$theta" "$phi" "$ALPHA"
    expect_exit 0 "$name: the budget on a fisheye frame with a clipped sun" -- "$EP" "$dir/frame.png" \
        --input-kind fisheye --directions "$dir/directions.exr" --solid-angle "$dir/solid_angle.exr" \
        --response "$WORK/gamma.json" --exposure-s "$T" -o "$dir/sh.json" --max-error 0.01 \
        --report "$dir/r.json"
    jq '.metrics.environments[0]' "$dir/r.json" > "$dir/env.json"
    expect_true "$name: one light found, every pixel of it clipped" -- jq -e '.budget.lights_found
        | length == 1 and .[0].saturated_samples > 0 and .[0].saturated_samples == .[0].samples
          and (.[0].saturated_flux_fraction - 1 | fabs) < 1e-12' "$dir/env.json"
    expect_true "$name: the flux is flagged a lower bound in the report and the lights file" -- \
        jq -e '.budget.lights_found[0].flux_is_lower_bound' "$dir/env.json"
    expect_true "$name: ... and in the lights file" -- jq -e '.lights[0].flux_is_lower_bound' "$dir/sh.json"
    expect_true "$name: ... and in the warnings" -- \
        jq -e '[.warnings[] | select(test("lower bound"))] | length >= 1' "$dir/r.json"
    expect_true "$name: peak and background are the response's L_clip and L_sky (1e-6)" -- \
        jq -e --slurpfile x "$WORK/expect.json" '.budget.lights_found[0]
          | ((.peak_radiance / $x[0].l_clip - 1) | fabs) < 1e-6
            and ([.background[] | (. / $x[0].l_sky - 1) | fabs < 1e-6] | all)' "$dir/env.json"
    # The extraction's flux against the report's clipped light (camera.clipped_light_lower_bound
    # = L_clip x the clipped pixels' solid angle): (L_clip - L_sky) / L_clip of it.
    expect_true "$name: flux = (L_clip - L_sky) x solid angle of the clipped pixels (1e-6)" -- \
        jq -e --slurpfile x "$WORK/expect.json" '(.camera.clipped_light_lower_bound[0] / $x[0].l_clip) as $om
          | (.budget.lights_found[0].luminance_flux / (($x[0].l_clip - $x[0].l_sky) * $om) - 1 | fabs) < 1e-6
            and ((.budget.lights_found[0].solid_angle_sr / $om - 1) | fabs) < 1e-6' "$dir/env.json"
    expect_true "$name: the clipped solid angle is the cap's x $factor, within the rasterisation bound" -- \
        jq -e --slurpfile x "$WORK/expect.json" --argjson f "$factor" --arg k "$tol" \
          '((.budget.lights_found[0].solid_angle_sr / ($f * $x[0].omega_cap) - 1) | fabs) < $x[0][$k]' "$dir/env.json"
    # A real sun 30,000x the sky: the lower bound is (L_clip - L_sky) / (29,999 L_sky) = 0.19% of
    # its power; the shaded light is at least that dim, never brighter.
    expect_true "$name: the lower bound is below the true sun's power" -- \
        jq -e --slurpfile x "$WORK/expect.json" --argjson f "$factor" \
          '.budget.lights_found[0].luminance_flux < 29999 * $x[0].l_sky * $f * $x[0].omega_cap' "$dir/env.json"
    # A uniform sky: the residual is one band; the clipped region is shaded as found (no fit:
    # the brute force sees only the clipped radiance).
    expect_true "$name: one light over one band, the region as found (no fit)" -- \
        jq -e '.budget | .met and .chosen.lights == 1 and .chosen.sh_bands == 1 and (.chosen.lights_fitted | not)' "$dir/env.json"
}

# The sun inside the field (theta 40, phi 30): the whole clipped disc is seen.
sun_case inside 40 30 1 tol_cap
expect_true "inside: not at the field's edge, direction on the sun (within half a pitch)" -- \
    jq -e --slurpfile x "$WORK/expect.json" '.budget.lights_found[0]
      | (.at_field_edge | not) and ((.direction[0] * 0.5566703992264194 + .direction[1] * 0.3213938048432697
          + .direction[2] * 0.766044443118978) | acos) < $x[0].pitch / 2' "$WORK/inside/env.json"

# The sun centred on the rim of the field (theta 90, phi -60): half of it is seen.
sun_case rim 90 -60 0.5 tol_half
expect_true "rim: flagged at the field's edge" -- jq -e '.budget.lights_found[0].at_field_edge' "$WORK/rim/env.json"
expect_true "rim: direction 4 alpha / (3 pi) inside the rim, toward the field (half a pitch + 2%)" -- \
    jq -e --slurpfile x "$WORK/expect.json" '.budget.lights_found[0]
      | ((.direction[0] * 0.5 - .direction[1] * 0.8660254037844386) | acos) as $off
      | .direction[2] > 0 and (($off - $x[0].rim_offset) | fabs) < $x[0].pitch / 2 + 0.02 * $x[0].rim_offset' \
    "$WORK/rim/env.json"
finish
