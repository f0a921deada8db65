#!/usr/bin/env bash
# bake-catalog's quality gate (docs/pipelines.md "Quality gate"): a [quality] threshold in
# catalog.toml that a fabric's pair fails stops the bake with exit 3, naming the fabric, the
# environment and the figures; the failed pair is validated again on the next run, where a
# per-fabric override set from the error measured by the first run lets it pass; a bad [quality]
# table is a usage error (2) before any job.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
tiny_catalog 1
export VALIDATE_MAX_ERROR=0  # no band budget: it is not graded and costs half the pair's time
bake() { "$PIPE/bake-catalog.sh" -j 2 "$CAT" "$OUT"; }
cp "$CAT/catalog.toml" "$WORK/catalog.base.toml"
# Zero tolerance: any error at all fails (the model is not exact: checked below).
printf '[quality]\nfail-mean-rel = 0.0\ngate-modes = ["consistent"]\n' >> "$CAT/catalog.toml"

expect_exit 3 "a pair failing the gate stops the bake with exit 3" -- bake
expect_stderr "bake-catalog: quality gate failed: fabric f1 under night: FAILURE (mean relative error" \
    "names the fabric, the environment and the deciding figure"
expect_stderr "  cpu consistent b3: mean relative error" "lists each failing image's figures"
P="$OUT/validate/pairs/f1/night"
expect_true "the failed pair has no summary (its job failed: redone on the next run)" -- test ! -e "$P/summary.json"
expect_true "its render report says why" -- jq -e '.status == "quality_gate_failed" and .metrics.realtime.gate.verdict == "FAILURE"' "$P/render.json"
expect_true "no validation report after a failed gate" -- test ! -e "$OUT/validate/index.html"
max_rel=$(jq '[.metrics.realtime.gate.items[].mean_rel] | max' "$P/render.json")
# shellcheck disable=SC2016  # $v and $f are jq variables
expect_true "the model's error is not zero ($max_rel), so a zero tolerance must fail it" -- \
    jq -en --argjson v "$max_rel" '$v > 0'

# f1's own threshold at twice its measured error; [quality] still fails every other fabric.
fail_f1=$(jq -n --argjson v "$max_rel" '$v * 2')
printf '[quality.fabrics.f1]\nfail-mean-rel = %s\n' "$fail_f1" >> "$CAT/catalog.toml"
# Only the pair is asked for (a Snakemake target): the convergence study and the report after it
# would double the test's time and are not what is tested here.
expect_exit 0 "rerun with f1's override above its error: the pair's job succeeds" -- \
    "$PIPE/bake-catalog.sh" -j 2 "$CAT" "$OUT" validate/pairs/f1/night/summary.json
# shellcheck disable=SC2016
expect_true "the pair is validated again and passes with f1's threshold" -- jq -e --argjson f "$fail_f1" \
    '.gate.verdict == "PASS" and .gate.thresholds.fail_mean_rel == $f' "$P/summary.json"
expect_true "no failure marker left" -- test ! -e "$P/gate_failed.json"

# A bad [quality] table: exit 2 before any job, naming the file, table and key.
mkdir -p "$WORK/bad"
cp -r "$CAT/fabrics" "$WORK/bad/"
cp "$WORK/catalog.base.toml" "$WORK/bad/catalog.toml"
printf '[quality]\nwarn-de2000 = 3.0\nfail-de2000 = 2.0\n' >> "$WORK/bad/catalog.toml"
expect_exit 2 "warn above fail in [quality]" -- "$PIPE/bake-catalog.sh" "$WORK/bad" "$WORK/badout"
expect_stderr "catalog.toml: \[quality\]: warn-de2000 3 exceeds fail-de2000 2" "names the file, table and keys"
expect_true "no job ran" -- test ! -e "$WORK/badout/logs"
cp "$WORK/catalog.base.toml" "$WORK/bad/catalog.toml"
printf '[quality]\nfail-de2000 = nan\n[quality.fabrics.nosuch]\nfail-de2000 = 1.0\n' >> "$WORK/bad/catalog.toml"
expect_exit 2 "NaN in [quality]" -- "$PIPE/bake-catalog.sh" "$WORK/bad" "$WORK/badout"
expect_stderr "\[quality\] fail-de2000 = nan: expected a finite number >= 0" "names the key and what is wrong"
sed -i '/= nan/d' "$WORK/bad/catalog.toml"
expect_exit 2 "[quality.fabrics.<id>] of no fabric" -- "$PIPE/bake-catalog.sh" "$WORK/bad" "$WORK/badout"
expect_stderr "\[quality.fabrics.nosuch\]: no fabric 'nosuch'" "names the table"
cp "$WORK/catalog.base.toml" "$WORK/bad/catalog.toml"
printf '[quality]\nfail-dE2000 = 1.0\n' >> "$WORK/bad/catalog.toml"
expect_exit 2 "an unknown key in [quality]" -- "$PIPE/bake-catalog.sh" "$WORK/bad" "$WORK/badout"
expect_stderr "\[quality\] fail-dE2000: unknown key" "names the key"
cp "$WORK/catalog.base.toml" "$WORK/bad/catalog.toml"
printf '[quality]\ngate-modes = ["fancy"]\n' >> "$WORK/bad/catalog.toml"
expect_exit 2 "an unknown gate mode" -- "$PIPE/bake-catalog.sh" "$WORK/bad" "$WORK/badout"
expect_stderr "gate-modes = \['fancy'\]: expected a non-empty list" "names the key and the modes"
expect_true "no job ran after any of them" -- test ! -e "$WORK/badout/logs"
finish
