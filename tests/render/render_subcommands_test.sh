#!/usr/bin/env bash
# render's subcommands (docs/render.md "Usage"): each one's --help lists its own options and not
# another mode's, with a one-line example; an older command line (mode flags, no subcommand) is
# refused with exit 2 naming the new spelling, before any work; export-gles writes the GLES
# export without path tracing, the same files for any thread count, and the same table data and
# shaders as brdf-sh-bake's export of the same material for the same view.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
SRC=${INLIGHT_SOURCE_DIR:?}
FURNACE="$SRC/configs/scenes/sphere_furnace.toml"
SATIN_FABRIC="$SRC/configs/fabrics/satin.toml"

expect_exit 0 "render --help" -- "$R" --help
for mode in trace compare convergence capture-btf shade-btf export-gles; do
    expect_true "render --help lists $mode" -- grep -qE "^ +$mode( |$)" "$WORK/stdout"
done
expect_exit 2 "render without a subcommand is a usage error" -- "$R"
expect_exit 2 "an unknown subcommand is a usage error" -- "$R" frobnicate

# has MODE OPTION... / lacks MODE OPTION...: the option lines of `render MODE --help` (an option
# line starts with the option's name, so a mention inside another option's help does not count).
help_of() { "$R" "$1" --help > "$WORK/help_$1.txt" 2>&1; }
listed() {  # listed WANT MODE OPTION...: WANT = 1 each is listed, 0 none is
    local want=$1 mode=$2 opt got
    shift 2
    for opt in "$@"; do
        got=0
        grep -qE -- "^ +(-[a-zA-Z],)?$opt( |$)" "$WORK/help_$mode.txt" && got=1
        if [ "$got" = "$want" ]; then pass "$mode --help: $opt listed $got"; else
            fail "$mode --help: $opt listed $got, expected $want"; fi
    done
}
has() { listed 1 "$@"; }
lacks() { listed 0 "$@"; }
for mode in trace compare convergence capture-btf shade-btf export-gles; do
    expect_exit 0 "render $mode --help" -- "$R" "$mode" --help
    help_of "$mode"
    expect_true "$mode: its one-line example" -- grep -qE "^  render $mode " "$WORK/help_$mode.txt"
    has "$mode" --report --threads --seed --config --version
done
has trace --spp --time-budget-s --target-rel-error --sampler --adaptive --max-rel-error --stderr-output
lacks trace --rt-grid --rt-max-bands --decompose --rt-lighting --brdf-table --exposure --ref-spp \
    --btf-lights --btf --environment --gles-versions --export-gles --compare
has compare --spp --rt-grid --rt-max-bands --rt-bake-samples --rt-supersample --brdf-table \
    --rt-lighting --decompose --decompose-map-height --exposure --heat-max-rel
lacks compare --ref-spp --ref-image --btf-lights --environment --gles-versions --export-gles --grid
has convergence --spp --sampler --ref-spp --ref-image --ref-irradiance
lacks convergence --rt-grid --decompose --exposure --btf-lights --gles-versions
has capture-btf --btf-lights --btf-views --btf-pairs --btf-format --irradiance-w-m2 --spp --width-px \
    --max-depth --no-jitter
lacks capture-btf --sampler --adaptive --time-budget-s --target-rel-error --max-rel-error \
    --stderr-output --rt-grid --environment --exposure --ref-spp --gles-versions
has shade-btf --btf --environment --shade-views --btf-compressed --shade-stream --exposure --spp
lacks shade-btf --btf-lights --btf-format --sampler --adaptive --rt-grid --ref-spp --gles-versions
has export-gles --gles-versions --gles-modes --gles-lighting --grid --bake-samples
lacks export-gles --spp --sampler --rt-grid --rt-bake-samples --exposure --export-gles --width-px

# A mode's option under another mode is an unknown option (exit 2), nothing written.
expect_exit 2 "trace --rt-grid is a usage error" -- "$R" trace "$FURNACE" -o "$WORK/u.exr" --rt-grid octa:9
expect_stderr "rt-grid" "the error names the option"
expect_exit 2 "capture-btf --adaptive is a usage error" -- "$R" capture-btf "$SATIN_FABRIC" -o "$WORK/u" --adaptive
expect_exit 2 "convergence needs a reference" -- "$R" convergence "$FURNACE" -o "$WORK/u.exr" --spp 4
expect_stderr "convergence needs a reference: --ref-spp N, --ref-image EXR or --ref-irradiance" \
    "the error names the three references"
expect_true "nothing written by the usage errors" -- bash -c "! ls '$WORK'/u* 2>/dev/null | grep -q ."

# The old spellings: exit 2, the new command line named, nothing written (even a report: the
# command line is not parsed at all).
old() {  # old SUBCOMMAND DESCRIPTION -- ARGS...
    local want=$1 what=$2
    shift 3
    expect_exit 2 "old spelling: $what" -- "$R" "$@"
    expect_stderr "^render: modes are subcommands now: use 'render $want" "$what: names 'render $want'"
    expect_stderr "(see render --help)" "$what: points at render --help"
}
old "trace SCENE -o OUT'" "render SCENE -o OUT" -- "$FURNACE" -o "$WORK/o.exr" --spp 1
old "compare SCENE -o OUT'" "--compare" -- "$FURNACE" -o "$WORK/o.exr" --compare --rt-max-bands 3
old "compare SCENE -o OUT'" "--rt-decompose" -- "$FURNACE" -o "$WORK/o.exr" --compare --rt-decompose
old "convergence SCENE -o OUT --ref-spp N'" "--convergence-ref-spp" -- \
    "$FURNACE" -o "$WORK/o.exr" --convergence-ref-spp 64
old "convergence" "--convergence-ref-irradiance" -- "$FURNACE" -o "$WORK/o.exr" --no-jitter \
    --convergence-ref-irradiance
old "capture-btf FABRIC -o FOLDER'" "--btf-capture" -- "$SATIN_FABRIC" --btf-capture -o "$WORK/o"
old "shade-btf FABRIC --btf FOLDER" "--btf-shade" -- "$SATIN_FABRIC" --btf-shade "$WORK" -o "$WORK/o"
old "export-gles SCENE -o DIR'" "--export-gles" -- "$FURNACE" -o "$WORK/o.exr" --export-gles "$WORK/o"
old "trace SCENE -o OUT'" "options first" -- -o "$WORK/o.exr" --report "$WORK/o.json" "$FURNACE"
expect_true "nothing written by the old spellings" -- bash -c "! ls '$WORK'/o* 2>/dev/null | grep -q ."

# export-gles: a GGX patch seen from +z (the view brdf-sh-bake bakes for by default).
cat > "$WORK/patch.toml" <<TOML
[environment]
radiance = [1, 1, 1]
[camera]
projection = "orthographic"
position = [0, 0, 1]
width_px = 8
height_px = 8
[material.satin]
file = "$SRC/configs/materials/satin-ggx.toml"
[[object]]
shape = "patch"
material = "satin"
TOML
GL=(--grid octa:5 --bake-samples 256 --gles-precisions highp)
expect_exit 0 "export-gles, 1 thread" -- "$R" export-gles "$WORK/patch.toml" -o "$WORK/g1" "${GL[@]}" \
    --threads 1 --report "$WORK/g1.json"
expect_true "no path tracing: the stages are loading the scene and the export" -- \
    jq -e '(.stage_time_s | keys) == ["export gles", "load scene"]' "$WORK/g1.json"
expect_true "4 variants (2 versions x 2 modes, highp), counted in the report" -- jq -e \
    '[.variants[].name] == ["satin-es100-consistent-b3-highp", "satin-es100-seed-b3-highp",
                           "satin-es300-consistent-b3-highp", "satin-es300-seed-b3-highp"]' "$WORK/g1/index.json"
expect_true "the report counts them and lists the files" -- jq -e \
    '.metrics.gles_export.variants == 4 and ([.outputs[] | select(.kind == "gles_export")] | length == 17)' \
    "$WORK/g1.json"
expect_exit 0 "export-gles, 2 threads" -- "$R" export-gles "$WORK/patch.toml" -o "$WORK/g2" "${GL[@]}" --threads 2
expect_true "the same bytes for 1 and 2 threads" -- diff -r "$WORK/g1" "$WORK/g2"
# The same material baked by brdf-sh-bake at the same grid, samples and bands for the same view:
# the tables and shaders render exports are the ones brdf-sh-bake exports (bytes equal).
expect_exit 0 "brdf-sh-bake exports the same material" -- "$BIN/brdf-sh-bake" \
    --material "$SRC/configs/materials/satin-ggx.toml" --grid octa:5 --sh-bands 3 --samples 256 \
    -o "$WORK/satin" --export-gles "$WORK/gb" --gles-precisions highp
for f in "$WORK"/gb/*.brdf.bin "$WORK"/gb/*.vert "$WORK"/gb/*.frag; do
    expect_true "$(basename "$f"): the same bytes from render export-gles" -- cmp "$f" "$WORK/g1/$(basename "$f")"
done
expect_exit 2 "export-gles: an unknown GLSL version is a usage error" -- \
    "$R" export-gles "$WORK/patch.toml" -o "$WORK/g3" --gles-versions 100,200
expect_exit 2 "export-gles: -o naming the scene file" -- "$R" export-gles "$WORK/patch.toml" -o "$WORK/patch.toml"
expect_stderr "(-o) needs the folder" "the error names -o"
expect_true "nothing written by the usage errors" -- test ! -e "$WORK/g3"
finish
