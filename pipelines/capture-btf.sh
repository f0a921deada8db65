#!/usr/bin/env bash
# capture-btf: a captured-BTF fabric's synthetic capture (render capture-btf, docs/btf.md).
#   pipelines/capture-btf.sh FABRIC_DIR OUTDIR        (binaries from ${INLIGHT_BIN:-ROOT/build/bin})
# FABRIC_DIR holds weave.toml (a render fabric file: configs/fabrics/ has more) and capture.toml
# (render capture-btf's options: width-px, height-px, spp, seed, btf-format, ...). Writes
# OUTDIR/btf/ (UBO2003 layout, 81 view folders) and OUTDIR/capture.json (render's report);
# render's output transaction makes the folder appear whole or not at all.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 2 2 "FABRIC_DIR OUTDIR"
FABRIC=$(abs_dir "$1")
BIN=$(tool_bin)
for f in weave.toml capture.toml; do
    if [ ! -f "$FABRIC/$f" ]; then
        echo "capture-btf: $FABRIC/$f not found (a captured fabric needs weave.toml and capture.toml)" >&2
        exit 2
    fi
done
OUT=$(out_dir "$2")
rm -rf "$OUT/btf"
echo "[capture-btf $(basename "$FABRIC")] render capture-btf weave.toml --config capture.toml" >&2
"$BIN/render" capture-btf "$FABRIC/weave.toml" --config "$FABRIC/capture.toml" -o "$OUT/btf" \
    -q --report "$OUT/capture.json"
jq -r '.metrics.capture | "[capture-btf] \(.images) images of \(.width_px)x\(.height_px) px at \(.spp) spp in \(.wall_time_s * 10 | round / 10) s, noise median \(if .rel_error_median then .rel_error_median * 1000 | round / 1000 else "n/a (1 spp)" end)"' \
    "$OUT/capture.json" >&2
