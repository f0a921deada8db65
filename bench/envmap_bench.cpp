// Projection throughput of lat-long maps next to the memory-bandwidth bound for the same bytes.
// Run with `make bench`. Counters: Mpixel_per_s (wall), Mpixel_per_cpu_s (all threads' CPU time,
// the figure that survives a shared machine), GB_per_s, and x_google_sh: Mpixel_per_s over
// google/spherical-harmonics' ProjectEnvironment, 4.2 Mpixel/s on one thread of the 2-core
// session machine (that library is not packaged for Debian, so it is not rerun here).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <numeric>

#include "core/conventions.h"
#include "core/parallel.h"
#include "envmap/project.h"

namespace {

using inlight::image::Image;

Image make_map(int w) {
    Image img(w, w / 2, 3);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = static_cast<float>(1.0 + 0.5 * std::sin(0.001 * static_cast<double>(i)));
    return img;
}

const Image& map_of_width(int w) {
    static const Image small = make_map(1024);
    static const Image large = make_map(4096);
    return w == 1024 ? small : large;
}

constexpr double kGoogleShMpixelPerS = 4.2;

double process_cpu_s() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void set_counters(benchmark::State& state, const Image& img, double cpu_s) {
    const double pixels = static_cast<double>(img.pixel_count()) * state.iterations();
    state.counters["Mpixel_per_s"] = benchmark::Counter(pixels * 1e-6, benchmark::Counter::kIsRate);
    state.counters["Mpixel_per_cpu_s"] = pixels * 1e-6 / std::max(cpu_s, 1e-9);
    state.counters["GB_per_s"] =
        benchmark::Counter(pixels * 12 * 1e-9, benchmark::Counter::kIsRate);
    state.counters["x_google_sh"] = benchmark::Counter(pixels * 1e-6 / kGoogleShMpixelPerS,
                                                       benchmark::Counter::kIsRate);
}

// args: width, threads, sh_bands, float (1: float row sums, the default; 0: the double path)
void BM_ProjectLatLong(benchmark::State& state) {
    const Image& img = map_of_width(static_cast<int>(state.range(0)));
    inlight::parallel::set_thread_count(static_cast<int>(state.range(1)));
    const auto precision = state.range(3) ? inlight::envmap::LatlongPrecision::kFloatRowSums
                                          : inlight::envmap::LatlongPrecision::kDouble;
    const double cpu0 = process_cpu_s();
    for (auto _ : state) {
        benchmark::DoNotOptimize(
            inlight::envmap::project_latlong(img, static_cast<int>(state.range(2)), precision));
    }
    set_counters(state, img, process_cpu_s() - cpu0);
}

// The bound: one pass summing the same floats (what any projection must at least read).
void BM_MemoryBound(benchmark::State& state) {
    const Image& img = map_of_width(static_cast<int>(state.range(0)));
    inlight::parallel::set_thread_count(static_cast<int>(state.range(1)));
    const double cpu0 = process_cpu_s();
    for (auto _ : state) {
        const double s = inlight::parallel::reduce(
            static_cast<int64_t>(img.pixels.size()), 1 << 16, 0.0,
            [&](int64_t b, int64_t e) {
                // Eight independent accumulators so the loop is limited by memory, not by the
                // latency of one chain of additions.
                double acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                const float* p = img.pixels.data();
                int64_t i = b;
                for (; i + 8 <= e; i += 8) {
                    for (int k = 0; k < 8; ++k) acc[k] += p[i + k];
                }
                for (; i < e; ++i) acc[0] += p[i];
                return acc[0] + acc[1] + acc[2] + acc[3] + acc[4] + acc[5] + acc[6] + acc[7];
            },
            [](double a, double b) { return a + b; });
        benchmark::DoNotOptimize(s);
    }
    set_counters(state, img, process_cpu_s() - cpu0);
}

}  // namespace

BENCHMARK(BM_ProjectLatLong)
    ->ArgsProduct({{1024, 4096}, {1, 2}, {3, 9}, {1, 0}})
    ->ArgNames({"width", "threads", "sh_bands", "float"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_MemoryBound)
    ->ArgsProduct({{1024, 4096}, {1, 2}})
    ->ArgNames({"width", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
