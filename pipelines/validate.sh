#!/usr/bin/env bash
# validate: every fabric bundle of a bundle root under every environment: path-traced truth
# against the real-time model (validate-pair.sh), then one HTML page, a Markdown summary and
# plots of error against cost (validate-report.sh) in OUT/.
#   pipelines/validate.sh OUT BUNDLE_ROOT ENVIRONMENT...     (binaries from ${INLIGHT_BIN})
# A fabric whose BTF bake-fabric.sh captured (BUNDLE_ROOT/../work/fabrics/<id>/capture/btf) is
# also shaded as a BTF against its woven geometry (validate-pair.sh's RAW_BTF).
# bake-catalog runs the same two scripts as Snakemake rules, in parallel. With quality-gate
# thresholds (validate-pair.sh's VALIDATE_WARN_* / VALIDATE_FAIL_*), the first pair that fails
# the gate stops the run with exit 3, its summary and gate_failed.json written.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 3 - "OUT BUNDLE_ROOT ENVIRONMENT..."
OUT=$1
BUNDLES=$2
shift 2
mapfile -t fabrics < <(find "$BUNDLES/fabrics" -mindepth 1 -maxdepth 1 -type d ! -name '.*' | sort)
n=$((${#fabrics[@]} * $#))
i=0
for fabric in "${fabrics[@]}"; do
    for env in "$@"; do
        i=$((i + 1))
        name=$(basename "$env")
        echo "[validate $i/$n] $(basename "$fabric") under ${name%.*}" >&2
        raw=()
        capture="$BUNDLES/../work/fabrics/$(basename "$fabric")/capture/btf"
        [ -f "$capture/capture.json" ] && raw=("$capture")
        "$HERE/validate-pair.sh" "$fabric" "$env" "$OUT/pairs/$(basename "$fabric")/${name%.*}" "${raw[@]}"
    done
done
first=$(find "$OUT/pairs" -mindepth 2 -maxdepth 2 -type d | sort | sed -n 1p)
echo "[validate] the truth's error against spp on $first" >&2
"$HERE/validate-convergence.sh" "$first"
"$HERE/validate-report.sh" "$OUT"
