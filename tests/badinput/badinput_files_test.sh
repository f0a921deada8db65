#!/usr/bin/env bash
# Bad input files, at least one per loader a tool reads: images (EXR, HDR, PNG), TOML (scene,
# material, fabric via bundle, --config), OBJ and PLY meshes, OpenCV corner files, response JSON
# and bundle manifests; plus the silent defaults the hostile sweep found (an empty material file or one
# without `specular` baked a default GGX without a word). Each: exit code, a message naming the
# file and the problem, $OUT as it was. (The SH coefficient and BTF readers have no tool yet:
# fuzz/ replays their seeds and crash inputs, and their unit tests hold the bad-file cases.)
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
# shellcheck source=tests/badinput/lib.sh
source "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/../.." && pwd)
EP="$BIN/envmap-project"
BAKE="$BIN/brdf-sh-bake"
R="$BIN/render"
CAL="$BIN/calibrate"
MK="$TBIN/inlight_make_test_image"
"$MK" "$WORK/env.exr" 32 16 0.5

# Images: truncated EXR, garbage HDR and PNG, an empty file.
head -c 200 "$WORK/env.exr" > "$WORK/truncated.exr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 99999 +X 99999\nshort' > "$WORK/garbage.hdr"
printf '\x89PNG\r\n\x1a\nnot really a png' > "$WORK/garbage.png"
: > "$WORK/empty.exr"
bad 1 "truncated.exr" "truncated EXR" -- "$EP" "$WORK/truncated.exr" -o "$OUT/t_sh.json"
bad 1 "garbage.hdr" "HDR with a lying header" -- "$EP" "$WORK/garbage.hdr" -o "$OUT/g_sh.json"
bad 1 "garbage.png" "garbage PNG" -- "$EP" "$WORK/garbage.png" -o "$OUT/g_sh.json"
bad 1 "empty.exr" "empty EXR" -- "$EP" "$WORK/empty.exr" -o "$OUT/e_sh.json"
# A file is read only by the reader its extension names: OpenImageIO's fallback to its other
# readers read this PNG named .exr as a PNG, exit 0.
"$MK" "$WORK/env.png" 32 16 0.5
cp "$WORK/env.png" "$WORK/png_named.exr"
bad 1 "png_named.exr: cannot open: .*not an OpenEXR file" "PNG named .exr" -- \
    "$EP" "$WORK/png_named.exr" -o "$OUT/p_sh.json"
# Length fields larger than the file (fuzz/regressions/image, btf): refused before OpenEXR or
# libpng allocate them (they cost 2 GB and minutes). A string attribute claiming 1.9 GB in an
# EXR of 600 bytes; a PNG tEXt chunk claiming 1.7 GB; an EXR whose data window needs more
# samples than its bytes can decode to (8192x8192x3, zip, 20 KB).
tail -c +2 "$SRC/fuzz/regressions/image/exr_string_attribute_1.9GB" > "$WORK/lying_attr.exr"
bad 1 "lying_attr.exr: EXR attribute 'inlight:color_space' claims 1920139275 bytes" \
    "EXR attribute longer than the file" -- "$EP" "$WORK/lying_attr.exr" -o "$OUT/l_sh.json"
printf '\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x04\0\0\0\x02\x08\x02\0\0\0\xfa\x04\x8e\xa6\x69\x6d\x1f\x54tEXtxx' > "$WORK/lying_chunk.png"
bad 1 "lying_chunk.png: PNG chunk 'tEXt' at byte 33 claims 1768759124 bytes" \
    "PNG chunk longer than the file" -- "$EP" "$WORK/lying_chunk.png" -o "$OUT/l_sh.json"
# 3997697 x 1 half pixels in 323 bytes and no compression attribute (fuzz/regressions/image):
# OpenEXR reads it as ZIP, so its bytes decode to ~80 K samples, not the 8 M it claims; bounded
# as an unknown compression it passed, and OpenEXR and OpenImageIO asked for 4 GB.
tail -c +2 "$SRC/fuzz/regressions/image/exr_wide_row_oiio_chunk_4gb" > "$WORK/wide_row.exr"
bad 1 "wide_row.exr: header claims 3997697x1x[0-9]*, more than the file's bytes can decode to" \
    "EXR without a compression attribute" -- "$EP" "$WORK/wide_row.exr" -o "$OUT/w_sh.json"
python3 - "$WORK/env.exr" "$WORK/huge_window.exr" <<'PY'
import struct, sys
data = bytearray(open(sys.argv[1], "rb").read())
at = data.index(b"dataWindow\0box2i\0") + len(b"dataWindow\0box2i\0") + 4
data[at:at + 16] = struct.pack("<4i", 0, 0, 8191, 8191)
open(sys.argv[2], "wb").write(bytes(data) + bytes(20000))
PY
bad 1 "huge_window.exr: .*more than its .* chunks\|huge_window.exr: header claims 8192x8192x3" \
    "EXR data window larger than its bytes can decode to" -- "$EP" "$WORK/huge_window.exr" -o "$OUT/l_sh.json"

# Files that never end: a FIFO or /dev/zero where a file is expected was read forever (a hang,
# or memory until the kernel stepped in). Named on the command line: a usage error; named in a
# file or read by a loader: a data error. (timeout: a regression fails instead of hanging.)
mkfifo "$WORK/fifo.exr" "$WORK/fifo.yml"
bad 2 "fifo.exr' is a FIFO" "FIFO as an input image" -- timeout 60 "$EP" "$WORK/fifo.exr" -o "$OUT/f_sh.json"
bad 2 "/dev/zero' is a character device" "/dev/zero as render's scene" -- timeout 60 "$R" trace /dev/zero -o "$OUT/z.exr"
bad 2 "/dev/zero' is a character device" "/dev/zero as a material" -- timeout 60 "$BAKE" --material /dev/zero -o "$OUT/z"
bad 2 "/dev/zero: is a character device" "/dev/zero as --config" -- \
    timeout 60 "$EP" "$WORK/env.exr" -o "$OUT/c_sh.json" --config /dev/zero
bad 1 "fifo.yml: is a FIFO" "FIFO as a corner file" -- \
    timeout 60 "$CAL" geometry --image-points "$WORK/fifo.yml" --board 3x2 -o "$OUT/cal"
printf '[environment]\npath = "/dev/zero"\n[camera]\nwidth_px = 8\nheight_px = 8\n[material.m]\nspecular = "lambert"\n[[object]]\nmaterial = "m"\nshape = "sphere"\n' > "$WORK/zero_env.toml"
bad 1 "/dev/zero: is a character device" "scene whose environment map is /dev/zero" -- \
    timeout 60 "$R" trace "$WORK/zero_env.toml" -o "$OUT/z.exr"

# --config: a TOML syntax error names file, line and column; a binary file says it is binary.
printf 'sh-bands = 3\nvalidate = = true\n' > "$WORK/syntax.toml"
bad 2 "syntax.toml:2:[0-9]*: TOML syntax error" "TOML syntax error in --config" -- \
    "$EP" "$WORK/env.exr" -o "$OUT/c_sh.json" --config "$WORK/syntax.toml"
# A table header whose key starts with '`': toml++ 3.3 asserted on it in a debug build.
printf '[\x60x\x60]\nsh-bands = 3\n' > "$WORK/backtick.toml"
bad 2 "backtick.toml:1:2: TOML syntax error.*bare key" "TOML table header with a backtick" -- \
    "$EP" "$WORK/env.exr" -o "$OUT/c_sh.json" --config "$WORK/backtick.toml"
cp "$WORK/env.exr" "$WORK/binary.toml"
bad 2 "binary.toml.*binary" "binary file as --config" -- "$EP" "$WORK/env.exr" -o "$OUT/c_sh.json" --config "$WORK/binary.toml"
printf 'sh-bandz = 3\n' > "$WORK/typo.toml"
bad 2 "typo.toml:1: unknown key 'sh-bandz'" "unknown key in --config" -- \
    "$EP" "$WORK/env.exr" -o "$OUT/c_sh.json" --config "$WORK/typo.toml"

# Material files: silent defaults are errors now; a syntax error names line and column.
: > "$WORK/empty.toml"
bad 1 "empty.toml: specular: required key is missing" "empty material file" -- \
    "$BAKE" --material "$WORK/empty.toml" -o "$OUT/m"
printf 'alpha = 0.3\nf0 = 0.04\n' > "$WORK/nospec.toml"
bad 1 "nospec.toml: specular: required key is missing" "material file without specular" -- \
    "$BAKE" --material "$WORK/nospec.toml" -o "$OUT/m"
printf 'specular = 3\n' > "$WORK/mtype.toml"
bad 1 "error: [^ ]*mtype.toml:1: specular: expected a string, got a number" "material specular of the wrong type (file named once)" -- \
    "$BAKE" --material "$WORK/mtype.toml" -o "$OUT/m"
printf 'specular = "ggx"\nalpha = 0.3 0.4\n' > "$WORK/msyntax.toml"
bad 1 "msyntax.toml:2:[0-9]*: TOML syntax error" "material syntax error" -- \
    "$BAKE" --material "$WORK/msyntax.toml" -o "$OUT/m"

# Scene files (render): syntax, NaN rotation of the environment, a material without specular,
# and meshes holding NaN, Inf, garbage or out-of-range indices.
scene() {  # scene FILE ENV_LINES MATERIAL_LINES OBJECT_LINES
    printf '[environment]\nradiance = 1\n%s\n[camera]\nwidth_px = 8\nheight_px = 8\n[material.m]\n%s\n[[object]]\nmaterial = "m"\n%s\n' \
        "$2" "$3" "$4" > "$1"
}
scene "$WORK/ok.toml" '' 'specular = "lambert"' 'shape = "sphere"'
expect_exit 0 "the scene the bad ones derive from renders" -- "$R" trace "$WORK/ok.toml" -o "$WORK/ok.exr" --spp 1
scene "$WORK/rotnan.toml" 'rotation = "z=nan"' 'specular = "lambert"' 'shape = "sphere"'
bad 1 "rotnan.toml:.*rotation" "scene rotation z=nan" -- "$R" trace "$WORK/rotnan.toml" -o "$OUT/s.exr"
scene "$WORK/nospec_scene.toml" '' 'albedo = 0.5' 'shape = "sphere"'
bad 1 "nospec_scene.toml:.*\[material.m\] specular: required key is missing" "scene material without specular" -- \
    "$R" trace "$WORK/nospec_scene.toml" -o "$OUT/s.exr"
printf '[environment]\nradiance = 1\n[camera\n' > "$WORK/ssyntax.toml"
bad 1 "ssyntax.toml:3:[0-9]*: TOML syntax error" "scene syntax error" -- "$R" trace "$WORK/ssyntax.toml" -o "$OUT/s.exr"
bad_mesh() {  # bad_mesh FILE CONTENT PATTERN DESCRIPTION [ROTATION]: a scene with that mesh fails
    printf '%b' "$2" > "$WORK/$1"
    scene "$WORK/$1.toml" '' 'specular = "lambert"' "shape = \"mesh\"
path = \"$WORK/$1\"
rotation = \"${5:-none}\""
    bad 1 "$3" "$4" -- "$R" trace "$WORK/$1.toml" -o "$OUT/s.exr"
}
bad_mesh nan.obj 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n' "nan.obj:3" "OBJ vertex with NaN"
bad_mesh index.obj 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' "index.obj:4" "OBJ face index out of range"
PLY_HEAD='ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n'
bad_mesh inf.ply "${PLY_HEAD}0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n" "inf.ply" "PLY vertex with Inf"
bad_mesh short.ply 'ply\nformat binary_little_endian 1.0\nelement vertex 1000000\nproperty float x\nend_header\nxx' \
    "short.ply" "binary PLY shorter than its header says"
bad_mesh ok.obj 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' "ok.obj.toml:.*rotation" "mesh rotation x=nan" "x=nan"
# Meshes that rendered as nothing with exit 0: a coordinate past float's range (Embree's
# vertices are float), triangles all of zero area, a PLY vertex without z (read as 0), and
# unknown types or versions read as "no triangles".
bad_mesh far.obj 'v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n' "far.obj: vertex 2: coordinate 1e+39 is outside" "OBJ vertex past float's range"
bad_mesh flat.obj 'v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n' "flat.obj: all 1 triangles have zero area" "OBJ whose triangles have no area"
bad_mesh noz.ply 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n' \
    "noz.ply: PLY element 'vertex' has no property 'z'" "PLY vertex without z"
bad_mesh quat.ply 'ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n1\n' \
    "quat.ply: unknown PLY property type 'quaternion'" "PLY property of an unknown type"
bad_mesh v2.ply 'ply\nformat ascii 2.0\nelement vertex 0\nend_header\n' "v2.ply: PLY format version '2.0'" "PLY of another version"

# Corner files (calibrate geometry --image-points): NaN, a missing node, not YAML at all.
corners() {  # corners FILE FIRST_VALUE
    printf '%%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\nimage_0: [ %s, 80., 140., 80., 180., 80., 100., 120., 140., 120., 180., 120. ]\n' "$2" > "$1"
}
corners "$WORK/nan_corners.yml" .nan
bad 1 "nan_corners.yml.*image_0" "corner file holding NaN" -- \
    "$CAL" geometry --image-points "$WORK/nan_corners.yml" --board 3x2 -o "$OUT/cal"
printf '%%YAML:1.0\n---\nimage_width: 640\n' > "$WORK/no_views.yml"
bad 1 "no_views.yml" "corner file without views" -- \
    "$CAL" geometry --image-points "$WORK/no_views.yml" --board 3x2 -o "$OUT/cal"
# OpenCV 4.6's YAML parser loops forever on an indented top level followed by a dedent
# (fuzz/regressions/corners); a top level that is a sequence made OpenCV assert.
printf '%%YAML:1.0\n   - 1\nimage_0: [ 1, 2 ]\n' > "$WORK/indented.yml"
bad 1 "indented.yml:2: the top-level collection must start at column 1" "indented YAML top level" -- \
    "$CAL" geometry --image-points "$WORK/indented.yml" --board 3x2 -o "$OUT/cal"
printf '%%YAML:1.0\n- 1\n- 2\n' > "$WORK/sequence.yml"
bad 1 "sequence.yml:2: a top-level key must start with a letter" "YAML top level a sequence" -- \
    "$CAL" geometry --image-points "$WORK/sequence.yml" --board 3x2 -o "$OUT/cal"
# "--a:" over an indented sequence and an empty key: OpenCV 4.6 called std::terminate.
printf '%%YAML:1.0\n--a:\n   - 1\n  :\n' > "$WORK/dashkey.yml"
bad 1 "dashkey.yml:2: a top-level key must start with a letter" "YAML key starting with --" -- \
    "$CAL" geometry --image-points "$WORK/dashkey.yml" --board 3x2 -o "$OUT/cal"
cp "$WORK/env.exr" "$WORK/binary.yml"
bad 1 "binary.yml" "binary file as corner file" -- \
    "$CAL" geometry --image-points "$WORK/binary.yml" --board 3x2 -o "$OUT/cal"

# Response curves (envmap-project --response): not JSON, wrong format, short curves.
"$MK" "$WORK/frame.png" 32 16 0.5
printf '{"format": "inlight_response", "channels": ["r"], "g": [[0, 1]]' > "$WORK/notjson.json"
bad 1 "notjson.json" "response file that is not JSON" -- \
    "$EP" "$WORK/frame.png" -o "$OUT/r_sh.json" --response "$WORK/notjson.json" --exposure-s 0.01
printf '{"format": "something_else"}' > "$WORK/format.json"
bad 1 "format.json.*inlight_response" "response file of another format" -- \
    "$EP" "$WORK/frame.png" -o "$OUT/r_sh.json" --response "$WORK/format.json" --exposure-s 0.01
printf '{"format": "inlight_response", "channels": ["r", "g", "b"], "g": [[0, 1], [0, 1], [0, 1]]}' > "$WORK/short.json"
bad 1 "short.json.*256" "response curves of 2 values" -- \
    "$EP" "$WORK/frame.png" -o "$OUT/r_sh.json" --response "$WORK/short.json" --exposure-s 0.01

# A curve past any camera's range (g = 1e308, ln exposure) or an exposure that takes radiance
# past float: blamed on the frame ("pixel (x=0, y=0) is Inf; pass --nonfinite zero").
python3 -c "print('{\"format\": \"inlight_response\", \"channels\": [\"r\", \"g\", \"b\"], \"g\": [' + ','.join(['[' + ','.join(['1e308'] * 256) + ']'] * 3) + ']}')" > "$WORK/huge_g.json"
bad 1 "huge_g.json: curve 0, code 0: g = 1e+308 is outside" "response curve past any camera's range" -- \
    "$EP" "$WORK/frame.png" -o "$OUT/r_sh.json" --response "$WORK/huge_g.json" --exposure-s 0.01
python3 -c "print('{\"format\": \"inlight_response\", \"channels\": [\"r\", \"g\", \"b\"], \"g\": [' + ','.join(['[' + ','.join([str(i / 255) for i in range(256)]) + ']'] * 3) + ']}')" > "$WORK/ok_g.json"
bad 1 "past the float range (check the curve and --exposure-s)" "--exposure-s 1e-300 (radiance past float)" -- \
    "$EP" "$WORK/frame.png" -o "$OUT/r_sh.json" --response "$WORK/ok_g.json" --exposure-s 1e-300

# Bundle manifests (bundle verify): not JSON, traversal.
mkdir -p "$WORK/bundle1" "$WORK/bundle2"
printf '{"format": "inlight_bundle", ' > "$WORK/bundle1/manifest.json"
bad 1 "manifest.json.*not valid JSON" "bundle manifest that is not JSON" -- "$BIN/bundle" verify "$WORK/bundle1"
printf '{"format": "inlight_bundle", "version": 1, "kind": "fabric", "id": "x", "name": "x", "created_by": "t", "properties": {}, "files": [{"path": "../../etc/passwd", "role": "albedo", "media_type": "image/png", "color_space": "srgb", "bytes": 1, "sha256": "%064d", "width_px": 1, "height_px": 1, "stream_index": -1}]}' 0 > "$WORK/bundle2/manifest.json"
bad 1 "\.\." "bundle manifest with a path out of the bundle" -- "$BIN/bundle" verify "$WORK/bundle2"
# 30000 nested arrays in "properties" (60 kB): refused before any recursive walk (it crashed
# the reader with a stack overflow before every JSON read went through core/json_in.h).
mkdir -p "$WORK/bundle3"
python3 -c "d = 30000; print('{\"format\": \"inlight_bundle\", \"version\": 1, \"kind\": \"fabric\", \"id\": \"bundle3\", \"name\": \"x\", \"created_by\": \"t\", \"properties\": {\"p\": ' + '[' * d + ']' * d + '}, \"files\": []}')" > "$WORK/bundle3/manifest.json"
bad 1 "bundle3/manifest.json: arrays/objects nested deeper than 64" "bundle manifest nested 30000 deep" -- "$BIN/bundle" verify "$WORK/bundle3"
mkdir -p "$WORK/root3/fabrics" && cp -r "$WORK/bundle3" "$WORK/root3/fabrics/bundle3"
bad 1 "manifest.json: arrays/objects nested deeper than 64" "bundle index of a manifest nested 30000 deep" -- "$BIN/bundle" index "$WORK/root3" -o "$OUT/deep.sqlite"
# A bundle folder in a root that is a symlink out of it: refused, naming the link, before anything
# is read through it (the linked bundle is the deep one above: the link is what is reported).
mkdir -p "$WORK/root4/fabrics" && ln -s "$WORK/bundle3" "$WORK/root4/fabrics/bundle3"
bad 1 "root4/fabrics/bundle3: resolves through a symlink to .*, outside the bundle root" "bundle verify of a root holding a bundle linked from outside" -- "$BIN/bundle" verify "$WORK/root4"
bad 1 "root4/fabrics/bundle3: resolves through a symlink to .*, outside the bundle root" "bundle index of that root" -- "$BIN/bundle" index "$WORK/root4" -o "$OUT/linked.sqlite"
finish
