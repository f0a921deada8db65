#!/usr/bin/env bash
# Outputs, the classes of the hostile sweep (docs/fuzzing.md): an output naming an input (calibrate response's image, the
# scene's environment map, a bundle's file) or another output (--stderr-output = -o; two inputs of one stem into
# one folder) is a usage error naming both, found before any work; a run that fails after some
# of its outputs could be written (the second of two envmap-project inputs is bad; the .json of
# brdf-sh-bake cannot be placed) leaves nothing, the output folder as it was.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
# shellcheck source=tests/badinput/lib.sh
source "$(dirname "$0")/lib.sh"
SRC=${INLIGHT_SOURCE_DIR:?}
EP="$BIN/envmap-project"
MK="$TBIN/inlight_make_test_image"

# Inputs overwritten: -o naming an input of calibrate response.
"$MK" "$WORK/a.png" 32 16 0.2
"$MK" "$WORK/b.png" 32 16 0.6
cp "$WORK/a.png" "$WORK/a_orig.png"
bad 2 "a.png" "calibrate response -o naming an input image" -- \
    "$BIN/calibrate" response --images "$WORK/a.png" "$WORK/b.png" --exposure-s 0.01 0.04 -o "$WORK/a.png"
same_file "$WORK/a.png" "$WORK/a_orig.png" "the input image is untouched"

# render -o naming the scene's environment map.
"$MK" "$WORK/sky.exr" 32 16 1
cp "$WORK/sky.exr" "$WORK/sky_orig.exr"
printf '[environment]\npath = "sky.exr"\n[camera]\nwidth_px = 8\nheight_px = 8\n[material.m]\nspecular = "lambert"\n[[object]]\nmaterial = "m"\nshape = "sphere"\n' > "$WORK/scene.toml"
bad 2 "sky.exr" "render -o naming the scene's environment map" -- "$BIN/render" trace "$WORK/scene.toml" -o "$WORK/sky.exr" --spp 1
same_file "$WORK/sky.exr" "$WORK/sky_orig.exr" "the environment map is untouched"

# An output folder that exists as a file (here the scene itself): refused before rendering, not
# when the shaders are written at the end.
cp "$WORK/scene.toml" "$WORK/scene_orig.toml"
bad 2 "(-o) needs the folder .*scene.toml', which is an existing file" \
    "render export-gles -o naming the scene file" -- \
    "$BIN/render" export-gles "$WORK/scene.toml" -o "$WORK/scene.toml"
same_file "$WORK/scene.toml" "$WORK/scene_orig.toml" "the scene file is untouched"

# render's --convergence-ref-image: -o naming it was not caught as an input, and a reference of
# the wrong size was found only after path tracing.
"$MK" "$WORK/ref.exr" 8 8 1
cp "$WORK/ref.exr" "$WORK/ref_orig.exr"
bad 2 "ref.exr.*is the input" "render convergence -o naming its --ref-image" -- \
    "$BIN/render" convergence "$WORK/scene.toml" -o "$WORK/ref.exr" --spp 4 --ref-image "$WORK/ref.exr"
same_file "$WORK/ref.exr" "$WORK/ref_orig.exr" "the reference image is untouched"
"$MK" "$WORK/ref_small.exr" 4 4 1
bad 1 "ref_small.exr: reference is 4x4" "render convergence --ref-image of another size" -- \
    "$BIN/render" convergence "$WORK/scene.toml" -o "$OUT/r.exr" --spp 4 --ref-image "$WORK/ref_small.exr"
expect_true "refused before the render stage" -- bash -c "! grep -q 'render done' '$WORK/stderr'"

# Two outputs of one run on one path.
bad 2 "stderr-output" "render --stderr-output equal to -o" -- \
    "$BIN/render" trace "$WORK/scene.toml" -o "$OUT/x.exr" --stderr-output "$OUT/x.exr" --spp 1
mkdir -p "$WORK/d1" "$WORK/d2"
"$MK" "$WORK/d1/sky.exr" 32 16 1
"$MK" "$WORK/d2/sky.exr" 32 16 2
bad 2 "sky" "two inputs of one stem into one output folder" -- "$EP" "$WORK/d1/sky.exr" "$WORK/d2/sky.exr" -o "$OUT"

# --report on an output of the run: the report was written there after the usage error (a
# failed run's report under the output's name; make would take the step as done).
bad 2 "report.*also an output of the run: report not written" "--report equal to -o" -- \
    "$EP" "$WORK/d1/sky.exr" -o "$OUT/sky.json" --report "$OUT/sky.json"
bad 2 "report.*also an output of the run: report not written" "--report equal to the .bin beside -o" -- \
    "$EP" "$WORK/d1/sky.exr" -o "$OUT/sky.json" --report "$OUT/sky.bin"
# A report that cannot be written (/proc takes no new files, not even from root) failed the run
# only after its outputs were in place.
bad 1 "report.*cannot be written" "--report where no file can be made" -- \
    "$EP" "$WORK/d1/sky.exr" -o "$OUT/sky.json" --report /proc/inlight_report.json
# brdf-sh-bake's -o is a stem: a folder wrote the hidden files OUT/.bin, OUT/.json, ...
bad 2 "\-o '.*out/': names a folder, not a file stem" "brdf-sh-bake -o naming a folder" -- \
    "$BIN/brdf-sh-bake" --material "$SRC/configs/materials/satin-ggx.toml" -o "$OUT/" --grid report5x5 --samples 64
# render's -o without an image extension failed only after path tracing.
bad 2 "\-o: .*unsupported extension" "render -o without an image extension" -- \
    "$BIN/render" trace "$WORK/scene.toml" -o "$OUT/picture" --spp 1
expect_true "refused before the render stage" -- bash -c "! grep -q 'render done' '$WORK/stderr'"

# Pipelines: an id that is not a bundle id (from a folder named "My Fabric") failed at `bundle
# pack`, after every step had run and written its work folder; now before any step, OUT untouched.
mkdir -p "$WORK/My Fabric"
bad 2 "id 'My Fabric': expected 1-64 characters" "bake-fabric of a folder whose name is no bundle id" -- \
    env INLIGHT_BIN="$BIN" "$SRC/pipelines/bake-fabric.sh" "$WORK/My Fabric" "$OUT/bake"
bad 2 "id 'a/../b': expected" "bake-device with an id holding a path" -- \
    env INLIGHT_BIN="$BIN" "$SRC/pipelines/bake-device.sh" "$WORK/d1" "$OUT/bake" "a/../b"

# Partial results: the second input is bad; the first one's results must not stay.
"$MK" "$WORK/good.exr" 32 16 1
"$MK" "$WORK/wrong_aspect.exr" 32 15 1
bad 1 "wrong_aspect.exr" "second of two envmap-project inputs bad" -- "$EP" "$WORK/good.exr" "$WORK/wrong_aspect.exr" -o "$OUT"
# brdf-sh-bake: OUT.json cannot be placed (a folder holds its name): found before any work now,
# so OUT.bin is never written.
mkdir -p "$OUT/satin.json"
bad 2 "satin.json.*existing folder" "brdf-sh-bake whose .json cannot be placed" -- \
    "$BIN/brdf-sh-bake" --material "$SRC/configs/materials/satin-ggx.toml" -o "$OUT/satin" --grid report5x5 --samples 64
rmdir "$OUT/satin.json"

# bundle: the catalogue's -o naming a file of a bundle it indexes (it was overwritten with the
# SQLite file, exit 0), and pack taking a --file from inside the bundle folder it replaces.
"$MK" "$WORK/alb.png" 16 16 0.5
"$MK" "$WORK/thumb.png" 4 4 0.5
printf 'specular = "lambert"\n' > "$WORK/m.toml"
"$BIN/bundle" pack --kind fabric --id f --file albedo="$WORK/alb.png" --file thumbnail="$WORK/thumb.png" \
    --file material="$WORK/m.toml" -o "$WORK/bundles" >/dev/null 2>&1 || fail "bundle pack (set-up)"
cp "$WORK/bundles/fabrics/f/alb.png" "$WORK/alb_packed.png"
# bundle pack --id that is no bundle id: found after the bundle root's folders were made (exit 1,
# $OUT/b/fabrics left behind); bundle fabric-maps -o naming a file: found when writing.
bad 2 "id: '../x': expected 1-64 characters" "bundle pack --id ../x" -- \
    "$BIN/bundle" pack --kind fabric --id ../x --file albedo="$WORK/alb.png" --file thumbnail="$WORK/thumb.png" \
    --file material="$WORK/m.toml" -o "$OUT/b"
bad 2 "needs the folder .*alb.png', which is an existing file" "bundle fabric-maps -o naming a file" -- \
    "$BIN/bundle" fabric-maps --albedo-texture "$WORK/alb.png" -o "$WORK/alb.png"

bad 2 "alb.png" "bundle index -o naming a bundle's file" -- "$BIN/bundle" index "$WORK/bundles" -o "$WORK/bundles/fabrics/f/alb.png"
same_file "$WORK/bundles/fabrics/f/alb.png" "$WORK/alb_packed.png" "the bundle's file is untouched"
bad 2 "lies inside the bundle folder" "bundle pack of a file inside the bundle it replaces" -- \
    "$BIN/bundle" pack --kind fabric --id f --file albedo="$WORK/bundles/fabrics/f/alb.png" \
    --file thumbnail="$WORK/thumb.png" --file material="$WORK/m.toml" -o "$WORK/bundles"
same_file "$WORK/bundles/fabrics/f/alb.png" "$WORK/alb_packed.png" "the packed file is untouched"
finish
