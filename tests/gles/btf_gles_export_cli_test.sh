#!/usr/bin/env bash
# btf-pca export-gles: a btf-pca folder to GLES shaders, atlases and lighting matrices
# (docs/btf-gles.md); bad inputs refused before anything is written, no partial outputs.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
PCA="$BIN/btf-pca"

make_small_btf
"$PCA" compress "$WORK/btf" -o "$WORK/pca" -k 2 -c 3 "${DIRS[@]}" >/dev/null 2>&1 || fail "compress"

expect_exit 0 "export-gles --help" -- "$PCA" export-gles --help
for opt in --bands --gles-versions --precision --irradiance-w-m2 --atlases; do
    grep -q -- "$opt" "$WORK/stdout" || fail "export-gles --help lacks $opt"
done
expect_exit 0 "btf-pca --help lists export-gles" -- "$PCA" --help
expect_true "the mode list names export-gles" -- grep -qF "export-gles" "$WORK/stdout"

# Success: every file the manifest names, deterministic bytes.
expect_exit 0 "export" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/out" --bands 3 --report "$WORK/r1.json"
for f in btf-gles.json btf-es300-highp.frag btf-es300-highp.vert btf-es100-highp.frag btf-es100-highp.vert \
    lighting-matrices.bin g000-atlas.png g002-atlas.png; do
    [[ -s "$WORK/out/$f" ]] || fail "missing $f"
done
expect_true "the manifest's matrices size is the file's" -- bash -c \
    "[[ \$(jq '.matrices.bytes' '$WORK/out/btf-gles.json') == \$(stat -c %s '$WORK/out/lighting-matrices.bin') ]]"
# 5 views x 3 channels x (1 + 3) rows x 9 columns x 4 bytes.
expect_true "matrices: 5 views x 3 x 4 x 9 floats" -- bash -c \
    "[[ \$(stat -c %s '$WORK/out/lighting-matrices.bin') == 2160 ]]"
expect_true "ES 1.00 fits ES 2.0's 16 vectors" -- bash -c \
    "[[ \$(jq '.variants[] | select(.glsl_version == \"100\") | .gl_limits_needed.max_fragment_uniform_vectors' '$WORK/out/btf-gles.json') -le 16 ]]"
expect_exit 0 "export again" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/out2" --bands 3
expect_true "same inputs, same bytes" -- diff -r "$WORK/out" "$WORK/out2"
expect_true "atlases written and said so" -- jq -e '.textures.atlas_files == true and .textures.groups[0].file == "g000-atlas.png"' "$WORK/out/btf-gles.json"
# --atlases none: no atlas PNG, the manifest says the app assembles them, every other file the same.
expect_exit 0 "export without atlases" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/none" --bands 3 --atlases none
expect_true "no atlas files" -- bash -c "! ls '$WORK/none' | grep -q atlas"
expect_true "the manifest says so" -- jq -e '.textures.atlas_files == false and ([.textures.groups[].file] | unique) == [null] and (.textures.assembly | test("assembles"))' "$WORK/none/btf-gles.json"
for f in btf-es300-highp.frag btf-es300-highp.vert btf-es100-highp.frag btf-es100-highp.vert lighting-matrices.bin; do
    expect_true "$f as with atlases" -- cmp "$WORK/out/$f" "$WORK/none/$f"
done
# 3 components per group: both highp variants named for their capabilities, none without highp.
expect_true "load table" -- jq -e '[.load[].variant] == ["btf-es300-highp", "btf-es100-highp", null]' "$WORK/out/btf-gles.json"
expect_exit 0 "ES 3.00 only" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/out3" --gles-versions 300
expect_true "no ES 1.00 shader" -- test ! -e "$WORK/out3/btf-es100-highp.frag"

# Usage errors: exit 2, nothing written.
expect_exit 2 "mediump refused" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/bad1" --precision mediump
expect_stderr "mediump guarantees a 10-bit mantissa" "says why mediump is refused"
expect_exit 2 "bands 10" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/bad2" --bands 10
expect_exit 2 "unknown version" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/bad3" --gles-versions 200
expect_exit 2 "NaN irradiance" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/bad4" --irradiance-w-m2 nan
expect_exit 2 "unknown --atlases" -- "$PCA" export-gles "$WORK/pca" -o "$WORK/bad9" --atlases some
expect_stderr "--atlases" "names the option"
expect_exit 2 "missing input" -- "$PCA" export-gles "$WORK/nope" -o "$WORK/bad5"
for d in bad1 bad2 bad3 bad4 bad5 bad9; do
    expect_true "$d: nothing written" -- test ! -e "$WORK/$d"
done

# Runtime errors: exit 1 naming the file, no partial output.
mkdir -p "$WORK/empty"
expect_exit 1 "not a btf-pca folder" -- "$PCA" export-gles "$WORK/empty" -o "$WORK/bad6"
expect_stderr "btf-pca.json" "names the manifest"
cp -r "$WORK/pca" "$WORK/cut"
rm "$WORK/cut/g001-c01.png"
expect_exit 1 "a component image missing" -- "$PCA" export-gles "$WORK/cut" -o "$WORK/bad7"
expect_stderr "g001-c01.png" "names the missing image"
"$PCA" compress "$WORK/btf" -o "$WORK/srgb" -k 2 -c 3 --fit-space srgb "${DIRS[@]}" >/dev/null 2>&1 || fail "compress srgb"
expect_exit 1 "sRGB fit space refused" -- "$PCA" export-gles "$WORK/srgb" -o "$WORK/bad8"
expect_stderr "only the linear fit space" "says why"
# The irradiance: given, else btf-pca.json's (a capture's), else 1.
expect_true "no recorded irradiance: E = 1" -- jq -e '.matrices.irradiance_w_m2 == 1' "$WORK/out/btf-gles.json"
cp -r "$WORK/pca" "$WORK/lit"
jq '.irradiance_w_m2 = 2.5' "$WORK/pca/btf-pca.json" >"$WORK/lit/btf-pca.json"
expect_exit 0 "the folder's irradiance" -- "$PCA" export-gles "$WORK/lit" -o "$WORK/lit-out" --bands 3
expect_true "E = btf-pca.json's 2.5" -- jq -e '.matrices.irradiance_w_m2 == 2.5' "$WORK/lit-out/btf-gles.json"
# The matrices divide by E: the first float at E = 2.5 is 1 / 2.5 of the one at E = 1.
expect_true "the matrices scale as 1 / E" -- bash -c "[[ \$(od -An -f -N4 '$WORK/lit-out/lighting-matrices.bin' | awk '{printf \"%.4g\", \$1 * 2.5}') == \$(od -An -f -N4 '$WORK/out/lighting-matrices.bin' | awk '{printf \"%.4g\", \$1}') ]]"
expect_exit 0 "a given irradiance wins" -- "$PCA" export-gles "$WORK/lit" -o "$WORK/lit-given" --bands 3 --irradiance-w-m2 1
expect_true "E = 1 as given" -- cmp "$WORK/out/lighting-matrices.bin" "$WORK/lit-given/lighting-matrices.bin"
jq '.irradiance_w_m2 = -1' "$WORK/pca/btf-pca.json" >"$WORK/lit/btf-pca.json"
expect_exit 1 "a negative recorded irradiance" -- "$PCA" export-gles "$WORK/lit" -o "$WORK/bad10"
expect_stderr "lit/btf-pca.json: irradiance_w_m2" "names the file and the key"
for d in bad6 bad7 bad8 bad10; do
    expect_true "$d: nothing written" -- test ! -e "$WORK/$d"
done
finish
