#!/usr/bin/env bash
# validate-convergence: the path tracer's own error against samples per pixel on one validation
# pair's scene (render convergence --ref-spp), so the report can show how many samples the
# truth needs to judge the real-time model's error. Writes PAIR_DIR/convergence.json.
#   pipelines/validate-convergence.sh PAIR_DIR [SPP] [REFERENCE_SPP]   (after validate-pair.sh)
# 32 x 32 pixels: per-pixel noise depends on samples, not on the image size.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 1 - "PAIR_DIR [SPP] [REFERENCE_SPP]"
PAIR=$(abs_dir "$1")
SPP=${2:-256}
REF=${3:-1024}
BIN=$(tool_bin)
mkdir -p "$PAIR/convergence"
"$BIN/render" convergence "$PAIR/scene.toml" -o "$PAIR/convergence/render.exr" --spp "$SPP" \
    --ref-spp "$REF" --width-px 32 --height-px 32 -q --report "$PAIR/convergence/report.json"
jq '{reference_spp: .metrics.convergence.reference_spp, slope: .metrics.convergence.slope,
     points: [.metrics.convergence.points[] | {spp, time_s, rel_rmse: .rel_rmse_corrected}]}' \
    "$PAIR/convergence/report.json" > "$PAIR/convergence.json.tmp"
mv "$PAIR/convergence.json.tmp" "$PAIR/convergence.json"
