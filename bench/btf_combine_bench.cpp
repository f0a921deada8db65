// The compressed BTF under an environment (docs/btf-interpolation.md): one view's shaded image
// from a btf-pca folder, the environment folded into C coefficients per group and channel
// (CompressedBtf::combine) against decoding each of the 81 light images and summing them (the
// BtfSource default). Analytic BTF, UBO2003 dome, 64 x 64 px, k = 3, C = 16, 8-bit components.
// Counter: max_abs_diff between the two results (they compute the same sum).
// The app's per-frame step (btf/sh_lighting.h): SH lighting of 3 or 9 bands turned into one
// view's 1 + C component weights per colour by the baked (1 + C) x bands^2 matrices, against
// integrating a 64 x 32 map over the 81 light cells (the offline path); counter macs_per_colour.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "btf/compressed.h"
#include "btf/lighting.h"
#include "btf/pca_run.h"
#include "btf/sh_lighting.h"
#include "btf/synthetic.h"

namespace {

using namespace inlight;
using namespace inlight::btf;

struct Setup {
    std::unique_ptr<CompressedBtf> btf;
    std::vector<ImageTerm> terms;
};

const Setup& setup() {
    static const Setup s = [] {
        AnalyticBtfOptions o;
        o.width = o.height = 64;
        o.rank = 6;
        const AnalyticBtf raw(o);
        PcaRunOptions po;
        std::string dir = (std::filesystem::temp_directory_path() / "inlight_combine_bench_XXXXXX").string();
        if (!mkdtemp(dir.data())) throw std::runtime_error("combine_bench: mkdtemp failed");
        po.output = dir + "/pca";
        po.pca.view_group_size = 3;
        po.pca.components = 16;
        compress_to_folder(raw, po, 0);
        Setup r;
        r.btf = CompressedBtf::open(po.output);
        image::Image env(64, 32, 3, image::ColorSpace::kLinearSrgb);
        for (size_t i = 0; i < env.pixels.size(); ++i) env.pixels[i] = 0.5f + 0.5f * std::sin(0.01f * float(i));
        const DomeLighting lighting = integrate_dome_cells(env, raw.shape().lights);
        r.terms = shading_terms(lighting, {40}, {1.0}, 3.14159265358979);
        return r;
    }();
    return s;
}

void BM_ShadeFolded(benchmark::State& state) {
    const Setup& s = setup();
    for (auto _ : state) benchmark::DoNotOptimize(s.btf->combine(s.terms));
}

void BM_ShadeDecodeEachImage(benchmark::State& state) {
    const Setup& s = setup();
    for (auto _ : state) benchmark::DoNotOptimize(s.btf->BtfSource::combine(s.terms));
    const image::Image a = s.btf->combine(s.terms), b = s.btf->BtfSource::combine(s.terms);
    double m = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) m = std::max(m, double(std::abs(a.pixels[i] - b.pixels[i])));
    state.counters["max_abs_diff"] = m;
}

void BM_PerFrameComponentWeights(benchmark::State& state) {
    const Setup& s = setup();
    const int bands = static_cast<int>(state.range(0)), count = bands * bands;
    const Eigen::MatrixXd a = sh_light_weight_matrix(s.btf->shape().lights, bands, {}, 64);
    std::vector<Eigen::MatrixXd> m;  // per colour, view 40 (baked once)
    for (int ch = 0; ch < 3; ++ch) m.push_back(s.btf->lighting_matrix(40, ch, a, 3.14159265358979));
    Eigen::MatrixXd c(count, 3);
    for (int j = 0; j < count; ++j) c.row(j) << 1.0 / (1 + j), 0.5 / (1 + j), 0.25 / (1 + j);
    for (auto _ : state) {
        for (int ch = 0; ch < 3; ++ch) {
            Eigen::VectorXd w = m[static_cast<size_t>(ch)] * c.col(ch);
            benchmark::DoNotOptimize(w.data());
        }
    }
    state.counters["macs_per_colour"] = static_cast<double>(m[0].rows() * m[0].cols());
}

void BM_LightWeightsFromMap(benchmark::State& state) {
    const Setup& s = setup();
    image::Image env(64, 32, 3, image::ColorSpace::kLinearSrgb);
    for (size_t i = 0; i < env.pixels.size(); ++i) env.pixels[i] = 0.5f + 0.5f * std::sin(0.01f * float(i));
    for (auto _ : state) benchmark::DoNotOptimize(integrate_dome_cells(env, s.btf->shape().lights));
}

BENCHMARK(BM_PerFrameComponentWeights)->Arg(3)->Arg(9)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LightWeightsFromMap)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ShadeFolded)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ShadeDecodeEachImage)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
