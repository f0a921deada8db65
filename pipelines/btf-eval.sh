#!/usr/bin/env bash
# The Table 7.1-style evaluation of btf-pca (docs/btf.md), one Markdown table per fabric for k in
# {1,3,9,81} and C in {1,2,4,8,16,32}, the streaming curve of k=3 C=32 (table and gnuplot SVG)
# and every run's report under $OUT:
#  - woven: every configs/fabrics/*.toml captured with render --btf-capture (UBO2003 dome, 81 x 81,
#    CAP_PX^2, CAP_SPP paths per pixel, 8-bit sRGB PNG); the fabrics in NOISE_FABRICS are captured
#    a second time with another seed, and their tables add the error against that independent
#    capture (btf-pca --reference): the capture noise, the floor no model can go below;
#  - analytic: the rank-6 BTF of lib/btf/synthetic.h at SIZE_PX^2 (8-bit PNG), plain and saturated.
#   pipelines/btf-eval.sh [OUT] [SIZE_PX] [CAP_PX] [CAP_SPP]  (defaults: out/btf-eval, 32, 64, 4)
#   BTF_EVAL_SETS="woven analytic" (default both), NOISE_FABRICS="wool-twill" (default)
# Captures are reused when their folder exists. Minutes per capture: run it under nice.
set -euo pipefail
OUT=${1:-out/btf-eval}
SIZE=${2:-32}
CAP_PX=${3:-64}
CAP_SPP=${4:-4}
SETS=${BTF_EVAL_SETS:-woven analytic}
NOISE_FABRICS=${NOISE_FABRICS:-wool-twill}
BIN=${INLIGHT_BIN:-build/bin}
TBIN=${INLIGHT_TEST_BIN:-build/tests}
mkdir -p "$OUT"
say() { echo "[btf-eval] $*" >&2; }

# table NAME BTF_DIR [REFERENCE_DIR]: $OUT/NAME/table.md from one btf-pca run per k with C = 32;
# the rows for C = 1..16 are that model cut to C components (the same figures as a run with
# that C: test CompressToFolder.TableRowsEqualRunsWithThatManyComponents).
table() {
    local name=$1 btf=$2 ref=${3:-} k run
    local tab="$OUT/$name/table.md" extra=() head="" rule=""
    if [ -n "$ref" ]; then
        extra=(--reference "$ref")
        head=" MAE Lab vs seed 2 | RMSE RGB vs seed 2 |"
        rule=" --- | --- |"
    fi
    {
        echo "| k | C | MAE Lab | MAE RGB (8-bit) | RMSE RGB (8-bit) | mean dE2000 | raw : params float32 | raw : stored | PNG input : stored | stored MiB | run time s (C=32) | peak MiB |$head"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |$rule"
    } >"$tab"
    for k in 1 3 9 81; do
        run="$OUT/$name/k${k}"
        "$BIN/btf-pca" "$btf" -o "$run" -k "$k" -c 32 --table-components 1,2,4,8,16,32 \
            --color-samples 65536 "${extra[@]}" -q --report "$run.json"
        jq -r --arg k "$k" 'def r2: . * 100 | round / 100;
            .metrics as $m | $m.table[] | "| \($k) | \(.components) | \(.mae_lab|r2) | \(.mae_rgb8|r2) | \(.rmse_rgb8|r2) | \(.delta_e2000_mean|r2) | 1:\(.raw_8bit_to_parameters_float32*10|round/10) | 1:\(.raw_8bit_to_stored*10|round/10) | 1:\(.input_files_to_stored*10|round/10) | \(.stored_bytes/1048576*1000|round/1000) | \($m.time.total_s*10|round/10) | \($m.peak_rss_mib|round) |"
            + (if .vs_reference then " \(.vs_reference.mae_lab|r2) | \(.vs_reference.rmse_rgb8|r2) |" else "" end)' \
            "$run.json" >>"$tab"
    done
    if [ -n "$ref" ]; then
        jq -r 'def r2: . * 100 | round / 100; .metrics.reference.input
            | "\nThe input itself against the seed-2 capture (the noise floor x sqrt 2 in RMSE): MAE Lab \(.mae_lab|r2), MAE RGB \(.mae_rgb8|r2), RMSE RGB \(.rmse_rgb8|r2), mean dE2000 \(.delta_e2000_mean|r2)."' \
            "$OUT/$name/k1.json" >>"$tab"
    fi
    say "$name: $tab"
    (cd "$OUT/$name/k3" && gnuplot streaming.gp) || say "gnuplot failed: no streaming.svg"
}

# capture FABRIC_TOML DIR SEED: the UBO2003 capture, unless DIR exists.
capture() {
    [ -d "$2" ] && return 0
    say "capturing $(basename "$1") (seed $3, ${CAP_PX}x${CAP_PX} px, $CAP_SPP spp, 6561 images)"
    "$BIN/render" "$1" --btf-capture -o "$2" --width-px "$CAP_PX" --height-px "$CAP_PX" --spp "$CAP_SPP" \
        --seed "$3" -q --report "$2.json"
}

if [[ " $SETS " == *" woven "* ]]; then
    for toml in configs/fabrics/*.toml; do
        name=$(basename "$toml" .toml)
        capture "$toml" "$OUT/$name/capture" 1
        ref=""
        if [[ " $NOISE_FABRICS " == *" $name "* ]]; then
            capture "$toml" "$OUT/$name/capture-seed2" 2
            ref="$OUT/$name/capture-seed2"
        fi
        table "$name" "$OUT/$name/capture" "$ref"
    done
fi

if [[ " $SETS " == *" analytic "* ]]; then
    # fabric: name rank scale (scale > 1 saturates highlights in the 8-bit files)
    for f in "sheen 6 1.0" "saturated 6 2.5"; do
        read -r name rank scale <<<"$f"
        if [ ! -d "$OUT/$name/btf" ]; then
            say "writing $name (rank $rank, scale $scale, ${SIZE}x${SIZE} px, 6561 images)"
            "$TBIN/inlight_make_test_btf" "$OUT/$name/btf" "$SIZE" "$SIZE" "$rank" "$scale"
        fi
        table "$name" "$OUT/$name/btf"
    done
fi
