// Projection throughput of lat-long maps next to the memory-bandwidth bound for the same bytes.
// Run with `make bench`. Counters: Mpixel_per_s, GB_per_s.
#include <benchmark/benchmark.h>

#include <cmath>
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

void set_counters(benchmark::State& state, const Image& img) {
    const double pixels = static_cast<double>(img.pixel_count()) * state.iterations();
    state.counters["Mpixel_per_s"] = benchmark::Counter(pixels * 1e-6, benchmark::Counter::kIsRate);
    state.counters["GB_per_s"] =
        benchmark::Counter(pixels * 12 * 1e-9, benchmark::Counter::kIsRate);
}

// args: width, threads, sh_bands
void BM_ProjectLatLong(benchmark::State& state) {
    const Image& img = map_of_width(static_cast<int>(state.range(0)));
    inlight::parallel::set_thread_count(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        benchmark::DoNotOptimize(
            inlight::envmap::project_latlong(img, static_cast<int>(state.range(2))));
    }
    set_counters(state, img);
}

// The bound: one pass summing the same floats (what any projection must at least read).
void BM_MemoryBound(benchmark::State& state) {
    const Image& img = map_of_width(static_cast<int>(state.range(0)));
    inlight::parallel::set_thread_count(static_cast<int>(state.range(1)));
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
    set_counters(state, img);
}

}  // namespace

BENCHMARK(BM_ProjectLatLong)
    ->ArgsProduct({{1024, 4096}, {1, 2}, {3, 9}})
    ->ArgNames({"width", "threads", "sh_bands"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_MemoryBound)
    ->ArgsProduct({{1024, 4096}, {1, 2}})
    ->ArgNames({"width", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
