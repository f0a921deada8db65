// Frame time of the exported GLES shaders on this machine's driver (llvmpipe here) for a
// 1080 x 1920 phone screen filled by the textured satin patch (the app's case), per variant,
// beside the CPU model (render/realtime.h) on the same scene at one fragment per pixel. The
// GPU time is glDrawArrays to glFinish, the least of 3 draws after the first (which compiles).
// Error against the truth per variant: render --compare (docs/gles.md, docs/benchmarks.md).
#include <benchmark/benchmark.h>

#include "brdf/bake.h"
#include "core/parallel.h"
#include "gles/scene.h"
#include "render/realtime.h"

namespace {

using namespace inlight;

constexpr int kWidth = 1080, kHeight = 1920;

const render::Scene& scene() {
    static const render::Scene s = [] {
        const std::string path = std::string(INLIGHT_SOURCE_DIR) + "/configs/scenes/patch_city.toml";
        render::SceneDesc d = render::load_scene_desc(path);
        d.camera.width_px = kWidth;
        d.camera.height_px = kHeight;
        return render::Scene(d);
    }();
    return s;
}

const render::RealtimeLighting& lighting() {
    static const render::RealtimeLighting l = [] {
        render::RealtimeLighting r;
        r.coeffs = render::project_environment(scene().environment(), 5);
        brdf::BakeOptions bo;
        bo.sh_bands = 5;
        bo.samples = 1024;
        for (const auto& m : scene().materials()) {
            r.tables.push_back(brdf::bake(m.brdf, brdf::parse_grid("octa:17"), bo));
        }
        return r;
    }();
    return l;
}

// args: GLSL ES version (100 | 300), mode (0 consistent, 1 seed), bands, precision (0 highp,
// 1 mediump).
void BM_GlesFrame(benchmark::State& state) {
    const gles::Variant v{state.range(0) == 100 ? gles::GlslVersion::kEs100 : gles::GlslVersion::kEs300,
                          state.range(1) == 0 ? gles::ShaderMode::kConsistent : gles::ShaderMode::kSeed,
                          static_cast<int>(state.range(2)),
                          state.range(3) == 0 ? gles::Precision::kHighp : gles::Precision::kMediump};
    const gles::Context ctx(v.version == gles::GlslVersion::kEs300 ? 3 : 2);
    std::vector<gles::Export> exports;
    for (size_t i = 0; i < scene().materials().size(); ++i) {
        const auto& m = scene().materials()[i];
        gles::MaterialInputs in;
        if (m.albedo_texture) in.albedo_texture_px = {m.albedo_texture->width, m.albedo_texture->height};
        if (m.normal_texture) in.normal_texture_px = {m.normal_texture->width, m.normal_texture->height};
        exports.push_back(gles::export_variant(&lighting().tables[i], in, v, ctx.info().limits));
    }
    double ms = 0;
    for (auto _ : state) {
        ms = gles::render_scene(ctx, scene(), exports, lighting().coeffs, 4).frame_ms;
        state.SetIterationTime(ms * 1e-3);
    }
    state.SetLabel(exports[0].name.substr(exports[0].name.find('-') + 1) + " | " + ctx.info().renderer);
    state.counters["Mfragments_per_s"] = kWidth * kHeight / (ms * 1e-3) * 1e-6;
}
BENCHMARK(BM_GlesFrame)
    ->ArgNames({"es", "seed", "bands", "mediump"})
    ->Args({300, 0, 3, 0})
    ->Args({300, 0, 3, 1})
    ->Args({300, 0, 5, 0})
    ->Args({300, 1, 3, 0})
    ->Args({100, 0, 3, 0})
    ->Args({100, 0, 3, 1})
    ->Args({100, 1, 3, 0})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// The CPU model on the same frame. args: mode (0 consistent, 1 seed), bands, threads.
void BM_CpuModelFrame(benchmark::State& state) {
    render::RealtimeOptions ro;
    ro.mode = state.range(0) == 0 ? render::RealtimeMode::kConsistent : render::RealtimeMode::kSeed;
    ro.sh_bands = static_cast<int>(state.range(1));
    ro.supersample = 1;
    lighting();  // bake outside the timing
    parallel::set_thread_count(static_cast<int>(state.range(2)));
    for (auto _ : state) {
        const image::Image img = render::render_realtime(scene(), lighting(), ro);
        benchmark::DoNotOptimize(img.pixels.data());
    }
    parallel::set_thread_count(0);
}
BENCHMARK(BM_CpuModelFrame)
    ->ArgNames({"seed", "bands", "threads"})
    ->Args({0, 3, 1})
    ->Args({0, 3, 2})
    ->Args({0, 5, 2})
    ->Args({1, 3, 2})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
