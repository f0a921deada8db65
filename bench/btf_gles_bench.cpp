// Speed and memory of the BTF GLES shaders (gles/btf_export.h, docs/btf-gles.md) on this
// machine's driver (llvmpipe here). The fabric: the analytic BTF of btf/synthetic.h (rank 6) on
// the Bonn dome (81 views x 81 lights) at 256 x 256 px (or BTF_GLES_BENCH_SIDE_PX), compressed
// once by the btf-pca library (groups of k = 3 consecutive views: 27 groups, C = 8, 8-bit PNG)
// into a temporary folder removed at exit, and exported with gles::export_btf_gles at 3 SH bands.
//
// BM_BtfGlesFrame: a 1080 x 1920 RGBA32F target covered by the tiled fabric at one texel per pixel
// (u_uv_scale = target / image size: the texture repeats 4.2 x 7.5 times at 256 px), viewed from
// theta 30, phi 45 deg (its 3 nearest views lie in 3 groups: counter groups_bound), under the
// 3-band SH of a fixed smooth sky (smooth_sky_sh). Frame time: the harness' (gles::draw),
// glDrawArrays to glFinish, least of 3 draws after the first (which compiles), as gles_bench.
// Per variant and stream prefix N: 0 (means only), half the stream, the whole stream. Counters:
// N, the texture bytes the app uploads for the variant (the slabs it reads: all S for both
// versions) for the groups one frame binds (tex_frame_bytes) and for the whole fabric
// (tex_fabric_bytes), and the lighting-matrices.bin bytes (matrices_bytes).
//
// BM_BtfGlesFrameDecodeInShader: the ablation, the same draw with the decode in the shader (as
// exported before it was folded into the weights), to time the fold as a ratio in one run.
//
// BM_BtfFrameWeights: the app's per-frame CPU work, gles::btf_frame_weights (the view blend and
// the 3 blended views' (1 + C) x bands^2 matrices times the SH, per colour), at 2, 3 and 9 bands
// (one export each, the whole stream arrived). Counter madds_per_colour: sum over the blended
// views of (1 + C) (bands^2 + 1) (the matrix rows' dot products, then the blend weight).
// BM_BtfViewBlend: the view blend alone (render::select_views), the part that does not scale
// with the bands.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "btf/pca_run.h"
#include "btf/synthetic.h"
#include "core/conventions.h"
#include "core/log.h"
#include "core/number.h"
#include "envmap/project.h"
#include "gles/btf_draw.h"
#include "gles/btf_export.h"
#include "gles/harness.h"
#include "render/btf_shade.h"
#include "sh/sh.h"

namespace {

using namespace inlight;

constexpr int kWidth = 1080, kHeight = 1920;
constexpr int kSidePx = 256;       // the fabric's image size (compression time: counter compress_s)
constexpr int kViewGroup = 3, kComponents = 8;
constexpr int kRepeat = 4;         // the first draw compiles; the least of all is kept
const btf::Direction kView{30.0, 45.0};  // nearest views (30, 30), (30, 60), (45, 40): 3 groups

/// The fabric's image side: BTF_GLES_BENCH_SIDE_PX (16..512) when set (128: a 4x quicker run),
/// else kSidePx. Throws UsageError naming the variable for anything else.
int side_px() {
    const char* v = std::getenv("BTF_GLES_BENCH_SIDE_PX");
    return v ? static_cast<int>(parse_integer(v, "BTF_GLES_BENCH_SIDE_PX", 16, 512)) : kSidePx;
}

/// The btf-pca folder of the fabric, compressed once, removed when the process exits.
struct Folder {
    std::string root, dir;
    double compress_s = 0;  ///< btf-pca's wall time (read, fit, store, measure)
    Folder() {
        root = (std::filesystem::temp_directory_path() / "inlight_btf_gles_bench_XXXXXX").string();
        if (!mkdtemp(root.data())) throw std::runtime_error("btf_gles_bench: mkdtemp failed");
        dir = root + "/pca";
        btf::AnalyticBtfOptions ao;
        ao.width = ao.height = side_px();
        ao.rank = 6;
        const btf::AnalyticBtf raw(ao);
        btf::PcaRunOptions po;
        po.output = dir;
        po.pca.view_group_size = kViewGroup;
        po.pca.components = kComponents;
        const log::Level level = log::level();
        log::set_level(log::Level::kQuiet);  // no per-group lines in the bench's table
        compress_s = btf::compress_to_folder(raw, po, 0).at("time").at("total_s").get<double>();
        log::set_level(level);
        for (const std::string& w : log::take_warnings()) log::warn("btf-pca: " + w);
    }
    ~Folder() {
        std::error_code ec;
        std::filesystem::remove_all(root, ec);
    }
    Folder(const Folder&) = delete;
    Folder& operator=(const Folder&) = delete;
};

const Folder& folder() {
    static const Folder f;
    return f;
}

/// The export at `bands` (both variants) under the light rule `rule` (default: the export's),
/// made once per band count and rule.
const gles::BtfGlesExport& exported(int bands, btf::CellRule rule = gles::BtfGlesOptions().lighting.rule) {
    static std::map<std::pair<int, int>, std::unique_ptr<gles::BtfGlesExport>> cache;
    auto& e = cache[{bands, static_cast<int>(rule)}];
    if (!e) {
        gles::BtfGlesOptions o;
        o.sh_bands = bands;
        o.lighting.rule = rule;
        e = std::make_unique<gles::BtfGlesExport>(gles::export_btf_gles(folder().dir, o));
    }
    return *e;
}

const gles::BtfGlesVariant& variant(const gles::BtfGlesExport& e, gles::GlslVersion version) {
    for (const auto& v : e.variants) {
        if (v.version == version) return v;
    }
    throw std::runtime_error("btf_gles_bench: the export has no such variant");
}

/// A fixed smooth environment in the fabric's frame: a sky brightening toward the zenith with a
/// broad warm lobe toward (theta 40, phi 120 deg), on a 128 x 64 lat-long map, projected to `bands`.
Eigen::MatrixXd smooth_sky_sh(int bands) {
    image::Image env(128, 64, 3, image::ColorSpace::kLinearSrgb);
    const Eigen::Vector3d sun = direction_from_spherical(40 * kPi / 180, 120 * kPi / 180);
    for (int y = 0; y < env.height; ++y) {
        for (int x = 0; x < env.width; ++x) {
            const Eigen::Vector3d d = latlong_direction((x + 0.5) / env.width, (y + 0.5) / env.height);
            const double sky = 0.4 + 0.6 * std::max(d.z(), 0.0), lobe = 3.0 * std::exp(4.0 * (d.dot(sun) - 1));
            env.at(x, y, 0) = static_cast<float>(0.8 * sky + lobe);
            env.at(x, y, 1) = static_cast<float>(0.9 * sky + 0.85 * lobe);
            env.at(x, y, 2) = static_cast<float>(1.0 * sky + 0.6 * lobe);
        }
    }
    return envmap::project_latlong(env, bands);
}

int groups_bound(const gles::BtfFrame& f) {
    return static_cast<int>(std::set<int>(f.slot_group.begin(), f.slot_group.end()).size());
}

/// Draws `v` with `b` tiled over the kWidth x kHeight target, each iteration's time the least of
/// kRepeat draws (the first compiles); returns the last iteration's ms.
double time_frames(benchmark::State& state, const gles::Context& ctx, const gles::BtfGlesExport& e,
                   const gles::BtfGlesVariant& v, gles::Bindings b) {
    b.uv_scale = {static_cast<float>(kWidth) / e.width, static_cast<float>(kHeight) / e.height};
    const gles::Mesh quad = gles::btf_sample_quad();
    double ms = 0;
    for (auto _ : state) {
        ms = gles::draw(ctx, v.as_export, b, quad, kWidth, kHeight, gles::TargetFormat::kRgba32f, kRepeat).draw_ms;
        state.SetIterationTime(ms * 1e-3);
    }
    return ms;
}

// args: GLSL ES version (100 | 300), prefix (0 = means only, 1 = the first half of the stream,
// -1 = the whole stream). Both versions read every slab.
void BM_BtfGlesFrame(benchmark::State& state) {
    const gles::BtfGlesExport& e = exported(3);
    const bool es3 = state.range(0) == 300;
    const gles::BtfGlesVariant& v = variant(e, es3 ? gles::GlslVersion::kEs300 : gles::GlslVersion::kEs100);
    const int64_t sent = state.range(1) == 0   ? 0
                         : state.range(1) == 1 ? static_cast<int64_t>(e.stream.size() / 2)
                                               : static_cast<int64_t>(e.stream.size());
    const gles::Context ctx(es3 ? 3 : 2);
    const gles::BtfFrame frame = gles::btf_frame_weights(e, v, kView, smooth_sky_sh(3), sent);
    const double ms = time_frames(state, ctx, e, v, gles::btf_bindings(e, frame));
    const double slab_bytes = 4.0 * e.width * e.height;
    state.SetLabel(v.name + " | " + std::to_string(e.width) + " px, " + std::to_string(e.components.size()) +
                   " groups, S " + std::to_string(e.slabs) + " | " + ctx.info().renderer);
    state.counters["N"] = static_cast<double>(sent);
    state.counters["fragment_uniform_vectors"] = v.fragment_uniform_vectors;
    state.counters["groups_bound"] = groups_bound(frame);
    state.counters["tex_frame_bytes"] = groups_bound(frame) * v.slabs_used * slab_bytes;
    state.counters["tex_fabric_bytes"] = static_cast<double>(e.components.size()) * v.slabs_used * slab_bytes;
    state.counters["matrices_bytes"] = 4.0 * static_cast<double>(e.matrices.size());
    state.counters["compress_s"] = folder().compress_s;
    state.counters["Mfragments_per_s"] = kWidth * kHeight / (ms * 1e-3) * 1e-6;
}
BENCHMARK(BM_BtfGlesFrame)
    ->ArgNames({"es", "N"})
    ->Args({300, 0})
    ->Args({300, 1})
    ->Args({300, -1})
    ->Args({100, 0})
    ->Args({100, 1})
    ->Args({100, -1})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

/// The ablation: `folded` (an exported fragment shader) with the decode moved back into it, as
/// exported before the fold: per slot and slab u_scale and u_offset (3 S vec4 each) and
/// v = u_offset + u_scale * t dotted with the weights, 15 S vectors and 16 multiply-adds per slab
/// and slot against 9 S + 1 and 12. Its k-th weight line is slot k / S, slab k % S.
std::string decode_in_shader(const std::string& folded, int slabs_used) {
    const int n = 3 * slabs_used;
    std::string out;
    std::istringstream in(folded);
    int k = 0;
    for (std::string line; std::getline(in, line);) {
        if (line == "uniform vec4 u_bias;") {
            out += line + "\nuniform vec4 u_scale[" + std::to_string(n) + "];\nuniform vec4 u_offset[" +
                   std::to_string(n) + "];\n";
        } else if (line == "  vec4 t;") {
            out += line + "\n  vec4 v;\n";
        } else if (line.rfind("  sum += vec3(dot(t, ", 0) == 0) {
            std::string dots = line;
            for (size_t at = 0; (at = dots.find("dot(t, ", at)) != std::string::npos;) dots.replace(at, 7, "dot(v, ");
            out += "  v = u_offset[" + std::to_string(k) + "] + u_scale[" + std::to_string(k) + "] * t;\n" + dots + "\n";
            ++k;
        } else {
            out += line + "\n";
        }
    }
    if (k != n) throw std::runtime_error("btf_gles_bench: the fragment shader's weight lines changed");
    return out;
}

// The ablation's frame time beside BM_BtfGlesFrame's, same view and lighting (whole stream;
// u_scale 1, u_offset 0: the values do not change the work). args: GLSL ES version.
void BM_BtfGlesFrameDecodeInShader(benchmark::State& state) {
    const gles::BtfGlesExport& e = exported(3);
    const bool es3 = state.range(0) == 300;
    gles::BtfGlesVariant v = variant(e, es3 ? gles::GlslVersion::kEs300 : gles::GlslVersion::kEs100);
    v.as_export.fragment_source = decode_in_shader(v.as_export.fragment_source, v.slabs_used);
    v.as_export.name += "-decode-in-shader";
    const gles::Context ctx(es3 ? 3 : 2);
    const gles::BtfFrame frame =
        gles::btf_frame_weights(e, v, kView, smooth_sky_sh(3), static_cast<int64_t>(e.stream.size()));
    gles::Bindings b = gles::btf_bindings(e, frame);
    const size_t n4 = static_cast<size_t>(3 * v.slabs_used) * 4;
    b.vec4_arrays.emplace_back("u_scale", std::vector<float>(n4, 1.f));
    b.vec4_arrays.emplace_back("u_offset", std::vector<float>(n4, 0.f));
    const double ms = time_frames(state, ctx, e, v, b);
    state.SetLabel(v.as_export.name + " | " + ctx.info().renderer);
    state.counters["fragment_uniform_vectors"] = 15.0 * v.slabs_used;
    state.counters["Mfragments_per_s"] = kWidth * kHeight / (ms * 1e-3) * 1e-6;
}
BENCHMARK(BM_BtfGlesFrameDecodeInShader)
    ->ArgNames({"es"})
    ->Args({300})
    ->Args({100})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// args: SH bands of the export's matrices (and of the lighting).
void BM_BtfFrameWeights(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0));
    const gles::BtfGlesExport& e = exported(bands);
    const gles::BtfGlesVariant& v = variant(e, gles::GlslVersion::kEs300);
    const Eigen::MatrixXd sh = smooth_sky_sh(bands);
    const auto sent = static_cast<int64_t>(e.stream.size());
    for (auto _ : state) benchmark::DoNotOptimize(gles::btf_frame_weights(e, v, kView, sh, sent));
    const render::ViewBlend blend = render::select_views(e.views, kView, 3);
    double madds = 0;
    for (int view : blend.views) {
        const int g = e.manifest.at("views").at(static_cast<size_t>(view)).at("group").get<int>();
        madds += (1.0 + e.components[static_cast<size_t>(g)]) * (sh::count(bands) + 1);
    }
    state.counters["madds_per_colour"] = madds;
    state.counters["matrices_bytes"] = 4.0 * static_cast<double>(e.matrices.size());
    state.counters["groups_bound"] = groups_bound(gles::btf_frame_weights(e, v, kView, sh, sent));
}
BENCHMARK(BM_BtfFrameWeights)->ArgName("bands")->Arg(2)->Arg(3)->Arg(9)->Unit(benchmark::kMicrosecond);

// args: dominant lights (beside 3-band SH), their angular radius in degrees (0: point lights, one
// cell each; > 0: caps spread as kBtfCapSamples points).
void BM_BtfFrameWeightsWithLights(benchmark::State& state) {
    // cosine_cells 0: the default rule (cosine-barycentric: a triangle search per point); 1: the
    // cosine rule (a nearest-direction search per point).
    const gles::BtfGlesExport& e =
        exported(3, state.range(2) ? btf::CellRule::kCosine : gles::BtfGlesOptions().lighting.rule);
    const gles::BtfGlesVariant& v = variant(e, gles::GlslVersion::kEs300);
    const Eigen::MatrixXd sh = smooth_sky_sh(3);
    const auto sent = static_cast<int64_t>(e.stream.size());
    std::vector<gles::BtfLight> lights;
    const btf::Direction at[3] = {{35, 60}, {70, 200}, {10, 300}};
    for (int i = 0; i < state.range(0); ++i)
        lights.push_back({at[i % 3].vector(), {20, 18, 15}, static_cast<double>(state.range(1)) * kPi / 180});
    for (auto _ : state) benchmark::DoNotOptimize(gles::btf_frame_weights(e, v, kView, sh, sent, lights));
}
BENCHMARK(BM_BtfFrameWeightsWithLights)
    ->ArgNames({"lights", "radius_deg", "cosine_cells"})
    ->ArgsProduct({{1, 3}, {0, 5}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

// The part of btf_frame_weights that does not depend on the bands: the 3 nearest of the 81 views.
void BM_BtfViewBlend(benchmark::State& state) {
    const gles::BtfGlesExport& e = exported(3);
    for (auto _ : state) benchmark::DoNotOptimize(render::select_views(e.views, kView, 3));
}
BENCHMARK(BM_BtfViewBlend)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
    try {
        side_px();  // a bad BTF_GLES_BENCH_SIDE_PX is refused before any work
    } catch (const std::exception& e) {
        std::fprintf(stderr, "btf_gles_bench: %s\n", e.what());
        return 2;
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
