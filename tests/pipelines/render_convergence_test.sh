#!/usr/bin/env bash
# pipelines/render-convergence.sh run again into a folder that holds an earlier call's files
# (other sizes and spp) gives the same table as a fresh folder: nothing stale is read. Rendering
# is deterministic for a seed (any thread count), so every figure but the timing-dependent ones
# (CPU per sample, spp and error at equal time) must match exactly. Tiny sizes: seconds.
# shellcheck disable=SC2016 # awk programs in single quotes
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
RC="$HERE/../../pipelines/render-convergence.sh"

# The deterministic part of a call's results: the TSV without its CPU and wall seconds, and the
# Markdown tables without the columns and the note that depend on CPU times (which equal-time
# rows are "-", and the MAX_SPP that would measure them).
fixed_tsv() { cut -f1-4,7- "$1/convergence.tsv"; }
fixed_md() {
    awk -F'|' 'NF == 11 { print $2 $3 $4 $5 $6 $7 $8 $10 }  # per-sampler table: not CPU / sample
               NF == 8 { print $2 $3 $4 }                    # equal time: peer spp, error, sampler
               NF != 11 && NF != 8 && !/^(Machine|render-convergence|"-" \()/' "$1/convergence.md"
}
rc() {  # rc OUT MAX_SPP SPHERE_PX PATCH_PX PATCH_REF_SPP
    "$RC" "$@" > "$WORK/rc.log" 2>&1 || { sed 's/^/    /' "$WORK/rc.log" | tail -20; return 1; }
}

if have_package_file /usr/share/blender/datafiles/studiolights/world/city.exr blender-data; then
    expect_true "an earlier call into OUT (16 spp, sphere 8 px, patch 4 px, reference 64 spp)" -- \
        rc "$WORK/out" 16 8 4 64
    expect_true "the same OUT again with other parameters (256 spp, 12 px, 6 px, 128 spp)" -- \
        rc "$WORK/out" 256 12 6 128
    expect_true "the same parameters into a fresh folder" -- rc "$WORK/fresh" 256 12 6 128
    expect_true "TSV (all but the times) equals the fresh folder's" -- \
        cmp <(fixed_tsv "$WORK/out") <(fixed_tsv "$WORK/fresh")
    expect_true "tables (all but the timing columns) equal the fresh folder's" -- \
        cmp <(fixed_md "$WORK/out") <(fixed_md "$WORK/fresh")
    expect_true "no run of the earlier call in the TSV (every sphere row at 12 px reaches 256 spp)" -- \
        awk -F'\t' '$1 == "sphere" && $3 == 256 { n++ } END { exit n != 5 }' "$WORK/out/convergence.tsv"
    expect_true "the peer's scaled error is positive in every row" -- \
        awk -F'|' 'NF == 8 && $2 ~ /[0-9]/ { split($3, e, "/"); if (!(e[2] + 0 > 0)) bad++ } END { exit bad > 0 }' \
        "$WORK/out/convergence.md"
    # An equal-time row is "-" exactly when its spp lies beyond the mode's last snapshot (mean
    # spp for adaptive): at 256 spp the 64-spp peer rows are measured (77-160 spp), the 1024-spp
    # rows (1200-2600 spp) are not, and the table says why.
    expect_true "equal-time rows are \"-\" exactly when beyond the last snapshot" -- \
        awk -F'\t' 'FNR == NR { if ($1 == "sphere") last[$2] = $4; next }
                    NF == 8 && $2 ~ /[0-9]/ {
                        m = $4; gsub(/ /, "", m); s = $5 + 0; dash = ($6 ~ /-/ && $6 !~ /[0-9]/)
                        if (dash != (s > last[m])) bad++; if (!dash) measured++; if (dash) missing++ }
                    END { exit bad > 0 || measured == 0 || missing == 0 }' \
        "$WORK/out/convergence.tsv" FS='|' "$WORK/out/convergence.md"
    expect_true "the table explains its \"-\" rows and names the MAX_SPP that measures them" -- \
        grep -q 'beyond this run.s last snapshot .*MAX_SPP [0-9]* measures them' "$WORK/out/convergence.md"

    # RESUME=1 keeps a run only when the binary, scene and command are the same.
    cp "$WORK/fresh/convergence.tsv" "$WORK/fresh.tsv"
    export RESUME=1
    expect_true "RESUME=1, same call" -- rc "$WORK/fresh" 256 12 6 128
    expect_true "RESUME=1, same call: all 11 runs kept" -- \
        grep -q '^RESUME=1: 11 run(s)' "$WORK/fresh/convergence.md"
    expect_true "RESUME=1, same call: the TSV unchanged, times too" -- \
        cmp "$WORK/fresh.tsv" "$WORK/fresh/convergence.tsv"
    expect_true "RESUME=1, other MAX_SPP" -- rc "$WORK/fresh" 64 12 6 128
    expect_true "RESUME=1, other MAX_SPP: only the patch reference kept" -- \
        grep -q '^RESUME=1: 1 run(s)' "$WORK/fresh/convergence.md"
    unset RESUME
fi
finish
