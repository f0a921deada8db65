#!/usr/bin/env bash
# validate-pair's quality gate (docs/pipelines.md "Quality gate"): thresholds from the
# environment placed around the error a first run measures prove PASS (0), WARNING (0, said on
# stderr) and FAILURE (3, after the summary, with gate_failed.json naming the pair); bad values
# are usage errors (2) before anything is rendered.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data
make_fabric "$WORK/fab" "Tiny weave" 0.2
expect_exit 0 "bake-fabric" -- "$PIPE/bake-fabric.sh" "$WORK/fab" "$WORK/out" tiny
B="$WORK/out/bundles/fabrics/tiny"
ENV_MAP="$HDRI_DIR/night.exr"
printf 'spp = 8\nwidth-px = 16\nheight-px = 16\nrt-max-bands = 3\nrt-supersample = 1\n' > "$WORK/v.toml"
export VALIDATE_RENDER_CONFIG="$WORK/v.toml" VALIDATE_MAX_ERROR=0  # no band budget: not graded
pair() { env "${@:2}" "$PIPE/validate-pair.sh" "$B" "$ENV_MAP" "$WORK/$1"; }  # pair OUTDIR [VAR=VALUE...]

expect_exit 0 "validate-pair, no thresholds" -- pair m
expect_true "no gate without thresholds" -- jq -e '.gate == null' "$WORK/m/summary.json"
# The largest error of the consistent images (CPU and GLES): the thresholds below sit around it.
max_de=$(jq '[.consistent.mean_de2000, (.gles.variants[] | select(.mode == "consistent") | .mean_de2000)] | max' "$WORK/m/summary.json")
max_rel=$(jq '[.consistent.mean_rel, (.gles.variants[] | select(.mode == "consistent") | .mean_rel)] | max' "$WORK/m/summary.json")
echo "measured: largest mean dE2000 of the consistent images $max_de, mean relative error $max_rel"
x() { jq -n --argjson v "$max_de" "\$v * $1"; }
xr() { jq -n --argjson v "$max_rel" "\$v * $1"; }
export VALIDATE_GATE_MODES=consistent

expect_exit 3 "FAILURE: fail-de2000 at half the error" -- pair val/pairs/tiny/night VALIDATE_FAIL_DE2000="$(x 0.5)"
expect_stderr "validate-pair: tiny under night: quality gate failed: FAILURE (mean Delta E 2000" "names the pair and the deciding figure"
expect_true "the summary is written, with the verdict" -- jq -e '.gate.verdict == "FAILURE" and (.gate_error | test("FAILURE"))' "$WORK/val/pairs/tiny/night/summary.json"
expect_true "gate_failed.json names the pair and its failing images" -- jq -e \
    '.fabric == "tiny" and .environment == "night" and ([.gate.items[] | select(.verdict == "FAILURE")] | length) > 0' "$WORK/val/pairs/tiny/night/gate_failed.json"

expect_exit 0 "WARNING: warn at half, fail at twice the error" -- \
    pair val/pairs/tiny/night VALIDATE_WARN_DE2000="$(x 0.5)" VALIDATE_FAIL_DE2000="$(x 2)"
expect_stderr "validate-pair: tiny under night: quality gate WARNING (mean Delta E 2000" "says the pair warns"
expect_true "WARNING in the summary" -- jq -e '.gate.verdict == "WARNING" and .gate_error == null' "$WORK/val/pairs/tiny/night/summary.json"
expect_true "the earlier run's failure marker is gone" -- test ! -e "$WORK/val/pairs/tiny/night/gate_failed.json"
expect_exit 0 "validate-report" -- "$PIPE/validate-report.sh" "$WORK/val"
expect_true "the report's verdict shows the gate's" -- grep -q '| tiny | night | [a-z]*[^|]*; gate WARNING |' "$WORK/val/summary.md"

expect_exit 0 "PASS: both metrics' thresholds above the error" -- pair p VALIDATE_WARN_DE2000="$(x 2)" \
    VALIDATE_FAIL_DE2000="$(x 4)" VALIDATE_WARN_MEAN_REL="$(xr 2)" VALIDATE_FAIL_MEAN_REL="$(xr 4)"
expect_true "PASS in the summary, thresholds recorded" -- jq -e '.gate.verdict == "PASS"
    and .gate.thresholds.fail_mean_rel > .gate.thresholds.warn_mean_rel and .gate.thresholds.warn_de2000 > 0' "$WORK/p/summary.json"

expect_exit 2 "a threshold that is not a number" -- pair u VALIDATE_FAIL_DE2000=nan
expect_stderr "VALIDATE_FAIL_DE2000 'nan': expected a number >= 0" "names the variable"
expect_exit 2 "warn above fail" -- pair u VALIDATE_WARN_MEAN_REL=0.3 VALIDATE_FAIL_MEAN_REL=0.2
expect_stderr "VALIDATE_WARN_MEAN_REL 0.3 exceeds VALIDATE_FAIL_MEAN_REL 0.2" "names both variables"
expect_true "nothing rendered after a usage error" -- test ! -e "$WORK/u/render.json"
finish
