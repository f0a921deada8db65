# shellcheck shell=bash
# Tiny inputs for the pipeline tests (sourced after tests/cli/lib.sh): a catalogue folder of
# small fabrics made from blender-data's woven texture, with a fast BRDF bake and validation.
TEXTURE=/usr/share/blender/scripts/addons/archimesh/images/fabric_diffuse.png
HDRI_DIR=/usr/share/blender/datafiles/studiolights/world
ROOT=${INLIGHT_SOURCE_DIR:?}
export PIPE="$ROOT/pipelines"
require_blender_data() {
    if [ ! -f "$TEXTURE" ] || [ ! -d "$HDRI_DIR" ]; then
        echo "skip: blender-data not installed (make deps)"
        exit 77
    fi
}

# make_fabric DIR NAME ALPHA: a fabric folder with a 64-pixel texture and a small BRDF grid.
make_fabric() {
    mkdir -p "$1"
    cat > "$1/fabric.toml" <<TOML
name = "$2"
albedo-texture = "$TEXTURE"
relief-texels = 1.5
tile-size-m = 0.05
max-size-px = 64
thumbnail-px = 32
TOML
    printf 'specular = "ggx"\nalbedo = [1, 1, 1]\nf0 = [0.04, 0.04, 0.04]\nalpha = %s\n' "$3" > "$1/material.toml"
    printf 'grid = "thetaphi:5x8"\nsh-bands = 3\nintegrator = "gauss-legendre"\nsamples = 256\n' \
        > "$1/brdf-sh-bake.toml"
}

# make_captured_fabric DIR NAME: a captured-BTF fabric: weave.toml + capture.toml (4 x 4 px,
# 1 spp: the whole 81 x 81 dome in a few seconds), 3 view groups of 27 with 4 components, no
# albedo texture (the capture's frontal image stands in).
make_captured_fabric() {
    make_fabric "$1" "$2" 0.3
    sed -i '/^albedo-texture/d' "$1/fabric.toml"
    cp "$ROOT/configs/fabrics/wool-twill.toml" "$1/weave.toml"
    printf 'width-px = 4\nheight-px = 4\nspp = 1\n' > "$1/capture.toml"
    printf 'view-group-size = 27\ncomponents = 4\n' > "$1/btf-pca.toml"
}

# make_catalog DIR NFABRICS ENV...: fabrics f1..fN and the given environments.
make_catalog() {
    local dir=$1 n=$2 i
    shift 2
    for i in $(seq 1 "$n"); do make_fabric "$dir/fabrics/f$i" "Fabric $i" "0.$((i + 1))"; done
    {
        printf 'environments = ['
        local sep=""
        for e in "$@"; do printf '%s"%s"' "$sep" "$e"; sep=", "; done
        printf ']\n'
    } > "$dir/catalog.toml"
    printf 'spp = 8\nwidth-px = 16\nheight-px = 16\nrt-max-bands = 4\nrt-supersample = 1\n' > "$dir/validate.toml"
}

# tiny_catalog NFABRICS: the Snakemake tests' set-up: skips without blender-data, makes CAT (a
# catalogue of NFABRICS fabrics under night.exr) with its fast validation options
# (VALIDATE_RENDER_CONFIG, and no band budget: VALIDATE_MAX_ERROR=0) and names OUT, the
# bake-catalog output folder, both in WORK. The budget (envmap-project --max-error with the
# fabric's table: about half of each pair's time) is graded by no Snakemake test; its step of
# validate-pair.sh and its report column are checked by bake_pipelines_test.sh.
tiny_catalog() {
    require_blender_data
    CAT="$WORK/cat"
    # shellcheck disable=SC2034  # OUT is the calling test's
    OUT="$WORK/out"
    make_catalog "$CAT" "$1" "$HDRI_DIR/night.exr"
    export VALIDATE_RENDER_CONFIG="$CAT/validate.toml" VALIDATE_MAX_ERROR=0
}
