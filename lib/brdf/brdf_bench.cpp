// brdf_bench: error against time of the bake integrators (docs/brdf.md, "Benchmarks").
// Each case bakes GGX (alpha 0.25, f0 0.04, normal view) on thetaphi:5x16@80 (80 normals, none
// edge-on) and reports the max coefficient error relative to the largest reference coefficient
// (counter "err_rel") and the max radiance error under the test lightings relative to the
// largest reference radiance ("rad_err_rel"), against a gauss-legendre reference with
// 256 x 512 nodes per normal. Arguments: integrator (0 stratified-mc, 1 gauss-legendre,
// 2 sobol-is) / sh_bands / samples per normal / threads.
#include <benchmark/benchmark.h>

#include <map>
#include <mutex>

#include "brdf/bake.h"
#include "core/parallel.h"

namespace {

using namespace inlight::brdf;

Material bench_material() {
    Material m;
    m.specular = Model::kGgx;
    m.alpha = 0.25;
    return m;
}

const Table& reference(int bands) {
    static std::mutex mu;
    static std::map<int, Table> cache;
    std::lock_guard<std::mutex> lock(mu);
    auto it = cache.find(bands);
    if (it == cache.end()) {
        BakeOptions o;
        o.sh_bands = bands;
        o.integrator = Integrator::kGaussLegendre;
        o.samples = 2 * 256 * 256;
        it = cache.emplace(bands, bake(bench_material(), parse_grid("thetaphi:5x16@80"), o)).first;
    }
    return it->second;
}

void BM_Bake(benchmark::State& state) {
    const auto integrator = static_cast<Integrator>(state.range(0));
    const int bands = static_cast<int>(state.range(1));
    const int samples = static_cast<int>(state.range(2));
    const int threads = static_cast<int>(state.range(3));
    const Table& ref = reference(bands);
    inlight::parallel::set_thread_count(threads);
    BakeOptions o;
    o.sh_bands = bands;
    o.integrator = integrator;
    o.samples = samples;
    Table t;
    for (auto _ : state) {
        t = bake(bench_material(), ref.grid, o);
        benchmark::DoNotOptimize(t.coeffs.data());
    }
    double max_ref = 0, max_err = 0;
    for (size_t i = 0; i < t.coeffs.size(); ++i) {
        max_ref = std::max(max_ref, std::abs(static_cast<double>(ref.coeffs[i])));
        max_err = std::max(max_err, std::abs(static_cast<double>(t.coeffs[i]) - ref.coeffs[i]));
    }
    const auto lights = test_lighting_coeffs(bands);
    double rad_err = 0, rad_max = 0;
    const int kc = t.coeff_count();
    for (int node = 0; node < t.grid.node_count(); ++node) {
        for (const auto& l : lights) {
            double a = 0, b = 0;
            for (int k = 0; k < kc; ++k) {
                a += l[k] * t.coeffs[node * kc + k];
                b += l[k] * ref.coeffs[node * kc + k];
            }
            rad_err = std::max(rad_err, std::abs(a - b));
            rad_max = std::max(rad_max, std::abs(b));
        }
    }
    state.counters["err_rel"] = max_err / max_ref;
    state.counters["rad_err_rel"] = rad_err / rad_max;
    state.counters["coeffs"] = kc;
    state.SetLabel(to_string(integrator) + " threads=" + std::to_string(threads));
}

void args(benchmark::internal::Benchmark* b) {
    for (int integrator : {0, 1, 2}) {
        for (int bands : {3, 5}) {
            for (int samples : {256, 1024, 4096, 16384}) {
                for (int threads : {1, 2}) b->Args({integrator, bands, samples, threads});
            }
        }
    }
}

}  // namespace

BENCHMARK(BM_Bake)->Apply(args)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
