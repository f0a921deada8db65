// Path tracer throughput: rays per second and camera samples per second at 1 and 2 threads, on
// the app's case (textured GGX fabric patch, orthographic) and on the draped-cloth mesh with a
// floor (interreflection). Environment: city.exr when blender-data is installed, else a
// synthetic 1024x512 sky. Run with `make bench` or build/bench/render_bench.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "brdf/bake.h"
#include "core/conventions.h"
#include "core/parallel.h"
#include "render/path_tracer.h"
#include "render/realtime.h"
#include "render/render_testing.h"

namespace {

using namespace inlight;
using namespace inlight::render;

image::Image environment_map() {
    const std::string city = "/usr/share/blender/datafiles/studiolights/world/city.exr";
    if (std::filesystem::exists(city)) return load_latlong(city);
    image::Image img(1024, 512, 3);
    for (int y = 0; y < 512; ++y) {
        for (int x = 0; x < 1024; ++x) {
            const Eigen::Vector3d d = latlong_direction((x + 0.5) / 1024, (y + 0.5) / 512);
            const double v =
                0.3 + std::max(0.0, d.z()) + 500.0 * std::pow(std::max(0.0, d.x()), 400);
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(v);
        }
    }
    return img;
}

/// The app's case of the render tests (render_testing.h) at 64x64, the camera as wide as the
/// patch (as the figures in docs/benchmarks.md were measured).
SceneDesc patch_scene() {
    SurfaceMaterial m;
    m.name = "satin";
    m.brdf.specular = brdf::Model::kGgx;
    m.brdf.alpha = 0.2;
    SceneDesc d = testscenes::patch_scene(m, 64);
    d.camera.ortho_height = 1;
    d.environment.image = environment_map();
    return d;
}

SceneDesc drape_scene() {
    SceneDesc d = patch_scene();
    d.camera.projection = Projection::kPerspective;
    d.camera.position = {0, -1.4, 1.1};
    d.camera.look_at = {0, 0, -0.05};
    d.camera.up = {0, 0, 1};
    SurfaceMaterial velvet;
    velvet.name = "velvet";
    velvet.brdf.specular = brdf::Model::kCharlie;
    velvet.brdf.alpha = 0.5;
    d.materials.push_back(velvet);
    ObjectSpec cloth;
    cloth.shape.kind = ShapeKind::kMesh;
    cloth.mesh_path = std::string(INLIGHT_SOURCE_DIR) + "/tests/render/data/drape.obj";
    cloth.material = "velvet";
    ObjectSpec floor;
    floor.shape.kind = ShapeKind::kPatch;
    floor.shape.center = {0, 0, -0.3};
    floor.shape.size = {4, 4};
    floor.material = "satin";
    d.objects = {cloth, floor};
    return d;
}

const Scene& scene(int which) {
    static const Scene patch(patch_scene());
    static const Scene drape(drape_scene());
    return which == 0 ? patch : drape;
}

// args: scene (0 patch, 1 drape), threads
void BM_PathTrace(benchmark::State& state) {
    const Scene& s = scene(static_cast<int>(state.range(0)));
    parallel::set_thread_count(static_cast<int>(state.range(1)));
    RenderOptions o;
    o.spp = 4;
    int64_t rays = 0, samples = 0;
    for (auto _ : state) {
        const RenderResult r = inlight::render::render(s, o);
        rays += r.rays;
        samples += r.samples;
        benchmark::DoNotOptimize(r.radiance.pixels.data());
    }
    state.counters["Mrays_per_s"] = benchmark::Counter(rays * 1e-6, benchmark::Counter::kIsRate);
    state.counters["Msamples_per_s"] =
        benchmark::Counter(samples * 1e-6, benchmark::Counter::kIsRate);
    state.counters["rays_per_sample"] = static_cast<double>(rays) / std::max<int64_t>(1, samples);
    parallel::set_thread_count(0);
}
BENCHMARK(BM_PathTrace)
    ->ArgNames({"scene", "threads"})
    ->Args({0, 1})
    ->Args({0, 2})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Time per frame of the real-time model (CPU, one fragment per pixel) on the app's case at
// 256x256, consistent mode. args: sh_bands, threads.
void BM_RealtimeFrame(benchmark::State& state) {
    static const Scene s = [] {
        SceneDesc d = patch_scene();
        d.camera.width_px = d.camera.height_px = 256;
        return Scene(d);
    }();
    static const RealtimeLighting lighting =
        testscenes::one_material_lighting(s, 8, "octa:17", 1024);
    RealtimeOptions ro;
    ro.sh_bands = static_cast<int>(state.range(0));
    ro.supersample = 1;
    parallel::set_thread_count(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        const image::Image img = render_realtime(s, lighting, ro);
        benchmark::DoNotOptimize(img.pixels.data());
    }
    state.counters["Mfragments_per_s"] =
        benchmark::Counter(256.0 * 256.0 * state.iterations() * 1e-6, benchmark::Counter::kIsRate);
    parallel::set_thread_count(0);
}
BENCHMARK(BM_RealtimeFrame)
    ->ArgNames({"bands", "threads"})
    ->Args({3, 1})
    ->Args({3, 2})
    ->Args({5, 1})
    ->Args({8, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
