#!/usr/bin/env bash
# render compare's quality gate (docs/render.md "Quality gate"): thresholds placed around the
# error a first run measures prove each verdict and exit code (PASS 0, WARNING 0, FAILURE 3 with
# the outputs and report written); bad thresholds are usage errors (2) before any output.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
SRC=${INLIGHT_SOURCE_DIR:?}
SCENE="$SRC/configs/scenes/patch_report.toml"
have_package_file /usr/share/blender/datafiles/studiolights/world/courtyard.exr blender-data || finish
# 16x16, 16 spp, 3 bands: ~4 s a run; the same seed gives the same figures every run.
FAST=(--width-px 16 --height-px 16 --spp 16 --rt-max-bands 3 --rt-bake-samples 256 --rt-supersample 2 --seed 3)

expect_exit 0 "compare, no thresholds: no gate" -- "$R" compare "$SCENE" -o "$WORK/m.exr" "${FAST[@]}" --report "$WORK/m.json"
expect_true "no gate without thresholds" -- jq -e '.metrics.realtime | has("gate") | not' "$WORK/m.json"
# The largest mean dE2000 and mean relative error over the consistent images (CPU and GLES).
max_de=$(jq '[.metrics.realtime.modes.consistent.mean_de2000,
              (.metrics.realtime.gles.variants[] | select(.mode == "consistent") | .mean_de2000)] | max' "$WORK/m.json")
max_rel=$(jq '[.metrics.realtime.modes.consistent.mean_rel,
               (.metrics.realtime.gles.variants[] | select(.mode == "consistent") | .mean_rel)] | max' "$WORK/m.json")
seed_de=$(jq '.metrics.realtime.modes.seed.mean_de2000' "$WORK/m.json")
echo "measured: consistent max mean dE2000 $max_de, max mean relative error $max_rel; seed mean dE2000 $seed_de"
x() { jq -n --argjson v "$1" "\$v * $2"; }  # x VALUE FACTOR

# PASS: both thresholds of both metrics at 2x and 4x the measured error.
expect_exit 0 "PASS: thresholds above every consistent image's error" -- "$R" compare "$SCENE" -o "$WORK/p.exr" \
    "${FAST[@]}" --gate-modes consistent --warn-de2000 "$(x "$max_de" 2)" --fail-de2000 "$(x "$max_de" 4)" \
    --warn-mean-rel "$(x "$max_rel" 2)" --fail-mean-rel "$(x "$max_rel" 4)" --report "$WORK/p.json"
expect_true "PASS recorded, every consistent image graded (CPU + 2 GLES versions)" -- jq -e '.metrics.realtime.gate
    | .verdict == "PASS" and ([.items[].verdict] | unique) == ["PASS"] and (.items | length) == 3
    and ([.items[].name] | index("cpu consistent b3")) != null' "$WORK/p.json"
# shellcheck disable=SC2016  # $rt, $a and $b are jq variables
expect_true "the graded figures are the report's metrics" -- jq -e '.metrics.realtime as $rt
    | $rt.gate.items[0].mean_de2000 == $rt.modes.consistent.mean_de2000
      and ($rt.gate.items[1:] | map(.mean_rel)) == ($rt.gles.variants | map(select(.mode == "consistent") | .mean_rel))' "$WORK/p.json"
expect_stderr "^render: quality gate: PASS (" "PASS line printed"
expect_true "one line per graded image" -- test "$(grep -c '^render: quality gate: [cg]' "$WORK/stderr")" -eq 3

# WARNING: the measured error lies between warn (half of it) and fail (twice it): exit 0.
expect_exit 0 "WARNING: warn below the error, fail above it" -- "$R" compare "$SCENE" -o "$WORK/w.exr" \
    "${FAST[@]}" --gate-modes consistent --warn-de2000 "$(x "$max_de" 0.5)" --fail-de2000 "$(x "$max_de" 2)" \
    --report "$WORK/w.json"
expect_true "WARNING recorded, decided by mean dE2000" -- jq -e '.metrics.realtime.gate
    | .verdict == "WARNING" and (.decided_by | test("^mean Delta E 2000 .* > warn "))' "$WORK/w.json"
expect_stderr "^render: quality gate: WARNING (mean Delta E 2000" "WARNING line printed"

# FAILURE: fail below the measured error: exit 3, outputs and report written, message even with -q.
expect_exit 3 "FAILURE: fail below the error exits 3" -- "$R" compare "$SCENE" -o "$WORK/f.exr" "${FAST[@]}" \
    --gate-modes consistent --fail-mean-rel "$(x "$max_rel" 0.5)" -q --report "$WORK/f.json"
expect_true "FAILURE recorded; status quality_gate_failed" -- jq -e '.status == "quality_gate_failed"
    and .exit_code == 3 and .metrics.realtime.gate.verdict == "FAILURE"
    and (.metrics.realtime.gate.decided_by | test("^mean relative error .* > fail "))' "$WORK/f.json"
expect_true "FAILURE: the outputs are still written" -- test -s "$WORK/f.exr" -a -s "$WORK/f_compare_consistent.png"
expect_stderr "quality gate failed: FAILURE (mean relative error" "FAILURE named on stderr under -q"

# The seed mode is graded by default: thresholds the consistent images pass, the seed's fail.
mid=$(jq -n --argjson a "$max_de" --argjson b "$seed_de" '($a + $b) / 2')
# shellcheck disable=SC2016
expect_true "the seed mode's error is above the consistent mode's (the next case needs it)" -- \
    jq -en --argjson a "$max_de" --argjson b "$seed_de" '$b > 1.5 * $a'
expect_exit 3 "default --gate-modes grades the seed mode too" -- "$R" compare "$SCENE" -o "$WORK/s.exr" "${FAST[@]}" \
    --fail-de2000 "$mid" -q --report "$WORK/s.json"
expect_true "the seed images fail, the consistent ones pass" -- jq -e '.metrics.realtime.gate.items
    | all(if (.name | test("seed")) then .verdict == "FAILURE" else .verdict == "PASS" end) and length == 6' "$WORK/s.json"

# Bad thresholds: usage errors naming the option, before any output.
expect_exit 2 "warn above fail" -- "$R" compare "$SCENE" -o "$WORK/u.exr" "${FAST[@]}" --warn-de2000 2 --fail-de2000 1
expect_stderr "--warn-de2000 2 exceeds --fail-de2000 1" "warn above fail names both options"
expect_exit 2 "a negative threshold" -- "$R" compare "$SCENE" -o "$WORK/u.exr" "${FAST[@]}" --fail-mean-rel -0.1
expect_stderr "--fail-mean-rel" "a negative threshold names its option"
expect_exit 2 "a NaN threshold" -- "$R" compare "$SCENE" -o "$WORK/u.exr" "${FAST[@]}" --warn-mean-rel nan
expect_stderr "--warn-mean-rel" "a NaN threshold names its option"
expect_exit 2 "an unknown gate mode" -- "$R" compare "$SCENE" -o "$WORK/u.exr" "${FAST[@]}" --fail-de2000 1 --gate-modes fancy
expect_true "no output after a usage error" -- test ! -e "$WORK/u.exr"
finish
