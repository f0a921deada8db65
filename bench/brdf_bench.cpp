// brdf_bench: error against time of the bake integrators (docs/brdf.md, "Benchmarks").
// Each case bakes GGX (alpha 0.25, f0 0.04, normal view) on thetaphi:5x16@80 (80 normals, none
// edge-on) and reports the max coefficient error relative to the largest reference coefficient
// (counter "err_rel") and the max radiance error under the test lightings relative to the
// largest reference radiance ("rad_err_rel"), against a gauss-legendre reference with
// 256 x 512 nodes per normal. Arguments: integrator (0 stratified-mc, 1 gauss-legendre,
// 2 sobol-is) / sh_bands / samples per normal / threads.
#include <benchmark/benchmark.h>

#include <ctime>
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

// make(key) computed once per key and type, kept for the process.
template <typename T, typename Make>
const T& cached(int key, Make&& make) {
    static std::mutex mu;
    static std::map<int, T> cache;
    std::lock_guard<std::mutex> lock(mu);
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, make(key)).first;
    return it->second;
}

const Table& reference(int bands) {
    return cached<Table>(bands, [](int b) {
        BakeOptions o;
        o.sh_bands = b;
        o.integrator = Integrator::kGaussLegendre;
        o.samples = 2 * 256 * 256;
        return bake(bench_material(), parse_grid("thetaphi:5x16@80"), o);
    });
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

// The report's grid (report5x5, edge-on row included) against the independent cubature reference
// (validate(): Genz-Malik in plain theta-phi, to 1e-7 of each node's largest coefficient):
// error of the stored float32 table relative to its largest coefficient, and the process CPU
// time of one bake (all threads), the figure that survives a shared machine. Arguments: model
// (0 the report's Cook-Torrance f 0.04 r 0.3, 1 GGX alpha 1 f0 1) / integrator / samples.
Material report_grid_material(int model) {
    Material m;
    if (model == 0) {
        m.specular = Model::kCookTorranceReport;
        m.report_f = 0.04;
        m.report_r = 0.3;
    } else {
        m.specular = Model::kGgx;
        m.alpha = 1.0;
        m.f0 = Eigen::Vector3d::Ones();
    }
    return m;
}

const ReferenceSet& report_grid_reference(int model) {
    return cached<ReferenceSet>(model, [](int mdl) {
        ValidateOptions v;
        v.max_nodes = 0;
        v.test_normals = 4;
        return make_reference(report_grid_material(mdl), parse_grid("report5x5"),
                              Eigen::Vector3d::UnitZ(), v);
    });
}

double process_cpu_s() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_ReportGrid(benchmark::State& state) {
    const int model = static_cast<int>(state.range(0));
    const ReferenceSet& ref = report_grid_reference(model);
    BakeOptions o;
    o.integrator = static_cast<Integrator>(state.range(1));
    o.samples = static_cast<int>(state.range(2));
    Table t;
    const double cpu0 = process_cpu_s();
    for (auto _ : state) {
        t = bake(report_grid_material(model), ref.grid, o);
        benchmark::DoNotOptimize(t.coeffs.data());
    }
    state.counters["cpu_ms"] = 1e3 * (process_cpu_s() - cpu0) / state.iterations();
    state.counters["err_rel"] = validate(ref, t).integration_coeff_max_rel;
    state.counters["ref_err_rel"] = ref.error_max_rel;
    state.SetLabel(std::string(model == 0 ? "report f0.04 r0.3 " : "ggx a1 f0 1 ") +
                   to_string(o.integrator));
}

}  // namespace

BENCHMARK(BM_Bake)->Apply(args)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ReportGrid)
    ->ArgsProduct({{0, 1}, {0, 1}, {1024, 4096, 10000}})
    ->ArgNames({"model", "integrator", "samples"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
