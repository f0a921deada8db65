#!/usr/bin/env bash
# The Table 7.1-style evaluation of btf-pca (docs/btf.md): analytic fabric BTFs on the UBO2003
# dome (81 x 81 directions, 8-bit sRGB PNG) compressed for k in {1,3,9,81} and C in
# {1,2,4,8,16,32}; one Markdown table per fabric, the streaming curve of k=3 C=32 (table and
# gnuplot SVG) and every run's report under $OUT.
#   pipelines/btf-eval.sh [OUT] [SIZE_PX]       (defaults: out/btf-eval, 32)
# Until the synthetic capture (render --btf-capture) lands, the fabrics come from the analytic
# BTF of lib/btf/synthetic.h through build/tests/inlight_make_test_btf.
set -euo pipefail
OUT=${1:-out/btf-eval}
SIZE=${2:-32}
BIN=${INLIGHT_BIN:-build/bin}
TBIN=${INLIGHT_TEST_BIN:-build/tests}
mkdir -p "$OUT"
say() { echo "[btf-eval] $*" >&2; }

# fabric: name rank scale (scale > 1 saturates highlights in the 8-bit files)
FABRICS=("sheen 6 1.0" "saturated 6 2.5")
for f in "${FABRICS[@]}"; do
    read -r name rank scale <<<"$f"
    if [ ! -d "$OUT/$name/btf" ]; then
        say "writing $name (rank $rank, scale $scale, ${SIZE}x${SIZE} px, 6561 images)"
        "$TBIN/inlight_make_test_btf" "$OUT/$name/btf" "$SIZE" "$SIZE" "$rank" "$scale"
    fi
    table="$OUT/$name/table.md"
    {
        echo "| k | C | MAE Lab | MAE RGB (8-bit) | RMSE RGB (8-bit) | mean dE2000 | raw : params float32 | raw : stored | PNG input : stored | stored MiB | run time s (C=32) | peak MiB |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    } >"$table"
    for k in 1 3 9 81; do
        # One run per k with C = 32; the rows for C = 1..16 are that model cut to C components
        # (the same figures as a run with that C: test TableRowsEqualRunsWithThatManyComponents).
        run="$OUT/$name/k${k}"
        "$BIN/btf-pca" "$OUT/$name/btf" -o "$run" -k "$k" -c 32 --table-components 1,2,4,8,16,32 \
            --color-samples 65536 -q --report "$run.json"
        jq -r --arg k "$k" '.metrics as $m | $m.table[] | "| \($k) | \(.components) | \(.mae_lab*100|round/100) | \(.mae_rgb8*100|round/100) | \(.rmse_rgb8*100|round/100) | \(.delta_e2000_mean*100|round/100) | 1:\(.raw_8bit_to_parameters_float32*10|round/10) | 1:\(.raw_8bit_to_stored*10|round/10) | 1:\(.input_files_to_stored*10|round/10) | \(.stored_bytes/1048576*1000|round/1000) | \($m.time.total_s*10|round/10) | \($m.peak_rss_mib|round) |"' \
            "$run.json" >>"$table"
    done
    say "$name: $table"
    (cd "$OUT/$name/k3" && gnuplot streaming.gp) || say "gnuplot failed: no streaming.svg"
done
