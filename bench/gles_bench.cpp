// Frame time of the exported GLES shaders on this machine's driver (llvmpipe here) for a
// 1080 x 1920 phone screen filled by the textured satin patch (the app's case), per variant,
// beside the CPU model (render/realtime.h) on the same scene at one fragment per pixel. The
// GPU time is glDrawArrays to glFinish, the least of 3 draws after the first (which compiles).
// Variants with dominant lights (render/realtime_lights.h; frame time depends on their count,
// not their values: three fixed smooth-cap lights) and, with a small uniform-vector limit given
// to the exporter, with their lighting in a texture (RGBA32F on ES 3.00, RGBA8 on ES 1.00).
// Error against the truth per variant: render --compare (docs/gles.md, docs/benchmarks.md).
#include <benchmark/benchmark.h>

#include "brdf/bake.h"
#include "core/conventions.h"
#include "core/parallel.h"
#include "gles/scene.h"
#include "render/realtime.h"

namespace {

using namespace inlight;

constexpr int kWidth = 1080, kHeight = 1920;
constexpr int kTableBands = 6;  // ES 1.00 above 5 bands: the table's scale/offset in its texture

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
        r.coeffs = render::project_environment(scene().environment(), kTableBands);
        brdf::BakeOptions bo;
        bo.sh_bands = kTableBands;
        bo.samples = 1024;
        for (const auto& m : scene().materials()) {
            r.tables.push_back(brdf::bake(m.brdf, brdf::parse_grid("octa:17"), bo));
        }
        return r;
    }();
    return l;
}

/// `count` of three fixed lights (a small sun, a 5-degree lamp, a point), smooth caps (the
/// budget's default), world = device frame.
std::vector<envmap::DirectionalLight> lights(int count) {
    std::vector<envmap::DirectionalLight> out;
    const double dirs[3][2] = {{0.6, 0.5}, {1.1, 2.5}, {0.3, -2.0}};  // theta, phi
    const double radius_deg[3] = {0.27, 5.0, 0.0};
    for (int i = 0; i < count; ++i) {
        envmap::DirectionalLight l;
        l.direction = direction_from_spherical(dirs[i % 3][0], dirs[i % 3][1]);
        l.angular_radius = radius_deg[i % 3] * kPi / 180;
        l.flux = Eigen::Vector3d(3.0, 2.8, 2.5);
        l.shading = envmap::LightShading::kSmoothCap;
        out.push_back(l);
    }
    return out;
}

// args: GLSL ES version (100 | 300), mode (0 consistent, 1 seed), bands, precision (0 highp,
// 1 mediump), dominant lights, GL_MAX_FRAGMENT_UNIFORM_VECTORS given to the exporter (0 = the
// driver's; 16 = the ES 2.0 minimum, which moves the lighting into a texture).
void BM_GlesFrame(benchmark::State& state) {
    const int light_count = static_cast<int>(state.range(4));
    const std::vector<envmap::DirectionalLight> ls = lights(light_count);
    const gles::Variant v{state.range(0) == 100 ? gles::GlslVersion::kEs100 : gles::GlslVersion::kEs300,
                          state.range(1) == 0 ? gles::ShaderMode::kConsistent : gles::ShaderMode::kSeed,
                          static_cast<int>(state.range(2)),
                          state.range(3) == 0 ? gles::Precision::kHighp : gles::Precision::kMediump,
                          light_count, envmap::LightShading::kSmoothCap};
    const gles::Context ctx(v.version == gles::GlslVersion::kEs300 ? 3 : 2);
    gles::Limits limits = ctx.info().limits;
    if (state.range(5) > 0) limits.max_fragment_uniform_vectors = static_cast<int>(state.range(5));
    std::vector<gles::Export> exports;
    for (size_t i = 0; i < scene().materials().size(); ++i) {
        const auto& m = scene().materials()[i];
        gles::MaterialInputs in;
        if (m.albedo_texture) in.albedo_texture_px = {m.albedo_texture->width, m.albedo_texture->height};
        if (m.normal_texture) in.normal_texture_px = {m.normal_texture->width, m.normal_texture->height};
        in.brdf = m.brdf;
        exports.push_back(gles::export_variant(&lighting().tables[i], in, v, limits));
    }
    double ms = 0;
    for (auto _ : state) {
        ms = gles::render_scene(ctx, scene(), exports, lighting().coeffs, 4, ls).frame_ms;
        state.SetIterationTime(ms * 1e-3);
    }
    const gles::Export& e = exports[0];
    state.SetLabel(e.name.substr(e.name.find('-') + 1) + " | table " + gles::to_string(e.table_layout) +
                   ", lighting " + gles::to_string(e.lighting_layout) + " | " + ctx.info().renderer);
    state.counters["Mfragments_per_s"] = kWidth * kHeight / (ms * 1e-3) * 1e-6;
}
BENCHMARK(BM_GlesFrame)
    ->ArgNames({"es", "seed", "bands", "mediump", "lights", "vectors"})
    ->Args({300, 0, 3, 0, 0, 0})
    ->Args({300, 0, 3, 1, 0, 0})
    ->Args({300, 0, 5, 0, 0, 0})
    ->Args({300, 1, 3, 0, 0, 0})
    ->Args({300, 0, 3, 0, 1, 0})
    ->Args({300, 0, 3, 0, 3, 0})
    ->Args({300, 0, 5, 0, 0, 16})  // lighting in an RGBA32F texture
    ->Args({300, 0, 3, 0, 3, 16})
    ->Args({100, 0, 3, 0, 0, 0})
    ->Args({100, 0, 3, 1, 0, 0})
    ->Args({100, 1, 3, 0, 0, 0})
    ->Args({100, 0, 3, 0, 3, 0})
    ->Args({100, 0, 3, 0, 3, 16})  // the ES 2.0 minimum: lighting in an RGBA8 texture
    ->Args({100, 0, 5, 0, 0, 16})
    ->Args({100, 0, 6, 0, 0, 0})
    ->Args({100, 0, 6, 0, 0, 16})  // the table's scale/offset in its texture too
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// The CPU model on the same frame. args: mode (0 consistent, 1 seed), bands, threads, lights.
void BM_CpuModelFrame(benchmark::State& state) {
    render::RealtimeLighting lit = lighting();
    lit.lights = lights(static_cast<int>(state.range(3)));
    render::RealtimeOptions ro;
    ro.mode = state.range(0) == 0 ? render::RealtimeMode::kConsistent : render::RealtimeMode::kSeed;
    ro.sh_bands = static_cast<int>(state.range(1));
    ro.supersample = 1;
    lighting();  // bake outside the timing
    parallel::set_thread_count(static_cast<int>(state.range(2)));
    for (auto _ : state) {
        const image::Image img = render::render_realtime(scene(), lit, ro);
        benchmark::DoNotOptimize(img.pixels.data());
    }
    parallel::set_thread_count(0);
}
BENCHMARK(BM_CpuModelFrame)
    ->ArgNames({"seed", "bands", "threads", "lights"})
    ->Args({0, 3, 1, 0})
    ->Args({0, 3, 2, 0})
    ->Args({0, 5, 2, 0})
    ->Args({0, 6, 2, 0})
    ->Args({1, 3, 2, 0})
    ->Args({0, 3, 2, 1})
    ->Args({0, 3, 2, 3})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()  // CPU seconds of all threads: the wall time follows the load
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
