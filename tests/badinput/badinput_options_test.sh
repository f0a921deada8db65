#!/usr/bin/env bash
# Bad option values, one case per class of the hostile sweep (docs/fuzzing.md): NaN and Inf are usage errors
# everywhere (CLI11's Range lets NaN through; app::parse adds finite() to every float option), a
# rotation holding NaN is a usage error and not a CHECK abort, quality gates and stop rules
# reject NaN and negatives, sizes that cannot be allocated and empty sizes are named, and a run
# rejected by the parser still writes the report it asked for. Exit 2, option named, $OUT as it was.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
# shellcheck source=tests/badinput/lib.sh
source "$(dirname "$0")/lib.sh"
SRC=${INLIGHT_SOURCE_DIR:?}
EP="$BIN/envmap-project"
BAKE="$BIN/brdf-sh-bake"
R="$BIN/render"
CAL="$BIN/calibrate"
MAT="$SRC/configs/materials/satin-ggx.toml"
FURNACE="$SRC/configs/scenes/sphere_furnace.toml"
"$TBIN/inlight_make_test_image" "$WORK/env.exr" 32 16 0.5
ENV=("$WORK/env.exr" -o "$OUT/env_sh.json")

# Aborts: a rotation with NaN or Inf was a CHECK failure (SIGABRT, no message, no report).
bad 2 "rotate.*nan" "--rotate z=nan" -- "$EP" "${ENV[@]}" --rotate z=nan
bad 2 "rotate.*inf" "--rotate x=inf" -- "$EP" "${ENV[@]}" --rotate x=inf

# NaN accepted: every float option of every tool.
bad 2 "intensity.*nan" "--intensity nan" -- "$EP" "${ENV[@]}" --intensity nan
bad 2 "fit-lambda.*nan" "--fit-lambda nan" -- "$EP" "${ENV[@]}" --fit-lambda nan
bad 2 "max-error.*nan" "envmap-project --max-error nan" -- "$EP" "${ENV[@]}" --max-error nan
bad 2 "max-mean-rel-error.*nan" "gate --max-mean-rel-error nan" -- "$EP" "${ENV[@]}" --max-mean-rel-error nan
bad 2 "max-mean-rel-error" "negative gate --max-mean-rel-error -1" -- "$EP" "${ENV[@]}" --max-mean-rel-error -1
bad 2 "view-deg.*nan" "brdf-sh-bake --view-deg nan" -- "$BAKE" --material "$MAT" -o "$OUT/b" --view-deg nan
bad 2 "max-error.*nan" "brdf-sh-bake --max-error nan" -- "$BAKE" --material "$MAT" -o "$OUT/b" --max-error nan
bad 2 "view" "view behind the screen (--view 0,0,-1)" -- "$BAKE" --material "$MAT" -o "$OUT/b" --view 0,0,-1
bad 2 "view-deg" "view behind the screen (--view-deg 120)" -- "$BAKE" --material "$MAT" -o "$OUT/b" --view-deg 120
bad 2 "time-budget-s.*nan" "stop rule --time-budget-s nan" -- "$R" trace "$FURNACE" -o "$OUT/f.exr" --time-budget-s nan
bad 2 "target-rel-error.*nan" "stop rule --target-rel-error nan" -- "$R" trace "$FURNACE" -o "$OUT/f.exr" --target-rel-error nan
bad 2 "max-rel-error.*nan" "gate --max-rel-error nan" -- "$R" trace "$FURNACE" -o "$OUT/f.exr" --max-rel-error nan
bad 2 "max-rel-error" "negative gate --max-rel-error -0.5" -- "$R" trace "$FURNACE" -o "$OUT/f.exr" --max-rel-error -0.5
bad 2 "fov-deg.*nan" "calibrate --fov-deg nan" -- "$CAL" geometry "$WORK" --board 9x6 -o "$OUT/cal" --fov-deg nan
bad 2 "outlier-factor.*nan" "calibrate --outlier-factor nan" -- "$CAL" geometry "$WORK" --board 9x6 -o "$OUT/cal" --outlier-factor nan
bad 2 "device-from-camera" "calibrate --device-from-camera z=nan" -- "$CAL" geometry "$WORK" --board 9x6 -o "$OUT/cal" --device-from-camera z=nan
bad 2 "exposure-s.*inf" "calibrate response --exposure-s inf" -- "$CAL" response --images "$WORK/env.exr" "$WORK/env.exr" --exposure-s 0.01 inf -o "$OUT/resp.json"

# Finite but overflowing: --intensity 1e308 wrote coefficients of null (NaN as JSON), exit 0.
bad 1 "env.exr: --intensity 1e+308 takes its largest value .* past the float range" "--intensity 1e308 (overflow)" -- \
    "$EP" "${ENV[@]}" --intensity 1e308

# bundle pack --property: a number JSON cannot hold was stored as the string "nan" (exit 0).
"$TBIN/inlight_make_test_image" "$WORK/alb.png" 16 16 0.5
PACK=("$BIN/bundle" pack --kind fabric --id f --file albedo="$WORK/alb.png" --file thumbnail="$WORK/alb.png" --file material="$MAT" -o "$OUT")
bad 2 "property.*nan.*not a finite number" "bundle pack --property tile_size_m=nan" -- "${PACK[@]}" --property tile_size_m=nan
bad 2 "property.*1e999.*not a finite number" "bundle pack --property tile_size_m=1e999" -- "${PACK[@]}" --property tile_size_m=1e999

# NaN in a --config file: the same check as on the command line, naming the option.
printf 'intensity = nan\n' > "$WORK/nan.toml"
bad 2 "intensity.*nan" "intensity = nan in --config" -- "$EP" "${ENV[@]}" --config "$WORK/nan.toml"
printf 'max-rel-error = -inf\n' > "$WORK/inf.toml"
bad 2 "max-rel-error" "max-rel-error = -inf in --config" -- "$R" trace "$FURNACE" -o "$OUT/f.exr" --config "$WORK/inf.toml"

# Unclear messages: sizes that cannot be allocated or are empty, and a negative seed.
bad 2 "board.*100000x100000" "--board 100000x100000" -- "$CAL" geometry "$WORK" --board 100000x100000 -o "$OUT/cal"
# A 3x2 board suits corner files, but OpenCV's detectors assert on it ("Both width and height of
# the pattern should have bigger than 2", a raw OpenCV error).
bad 2 "board 3x2: finding a chessboard in images needs at least 3x3" "--board 3x2 with images" -- \
    "$CAL" geometry "$WORK/env.exr" --board 3x2 -o "$OUT/cal"
bad 2 "downscale.*0x0" "--downscale 0x0" -- "$CAL" geometry "$WORK" --board 9x6 -o "$OUT/cal" --downscale 0x0
bad 2 "seed" "--seed -1" -- "$EP" "${ENV[@]}" --seed -1
# A parser's message is not prefixed twice with the option ("--seed: --seed: ...").
bad 2 "^--seed: -1 is outside" "--seed -1 named once" -- "$EP" "${ENV[@]}" --seed -1
bad 2 "^--board: 'nan': expected COLSxROWS" "--board nan named once" -- "$CAL" geometry "$WORK" --board nan -o "$OUT/cal"
# A render size this machine cannot hold (16384 x 16384: ~57 GiB of per-pixel sums) is refused
# before anything is allocated; it was zeroed page by page until the kernel killed the process.
if [ "$(awk '/MemTotal/ {print int($2 / 1048576)}' /proc/meminfo)" -lt 50 ]; then
    bad 1 "16384x16384 image needs about .* GiB .* more than this machine's" "render 16384x16384 (memory)" -- \
        "$R" trace "$FURNACE" -o "$OUT/f.exr" --width-px 16384 --height-px 16384 --spp 1
else
    echo "note: render 16384x16384 not tried: this machine has 50 GiB or more, the size fits"
fi
bad 2 "rt-grid" "render --rt-grid hex:4 (rejected before any path tracing)" -- "$R" compare "$FURNACE" -o "$OUT/f.exr" --rt-grid hex:4

# Reports: a run the parser rejects still writes its report, status failed, the error in it.
bad 2 "intensity" "report of a parse failure" -- "$EP" "${ENV[@]}" --intensity nan --report "$WORK/r.json"
expect_true "report written: failed, exit 2, error names the option" -- \
    jq -e '.status == "failed" and .exit_code == 2 and (.error | test("intensity"))' "$WORK/r.json"
# ... also when --report comes from the --config file that holds the bad value.
printf 'report = "%s"\nintensity = nan\n' "$WORK/cr.json" > "$WORK/report_nan.toml"
bad 2 "intensity" "report of a parse failure, --report in --config" -- "$EP" "${ENV[@]}" --config "$WORK/report_nan.toml"
expect_true "report from --config written: failed, exit 2" -- \
    jq -e '.status == "failed" and .exit_code == 2 and (.error | test("intensity"))' "$WORK/cr.json"
# Empty paths: -o '' wrote ".bin", ".json" into the working folder (brdf-sh-bake).
bad 2 "output.*an empty path" "brdf-sh-bake -o ''" -- "$BAKE" --material "$MAT" -o ""
bad 2 "output.*an empty path" "render -o ''" -- "$R" trace "$FURNACE" -o ""
finish
