#!/usr/bin/env bash
# validate-report: the validation pairs of a run (VALIDATE_DIR/pairs/<fabric>/<environment>/
# summary.json, from validate-pair.sh) -> VALIDATE_DIR/index.html, summary.md, summary.json and
# gnuplot plots of error against cost.
#   pipelines/validate-report.sh VALIDATE_DIR
# Verdict per pair: the app's shading (consistent mode, the bundle's SH bands) against the
# truth in mean CIEDE2000 after exposure: good <= MAX_DE2000 (default 2: a difference an
# observer notices only side by side), marginal <= 2 x that, else poor. The truth's own noise
# is a floor under every figure: a pair whose truth noise exceeds half the model's relative
# error is marked noise-limited. Where the pair has them: the GLES column (the exported shader
# the bundle ships, consistent mode, highp, drawn through EGL), the band budget (what
# envmap-project --max-error chooses for this environment and table) and the error decomposition
# at the shipped band count (render compare --decompose).
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 1 1 "VALIDATE_DIR"
V=$(abs_dir "$1")
MAX_DE2000=${MAX_DE2000:-2.0}
JND_DE2000=${JND_DE2000:-1.0}
P="$V/plots"
mkdir -p "$P"
mapfile -t summaries < <(find "$V/pairs" -name summary.json | sort)
if [ "${#summaries[@]}" -eq 0 ]; then
    echo "validate-report: no pairs in $V/pairs" >&2
    exit 1
fi

# 1. One table of every pair with its verdict and what would make it better.
jq -s --argjson t "$MAX_DE2000" --argjson jnd "$JND_DE2000" '
  map(. as $p
    | ($p.by_sh_bands | map(select(.sh_bands == $p.sh_bands_shipped))[0]) as $ship
    | ($p.by_sh_bands | map(select(.mean_de2000 <= $t)) | min_by(.sh_bands)) as $enough
    | ($p.by_sh_bands | min_by(.mean_de2000)) as $best
    | (($p.truth.rel_noise // 0) > 0.5 * $ship.mean_rel) as $noisy
    | ($p.gles.variants // [] | map(select(.mode == "consistent" and .sh_bands == $p.sh_bands_shipped
                                             and (.variant | test("highp")))) | sort_by(.glsl_version) | last) as $gl
    | ($p.decomposition.by_sh_bands // [] | map(select(.sh_bands == $p.sh_bands_shipped))[0]) as $dec
    | (if $dec then {grid: $dec.grid_interpolation, sh_diffuse: $dec.sh_truncation_diffuse,
                     sh_specular: $dec.sh_truncation_specular, fixed_view: $p.decomposition.fixed_view,
                     visibility: $p.decomposition.visibility, truth_noise: $p.decomposition.truth_noise}
       else null end) as $parts
    | ($p.btf.views // [] | (map(select(.view_deg == [0, 0]))[0] // .[0])) as $bv
    | $p + {shipped: $ship, gles_shipped: $gl, error_parts: $parts,
            btf_view: $bv,
            btf_enough: (if $bv then $bv.stream | map(select(.mean_de2000 <= $bv.shipped.mean_de2000 + $jnd))
                                                 | min_by(.components_sent) else null end),
            largest_part: (if $parts then ($parts | del(.truth_noise) | to_entries | max_by(.value) | .key) else null end),
            budget_text: (if $p.budget == null then null
                          else "\($p.budget.sh_bands) bands + \($p.budget.lights) light\(if $p.budget.lights == 1 then "" else "s" end): \($p.budget.error * 1000 | round / 10)% \(if $p.budget.met then "(meets \($p.budget.max_error * 100)%)" else "(best; misses \($p.budget.max_error * 100)%)" end)" end),
            verdict: (if $ship.mean_de2000 <= $t then "good"
                      elif $ship.mean_de2000 <= 2 * $t then "marginal" else "poor" end),
            noise_limited: $noisy,
            bands_needed: ($enough.sh_bands // null),
            best_sh_bands: $best.sh_bands, best_de2000: $best.mean_de2000,
            advice: (if $noisy then "truth too noisy to judge: render it with more samples (validate.toml spp / target-rel-error)"
                     elif $ship.mean_de2000 <= $t then "ships as is at \($p.sh_bands_shipped) SH bands"
                     elif $enough != null then "use \($enough.sh_bands) SH bands: dE2000 \($enough.mean_de2000 * 100 | round / 100) at \($enough.frame_time_ms * 100 | round / 100) ms per frame (CPU model)"
                     else "more SH bands do not get there (best \($best.sh_bands) bands, dE2000 \($best.mean_de2000 * 100 | round / 100)): the rest is the BRDF grid, the fixed view or missing shadowing; next lever: dominant lights (envmap-project --max-error, docs/budget.md)" end)})
  | sort_by(.fabric, .environment)' "${summaries[@]}" > "$V/summary.json"

# 2. Plot data: per fabric and environment, error against SH bands; per fabric, the median
#    over environments of error and of frame time per band count (single timings on a shared
#    machine are noisy; the median is not).
mapfile -t FABRICS < <(jq -r '[.[].fabric] | unique[]' "$V/summary.json")
mapfile -t ENVS < <(jq -r '[.[].environment] | unique[]' "$V/summary.json")
: > "$P/bands.dat"
: > "$P/cost.dat"
: > "$P/gles_cost.dat"
for fabric in "${FABRICS[@]}"; do
    for env in "${ENVS[@]}"; do
        {
            echo "# $fabric $env"
            jq -r --arg f "$fabric" --arg e "$env" '.[] | select(.fabric == $f and .environment == $e)
                | .by_sh_bands[] | [.sh_bands, .mean_de2000, .frame_time_ms, .mean_rel] | @tsv' "$V/summary.json"
            printf '\n\n'
        } >> "$P/bands.dat"
    done
    {
        echo "# $fabric: sh_bands, median frame_time_ms, median mean_de2000 over environments"
        jq -r --arg f "$fabric" 'def median: sort | if length % 2 == 1 then .[length / 2 | floor]
                                                   else (.[length / 2 - 1] + .[length / 2]) / 2 end;
            [.[] | select(.fabric == $f) | .by_sh_bands[]] | group_by(.sh_bands)[]
            | [.[0].sh_bands, (map(.frame_time_ms) | median), (map(.mean_de2000) | median)] | @tsv' "$V/summary.json"
        printf '\n\n'
    } >> "$P/cost.dat"
    {
        echo "# $fabric: GLES (consistent, highp, the newest GLSL ES): sh_bands, median frame_time_ms, median mean_de2000"
        jq -r --arg f "$fabric" 'def median: sort | if length % 2 == 1 then .[length / 2 | floor]
                                                   else (.[length / 2 - 1] + .[length / 2]) / 2 end;
            [.[] | select(.fabric == $f) | .gles.variants // [] | map(select(.mode == "consistent" and (.variant | test("highp"))))
             | (map(.glsl_version) | max) as $v | .[] | select(.glsl_version == $v)]
            | group_by(.sh_bands)[] | [.[0].sh_bands, (map(.frame_time_ms) | median), (map(.mean_de2000) | median)] | @tsv' "$V/summary.json"
        printf '\n\n'
    } >> "$P/gles_cost.dat"
done
jq -r '.[] | [.fabric, .environment, .bundle_bytes, .shipped.mean_de2000, .truth.rel_noise, .shipped.mean_rel, .seed.mean_de2000] | @tsv' \
    "$V/summary.json" > "$P/pairs.dat"
nf=${#FABRICS[@]}
ne=${#ENVS[@]}
cols=$((nf < 3 ? nf : 3))
rows=$(((nf + cols - 1) / cols))

gnuplot <<GNUPLOT
set terminal pngcairo size $((cols * 420 + 160)),$((rows * 360 + 40)) font "sans,9"
set output "$P/error_vs_sh_bands.png"
set multiplot layout $rows,$cols title "Real-time model vs path-traced truth: mean CIEDE2000 against SH bands (consistent mode; dashed: good)"
fabrics = "${FABRICS[*]}"
envs = "${ENVS[*]}"
set grid
set logscale y
set xtics 1
set xlabel "SH bands (lighting and BRDF table)"
set ylabel "mean CIEDE2000"
set key top right font "sans,7"
do for [f=0:$nf-1] {
    set title word(fabrics, f+1)
    plot for [e=0:$ne-1] "$P/bands.dat" index f*$ne+e using 1:2 with linespoints title word(envs, e+1), \
         $MAX_DE2000 with lines dashtype 2 lw 2 lc rgb "black" notitle
}
unset multiplot
set terminal pngcairo size 900,560 font "sans,10"
set key outside right top font "sans,8"
set output "$P/error_vs_frame_time.png"
set title "Error against cost: median over environments, per band count (labels: SH bands)"
set xlabel "frame time, ms (solid: CPU real-time model; dashed: GLES shader on $(jq -r '[.[].gles.driver // empty][0] // "no GL" | sub(".*[|] "; "") | sub(" [(].*"; "")' "$V/summary.json"))"
set ylabel "median mean CIEDE2000"
unset logscale x
set logscale y
plot for [f=0:$nf-1] "$P/cost.dat" index f using 2:3 with linespoints title word(fabrics, f+1), \
     for [f=0:$nf-1] "$P/cost.dat" index f using 2:3:1 with labels offset 0.8,0.6 notitle, \
     for [f=0:$nf-1] "$P/gles_cost.dat" index f using 2:3 with linespoints dashtype 2 lc f+1 title word(fabrics, f+1)." GLES", \
     $MAX_DE2000 with lines dashtype 2 lw 2 lc rgb "black" title "good"
set output "$P/truth_noise.png"
set title "Is the truth good enough? Its noise against the model error it judges"
set xlabel "truth: relative noise (standard error / mean)"
set ylabel "model: mean relative error"
set key inside left top
set logscale xy
set xrange [0.003:0.5]
set yrange [0.003:1]
plot "$P/pairs.dat" using 5:6 with points pt 7 title "pairs", x with lines lc rgb "red" title "noise = error", \
     2*x with lines dashtype 2 lc rgb "red" title "noise = error / 2 (above: judged by the model, not the noise)"
GNUPLOT

# The path tracer against spp, beside the model errors it must resolve (first pair with a study).
conv=$(find "$V/pairs" -name convergence.json | sort | sed -n 1p)
if [ -n "$conv" ]; then
    pair_dir=$(dirname "$conv")
    jq -r '.points[] | [.spp, .rel_rmse, .time_s] | @tsv' "$conv" > "$P/convergence.dat"
    cf=$(basename "$(dirname "$pair_dir")")
    ce=$(basename "$pair_dir")
    pick() { jq --arg f "$cf" --arg e "$ce" ".[] | select(.fabric == \$f and .environment == \$e) | $1" "$V/summary.json"; }
    model=$(pick .shipped.mean_rel)
    seed=$(pick .seed.mean_rel)
    gnuplot <<GNUPLOT2
set terminal pngcairo size 900,560 font "sans,10"
set output "$P/error_vs_spp.png"
set grid
set logscale xy
set title "The truth's own error against samples per pixel ($cf / $ce, slope $(jq '.slope * 1000 | round / 1000' "$conv"))"
set xlabel "samples per pixel (path tracer)"
set ylabel "relative RMSE against a $(jq .reference_spp "$conv") spp reference"
set key top right
plot "$P/convergence.dat" using 1:2 with linespoints pt 7 title "path tracer", \
     $model with lines lw 2 lc rgb "dark-green" title "real-time model, mean relative error", \
     $seed with lines dashtype 2 lc rgb "red" title "the report's seed shader"
GNUPLOT2
fi

gnuplot <<GNUPLOT
set terminal pngcairo size 900,560 font "sans,10"
set grid
set key outside right top font "sans,8"
set output "$P/error_vs_bytes.png"
set title "Error against bytes downloaded (whole bundle; the BTF stream: btf_error_vs_bytes.png)"
set xlabel "bundle bytes"
set ylabel "mean CIEDE2000 (shipped SH bands)"
unset logscale y
set autoscale xy
plot "$P/pairs.dat" using 3:4 with points pt 7 title "consistent model", \
     "$P/pairs.dat" using 3:7 with points pt 6 title "the report's seed shader"
GNUPLOT

# Where the error comes from, per decomposed pair (render compare --decompose at the shipped bands):
# the parts of the model's error, stacked (their sum bounds the total), and the truth's noise.
jq -r '.[] | select(.error_parts) | [.fabric + "/" + .environment, .error_parts.grid, .error_parts.sh_diffuse,
       .error_parts.sh_specular, .error_parts.fixed_view, .error_parts.visibility, .error_parts.truth_noise,
       .shipped.mean_rel] | @tsv' "$V/summary.json" > "$P/parts.dat"
if [ -s "$P/parts.dat" ]; then
    gnuplot <<GNUPLOT3
set terminal pngcairo size 900,560 font "sans,10"
set output "$P/error_parts.png"
set title "Where the model's error comes from (shipped SH bands; render compare --decompose)"
set ylabel "relative RMS of luminance"
set style data histograms
set style histogram rowstacked
set style fill solid 0.8 border -1
set boxwidth 0.6
set grid y
set key outside right top font "sans,8"
set xtics rotate by -30 font "sans,8"
plot "$P/parts.dat" using 2:xtic(1) title "BRDF grid", "" using 3 title "SH truncation, diffuse", \
     "" using 4 title "SH truncation, specular", "" using 5 title "fixed view", "" using 6 title "visibility", \
     "" using 0:7 with points pt 7 lc rgb "black" title "truth noise"
GNUPLOT3
fi

# The BTF fabrics shaded as BTFs: error against PCA components and bytes streamed, one line per
# environment; against the truth (dE2000; dashed: the raw BTF, all 81 x 81 images, the best the
# stream can reach against this truth) and against the raw BTF's shading (relative RMSE: the
# PCA loss alone, without the truth's noise or the BTF's own sampling error).
jq -r '[.[] | select(.btf_view)] | group_by(.fabric)[] | .[0].fabric as $f | .[]
       | "# \($f) \(.environment) raw_de2000 \(.btf_view.raw.mean_de2000)",
         (.btf_view.stream[] | [.components_sent, .bytes_sent / 1000, .mean_de2000, .vs_raw_rel_rmse, .mean_rel] | @tsv),
         "", ""' "$V/summary.json" > "$P/btf.dat"
mapfile -t BTF_KEYS < <(jq -r '.[] | select(.btf_view) | "\(.fabric)/\(.environment)"' "$V/summary.json")
mapfile -t BTF_FABRICS < <(jq -r '[.[] | select(.btf_view) | .fabric] | unique[]' "$V/summary.json")
if [ "${#BTF_KEYS[@]}" -gt 0 ]; then
    # Per fabric: its first block and block count in btf.dat, and the median raw-BTF dE2000.
    starts="" counts="" raws=""
    for f in "${BTF_FABRICS[@]}"; do
        starts="$starts $(jq --arg f "$f" '[.[] | select(.btf_view)] | map(.fabric) | index($f)' "$V/summary.json")"
        counts="$counts $(jq --arg f "$f" '[.[] | select(.btf_view and .fabric == $f)] | length' "$V/summary.json")"
        raws="$raws $(jq --arg f "$f" '[.[] | select(.btf_view and .fabric == $f) | .btf_view.raw.mean_de2000] | sort | .[length / 2 | floor]' "$V/summary.json")"
    done
    nb=${#BTF_FABRICS[@]}
    envs_of() { jq -r --arg f "$1" '[.[] | select(.btf_view and .fabric == $f) | .environment] | join(" ")' "$V/summary.json"; }
    for axis in components bytes; do
        if [ "$axis" = components ]; then col=1; xl="PCA components streamed (all groups)"; else col=2; xl="BTF bytes streamed, kB (bundle manifest: manifest, V and means first)"; fi
        {
            echo "set terminal pngcairo size 1000,$((nb * 380 + 40)) font 'sans,9'"
            echo "set output '$P/btf_error_vs_$axis.png'"
            echo "set multiplot layout $nb,2 title 'BTF fabrics: the shipped BTF stream shaded under each environment, view along the normal (render shade-btf --shade-stream)'"
            echo "set grid; set key top right font 'sans,7'; set xlabel '$xl'"
            i=0
            for f in "${BTF_FABRICS[@]}"; do
                i=$((i + 1))
                start=$(echo "$starts" | awk -v i="$i" '{print $i}')
                count=$(echo "$counts" | awk -v i="$i" '{print $i}')
                raw=$(echo "$raws" | awk -v i="$i" '{print $i}')
                echo "envs = '$(envs_of "$f")'"
                echo "set title '$f: against the path-traced weave'; set ylabel 'mean CIEDE2000'; unset logscale y"
                echo "plot for [e=0:$count-1] '$P/btf.dat' index $start+e using $col:3 with linespoints title word(envs, e+1), $raw with lines dashtype 2 lw 2 lc rgb 'black' title 'raw BTF (median)'"
                echo "set title '$f: against the raw BTF shading (PCA loss)'; set ylabel 'relative RMSE'; set logscale y"
                echo "plot for [e=0:$count-1] '$P/btf.dat' index $start+e using $col:4 with linespoints title word(envs, e+1)"
            done
            echo "unset multiplot"
        } | gnuplot
    done
fi

# jq definitions the BTF tables share.
JQ_DEFS='def r(n): . * n | round / n;
    def median: sort | if length % 2 == 1 then .[length / 2 | floor] else (.[length / 2 - 1] + .[length / 2]) / 2 end;
    def view_text: "theta \(.[0]), phi \(.[1]) deg";'
# The BTF views the pairs were shaded at, in one line.
BTF_VIEWS_TEXT=$(jq -r "$JQ_DEFS"' [.[] | .btf.views // [] | .[].view_deg] | unique | map(view_text) | join("; ")' "$V/summary.json")
# What each BTF comparison measures (the Markdown summary and the page say it once).
btf_measures_text() {
    echo "Each BTF fabric's BTF is shaded under the environment as the app would shade it (render"
    echo "shade-btf) at each of these views: $BTF_VIEWS_TEXT (theta from the normal). Theta 0 is the"
    echo "pair's own camera: the per-pair table, the stream table and the plots are at it; the view table"
    echo "sets the views side by side. Each is measured against a truth of its own: the woven"
    echo "geometry the BTF was captured from, path-traced under the same environment through the BTF's"
    echo "rectified camera at the BTF's size. **Raw BTF vs truth**: the BTF representation itself (81 light"
    echo "directions standing in for the environment, the capture's noise). **Shipped vs truth**: what"
    echo "the app shows from the bundle's whole stream. **Shipped (and each prefix) vs raw BTF**: the PCA"
    echo "loss alone, without the truth's noise; it falls with every component (a projection onto"
    echo "nested subspaces). The BRDF-table column is the pair's verdict model on another scene (the"
    echo "textured patch, its own truth), so the two dE2000s are not a like-for-like ranking."
}
# btf_stream_table md|html: per BTF fabric and stream prefix, the median and worst error over the
# environments against the truth and against the raw BTF shading, with the bytes sent.
btf_stream_table() {
    # shellcheck disable=SC2016  # jq program
    local prog="$JQ_DEFS"'
        [.[] | select(.btf_view)] | group_by(.fabric)[] | .[0].fabric as $f
        | [.[].btf_view.gles // [] | .[] | select(.variant == "btf-es300-highp")] as $gl
        | [.[].btf_view.stream[]] | group_by(.components_sent)[]
        | .[0].components_sent as $n | [$gl[] | select(.components_sent == $n) | .mean_de2000] as $gd
        | [$f, $n, (.[0].bytes_sent / 1000 | r(10)), (map(.mean_de2000) | median | r(100)),
           (map(.mean_de2000) | max | r(100)), (map(.vs_raw_rel_rmse) | median | r(10000)),
           (map(.vs_raw_rel_rmse) | max | r(10000)),
           (if ($gd | length) > 0 then "\($gd | median | r(100)) (\($gd | max | r(100)))" else "-" end)]'
    if [ "$1" = md ]; then
        echo "| fabric | components sent | kB sent | dE2000 vs truth, median (worst) | rel. RMSE vs raw BTF, median (worst) | GLES ES 3.00 dE2000 vs truth, median (worst) |"
        echo "| --- | --- | --- | --- | --- | --- |"
        jq -r "$prog"' | "| \(.[0]) | \(.[1]) | \(.[2]) | \(.[3]) (\(.[4])) | \(.[5]) (\(.[6])) | \(.[7]) |"' "$V/summary.json"
    else
        echo "<table><tr><th>fabric</th><th>components sent</th><th>kB sent</th><th>dE2000 vs truth, median (worst)</th><th>rel. RMSE vs raw BTF, median (worst)</th><th>GLES ES 3.00 dE2000 vs truth, median (worst)</th></tr>"
        jq -r "$prog"' | "<tr><td>\(.[0])</td><td>\(.[1])</td><td>\(.[2])</td><td>\(.[3]) (\(.[4]))</td><td>\(.[5]) (\(.[6]))</td><td>\(.[7])</td></tr>"' "$V/summary.json"
        echo "</table>"
    fi
}

# btf_view_table md|html: the BTF's view dependence: per BTF fabric and view, the median and worst
# error over the environments of the raw and the shipped BTF against the truth, and of the shipped
# against the raw BTF shading.
btf_view_table() {
    # shellcheck disable=SC2016  # jq program
    local prog="$JQ_DEFS"'
        [.[] | select(.btf_view) | .fabric as $f | .btf.views[] | . + {fabric: $f}]
        | group_by(.fabric)[] | group_by(.view_deg)[]
        | [.[0].fabric, (.[0].view_deg | view_text), length,
           (map(.raw.mean_de2000) | median | r(100)), (map(.raw.mean_de2000) | max | r(100)),
           (map(.shipped.mean_de2000) | median | r(100)), (map(.shipped.mean_de2000) | max | r(100)),
           (map(.shipped.vs_raw_rel_rmse) | median | r(10000)), (map(.shipped.vs_raw_rel_rmse) | max | r(10000))]'
    if [ "$1" = md ]; then
        echo "| fabric | view | environments | raw BTF vs truth: dE2000, median (worst) | shipped vs truth: dE2000, median (worst) | shipped vs raw BTF: rel. RMSE, median (worst) |"
        echo "| --- | --- | --- | --- | --- | --- |"
        jq -r "$prog"' | "| \(.[0]) | \(.[1]) | \(.[2]) | \(.[3]) (\(.[4])) | \(.[5]) (\(.[6])) | \(.[7]) (\(.[8])) |"' "$V/summary.json"
    else
        echo "<table><tr><th>fabric</th><th>view</th><th>environments</th><th>raw BTF vs truth: dE2000, median (worst)</th><th>shipped vs truth: dE2000, median (worst)</th><th>shipped vs raw BTF: rel. RMSE, median (worst)</th></tr>"
        jq -r "$prog"' | "<tr><td>\(.[0])</td><td>\(.[1])</td><td>\(.[2])</td><td>\(.[3]) (\(.[4]))</td><td>\(.[5]) (\(.[6]))</td><td>\(.[7]) (\(.[8]))</td></tr>"' "$V/summary.json"
        echo "</table>"
    fi
}

# btf_gles_table md|html: the BTF as the phone draws it: per BTF fabric, view and exported
# variant (its longest prefix: the whole stream), the median and worst error over the environments of its GLES picture against the
# truth, its mean-luminance bias, and its distance from the CPU shading of the same components
# (the SH lighting's truncation at the shipped bands: the CPU shading integrates the whole map).
btf_gles_table() {
    # shellcheck disable=SC2016  # jq program
    local prog="$JQ_DEFS"'
        [.[] | select(.btf_view) | .fabric as $f | .btf.gles_bands as $b | .btf.views[] | .view_deg as $v
         | (.gles // [] | group_by(.variant)[] | max_by(.components_sent)) | . + {fabric: $f, bands: $b, view_deg: $v}]
        | group_by(.fabric)[] | group_by(.view_deg)[] | group_by(.variant)[]
        | [.[0].fabric, (.[0].view_deg | view_text), .[0].variant, .[0].bands, length, .[0].components_sent,
           (map(.mean_de2000) | median | r(100)), (map(.mean_de2000) | max | r(100)),
           (map(.mean_rel) | median | r(1000)), (map(.mean_luminance_rel_diff * 100) | median | r(10)),
           (map(.mean_luminance_rel_diff * 100) | max_by(fabs) | r(10)), (map(.vs_cpu_rel_rmse) | median | r(1000))]'
    if [ "$1" = md ]; then
        echo "| fabric | view | variant | SH bands | environments | components sent | dE2000 vs truth, median (worst) | rel. error, median | luminance bias %, median (largest) | vs CPU shading: rel. RMSE, median |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
        jq -r "$prog"' | "| \(.[0]) | \(.[1]) | \(.[2]) | \(.[3]) | \(.[4]) | \(.[5]) | \(.[6]) (\(.[7])) | \(.[8]) | \(.[9]) (\(.[10])) | \(.[11]) |"' "$V/summary.json"
    else
        echo "<table><tr><th>fabric</th><th>view</th><th>variant</th><th>SH bands</th><th>environments</th><th>components sent</th><th>dE2000 vs truth, median (worst)</th><th>rel. error, median</th><th>luminance bias %, median (largest)</th><th>vs CPU shading: rel. RMSE, median</th></tr>"
        jq -r "$prog"' | "<tr><td>\(.[0])</td><td>\(.[1])</td><td>\(.[2])</td><td>\(.[3])</td><td>\(.[4])</td><td>\(.[5])</td><td>\(.[6]) (\(.[7]))</td><td>\(.[8])</td><td>\(.[9]) (\(.[10]))</td><td>\(.[11])</td></tr>"' "$V/summary.json"
        echo "</table>"
    fi
}
# Whether any pair drew the BTF's GLES shaders.
BTF_GLES=$(jq '[.[] | .btf_view.gles // [] | length] | add // 0' "$V/summary.json")

# 3. Markdown summary.
{
    echo "# Validation: real-time model against path-traced truth"
    echo
    echo "Verdict: mean CIEDE2000 of the app's shading (consistent mode, the bundle's SH bands) against"
    echo "the truth; good <= $MAX_DE2000, marginal <= $(jq -n "2 * $MAX_DE2000"), else poor. GLES: the exported shader (same"
    echo "exporter, grid and bands as the bundle's; consistent, highp) through EGL against the truth, and the share of its pixels within 1e-3"
    echo "of the CPU model. The GLES column draws one fragment per pixel, the CPU column the config's"
    echo "rt-supersample: where GLES agrees with the model but its dE2000 is higher, the gap is the pixel"
    echo "footprint (the weave texture aliasing), which MSAA or mipmaps on the phone would remove."
    echo "Budget: envmap-project --max-error's choice for this environment and table."
    echo "Largest part: of the model's error at the shipped bands (render compare --decompose), where run."
    echo
    echo "| fabric | environment | verdict | dE2000 CPU model | GLES dE2000 (agrees) | rel. error | seed shader dE2000 | truth noise | budget | largest part | advice |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    jq -r 'def r(n): . * n | round / n; .[] | "| \(.fabric) | \(.environment) | \(.verdict)\(if .noise_limited then " (noise-limited)" else "" end)\(if .gate then "; gate \(.gate.verdict)" else "" end) | \(.shipped.mean_de2000 | r(100)) | \(if .gles_shipped then "\(.gles_shipped.mean_de2000 | r(100)) (\(.gles_shipped.cpu_model_fraction_within_1e_3 * 100 | round)%)" else "-" end) | \(.shipped.mean_rel | r(1000)) | \(.seed.mean_de2000 | r(100)) | \(.truth.rel_noise | r(1000)) | \(.budget_text // "-") | \(if .largest_part then "\(.largest_part) \(.error_parts[.largest_part] | r(1000))" else "-" end) | \(.advice) |"' "$V/summary.json"
    if [ "${#BTF_KEYS[@]}" -gt 0 ]; then
        echo
        echo "## BTF fabrics: the BTF shaded as a BTF"
        echo
        btf_measures_text
        echo
        echo "| fabric | environment | truth noise | raw BTF vs truth: dE2000 (rel.) | shipped BTF: components, kB | shipped vs truth: dE2000 (rel.) | shipped vs raw BTF: rel. RMSE | enough: within $JND_DE2000 dE2000 of the whole stream | BRDF-table model dE2000 (textured patch) |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
        jq -r 'def r(n): . * n | round / n; .[] | select(.btf_view) | .btf_view as $b | "| \(.fabric) | \(.environment) | \($b.truth_noise | r(1000)) | \($b.raw.mean_de2000 | r(100)) (\($b.raw.mean_rel | r(1000))) | \($b.shipped.components_sent), \($b.shipped.bytes / 1000 | r(10)) | \($b.shipped.mean_de2000 | r(100)) (\($b.shipped.mean_rel | r(1000))) | \($b.shipped.vs_raw_rel_rmse | r(1000)) | \(.btf_enough.components_sent) components, \(.btf_enough.bytes_sent / 1000 | r(10)) kB (dE2000 \(.btf_enough.mean_de2000 | r(100))) | \(.shipped.mean_de2000 | r(100)) |"' "$V/summary.json"
        echo
        echo "Error against the stream, median (and worst) over the environments:"
        echo
        btf_stream_table md
        echo
        echo "The BTF's view dependence, median (and worst) over the environments:"
        echo
        btf_view_table md
        if [ "$BTF_GLES" -gt 0 ]; then
            echo
            echo "The BTF as the phone draws it: the bundle's BTF GLES shaders through EGL, one fragment per texel, lit by"
            echo "the environment's SH at the shipped bands (docs/btf-gles.md), median (and worst) over the environments:"
            echo
            btf_gles_table md
        fi
    fi
    jq -r '.[] | select(.has_btf and .btf_view == null) | "\nBTF of \(.fabric) under \(.environment) not shaded: no raw capture was given (a BTF without woven geometry has no truth to path-trace)."' "$V/summary.json"
    echo
    echo "Plots: plots/error_vs_sh_bands.png, plots/error_vs_frame_time.png, plots/error_vs_spp.png (with a convergence study), plots/truth_noise.png, plots/error_vs_bytes.png, plots/error_parts.png (with a decomposition), plots/btf_error_vs_components.png and plots/btf_error_vs_bytes.png (with BTF fabrics)."
    echo "Page: index.html."
} > "$V/summary.md"

# 4. The HTML page: verdicts first, then each pair side by side (truth | model | heat map).
{
    cat <<'HTML'
<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>inlight validation</title>
<style>
body{font-family:sans-serif;margin:1.5em;max-width:1200px}
table{border-collapse:collapse;font-size:90%}td,th{border:1px solid #ccc;padding:3px 6px}
.good{background:#c8f0c8}.marginal{background:#f8e8a0}.poor{background:#f4b8b8}
img.pair{max-width:900px;height:auto}
</style></head><body>
<h1>Validation: the app's real-time model against path-traced truth</h1>
HTML
    echo "<p>Each row: one fabric bundle under one environment. <b>Verdict</b>: mean CIEDE2000 of the"
    echo "app's shading (consistent mode, the SH bands the bundle ships) against the truth after"
    echo "exposure; good &le; $MAX_DE2000, marginal &le; $(jq -n "2 * $MAX_DE2000"), else poor."
    echo "<b>Advice</b> says what would make it better. Images: truth | real-time model | relative"
    echo "error heat map (0 to 0.5), then truth | CPU model | GLES shader | error where the pair drew the"
    echo "exported shaders. <b>GLES</b>: the exported GLES shader (same exporter, grid and bands as the bundle's; consistent, highp, through EGL)"
    echo "against the truth, with the share of its pixels within 1e-3 of the CPU model (drawn at one"
    echo "fragment per pixel, the CPU column supersampled: a higher GLES dE2000 with full agreement is"
    echo "the pixel footprint, texture aliasing that MSAA or mipmaps would remove). <b>Budget</b>:"
    echo "the fewest SH bands and dominant lights envmap-project --max-error finds for this environment"
    echo "and the bundle's table. <b>Largest part</b>: of the model's error at the shipped bands"
    echo "(render compare --decompose: grid, SH diffuse/specular truncation, fixed view, visibility).</p>"
    echo "<h2>Verdicts</h2><table><tr><th>fabric</th><th>environment</th><th>verdict</th><th>dE2000 CPU model</th><th>GLES dE2000 (agrees)</th><th>seed shader dE2000</th><th>truth noise</th><th>budget</th><th>largest part</th><th>advice</th><th>truth | model | error</th><th>truth | CPU | GLES | error</th></tr>"
    jq -r 'def r(n): . * n | round / n; .[] | "<tr class=\"\(.verdict)\"><td>\(.fabric)</td><td>\(.environment)</td><td>\(.verdict)\(if .noise_limited then " (noise-limited)" else "" end)\(if .gate then "; gate \(.gate.verdict)" else "" end)</td><td>\(.shipped.mean_de2000 | r(100))</td><td>\(if .gles_shipped then "\(.gles_shipped.mean_de2000 | r(100)) (\(.gles_shipped.cpu_model_fraction_within_1e_3 * 100 | round)%)" else "-" end)</td><td>\(.seed.mean_de2000 | r(100))</td><td>\(.truth.rel_noise | r(1000))</td><td>\(.budget_text // "-")</td><td>\(if .largest_part then "\(.largest_part) \(.error_parts[.largest_part] | r(1000))" else "-" end)</td><td>\(.advice)</td><td><img class=\"pair\" src=\"pairs/\(.fabric)/\(.environment)/\(.images.compare_consistent)\" alt=\"\(.fabric) \(.environment)\"></td><td>\(if .gles_shipped then "<img class=\"pair\" src=\"pairs/\(.fabric)/\(.environment)/render_compare3_\(.gles_shipped.variant).png\" alt=\"GLES\">" else "-" end)</td></tr>"' "$V/summary.json"
    echo "</table>"
    if [ "${#BTF_KEYS[@]}" -gt 0 ]; then
        echo "<h2>BTF fabrics: the BTF shaded as a BTF</h2><p>"
        btf_measures_text | sed 's/\*\*\([^*]*\)\*\*/<b>\1<\/b>/g'
        echo "</p><table><tr><th>fabric</th><th>environment</th><th>truth noise</th><th>raw BTF vs truth: dE2000 (rel.)</th><th>shipped BTF: components, kB</th><th>shipped vs truth: dE2000 (rel.)</th><th>shipped vs raw BTF: rel. RMSE</th><th>enough: within $JND_DE2000 dE2000 of the whole stream</th><th>BRDF-table model dE2000 (textured patch)</th><th>truth | raw BTF | error</th></tr>"
        jq -r 'def r(n): . * n | round / n; .[] | select(.btf_view) | .btf_view as $b | "<tr><td>\(.fabric)</td><td>\(.environment)</td><td>\($b.truth_noise | r(1000))</td><td>\($b.raw.mean_de2000 | r(100)) (\($b.raw.mean_rel | r(1000)))</td><td>\($b.shipped.components_sent), \($b.shipped.bytes / 1000 | r(10))</td><td>\($b.shipped.mean_de2000 | r(100)) (\($b.shipped.mean_rel | r(1000)))</td><td>\($b.shipped.vs_raw_rel_rmse | r(1000))</td><td>\(.btf_enough.components_sent) components, \(.btf_enough.bytes_sent / 1000 | r(10)) kB (dE2000 \(.btf_enough.mean_de2000 | r(100)))</td><td>\(.shipped.mean_de2000 | r(100))</td><td><img class=\"pair\" src=\"pairs/\(.fabric)/\(.environment)/\($b.compare_image)\" alt=\"BTF \(.fabric) \(.environment)\"></td></tr>"' "$V/summary.json"
        echo "</table><p>Error against the stream, median (and worst) over the environments:</p>"
        btf_stream_table html
        echo "<p>The BTF's view dependence, median (and worst) over the environments (images: truth | raw BTF | error at each view):</p>"
        btf_view_table html
        if [ "$BTF_GLES" -gt 0 ]; then
            echo "<p>The BTF as the phone draws it: the bundle's BTF GLES shaders through EGL, one fragment per texel, lit by the environment's SH at the shipped bands (docs/btf-gles.md), median (and worst) over the environments:</p>"
            btf_gles_table html
        fi
        jq -r '.[] | select(.btf_view) | "<p>\(.fabric) under \(.environment): " + ([.fabric as $f | .environment as $e | .btf.views[] | "<img class=\"pair\" src=\"pairs/\($f)/\($e)/\(.compare_image)\" alt=\"BTF \($f) \($e) theta \(.view_deg[0]) phi \(.view_deg[1])\" title=\"theta \(.view_deg[0]), phi \(.view_deg[1]) deg\">"] | join(" ")) + "</p>"' "$V/summary.json"
    fi
    echo "<h2>Error against cost</h2>"
    for p in error_vs_sh_bands error_vs_frame_time error_vs_spp truth_noise error_vs_bytes error_parts btf_error_vs_components btf_error_vs_bytes; do
        [ -f "$P/$p.png" ] && echo "<p><img src=\"plots/$p.png\" alt=\"$p\"></p>"
    done
    echo "<p>Data: <a href=\"summary.json\">summary.json</a>, <a href=\"summary.md\">summary.md</a>.</p>"
    echo "</body></html>"
} > "$V/index.html"
echo "validate: $(jq -r 'group_by(.verdict) | map("\(length) \(.[0].verdict)") | join(", ")' "$V/summary.json") of $(jq length "$V/summary.json") pairs; report $V/index.html" >&2
