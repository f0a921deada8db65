// btf-pca's speed on a Bonn-size BTF (81 x 81 directions, 256 x 256 px, RGB): one view group
// fitted by each method (Gram, randomized SVD, full SVD) at the same C, with its error, and the
// whole BTF compressed group by group. The data is the analytic BTF of btf/synthetic.h with
// highlights pushed past 1 and clipped there, as 8-bit captures saturate, so it is not of low
// rank. Run with `make bench` (docs/benchmarks.md). Counters: group_s (one group), btf_s (all
// groups of that k: group_s x group count, or measured in BM_CompressBonnBtf), *_cpu_s (CPU time
// of all threads: the figure to trust on a shared machine), rmse (linear, unquantised, C = 8),
// peak_rss_mib. BM_Fit81: k = 81 (one group of all views) at 64 x 64 px in core against out of
// core (fit_group_streamed, one view per block), each run's peak memory its own; run each
// argument in its own process (--benchmark_filter=BM_Fit81/0/ or /1/) so the allocator's
// retained memory from one does not hide the other's peak.
// After the table the binary prints the Bonn-size summary (`make bench` shows it): the whole
// BTF at k = 1, C = 8 in CPU seconds and wall time with the load average around it, and one
// group's Gram fit against the full SVD in the same run (CPU and wall ratios, RMSE of each),
// against the compression goals (whole BTF <= 60 CPU s, i.e. under a minute on 2 free cores;
// Gram >= 10x faster than the full SVD at equal error).
//
// `btf_bench --write-ubo2003 DIR ...` writes the same data as image files instead: the end-to-end
// figure (pipelines/btf-pca-bench.sh) decodes them with the btf-pca tool (write_ubo2003_main).
#include <benchmark/benchmark.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "btf/archive.h"
#include "btf/dataset.h"
#include "btf/pca.h"
#include "btf/synthetic.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/memory.h"
#include "core/parallel.h"

namespace {

using namespace inlight::btf;

constexpr int kComponents = 8;

/// The 1-minute load average (/proc/loadavg), -1 when unknown.
double load_average() {
    std::ifstream in("/proc/loadavg");
    double x = -1;
    in >> x;
    return x;
}

/// What the Bonn-size summary needs, filled by the runs that measure it.
struct Measured {
    double cpu_s = -1, wall_s = -1, rmse = -1, load_before = -1, load_after = -1;
};
struct Summary {
    Measured gram, full_svd, whole;
    double whole_read_cpu_s = -1, whole_fit_cpu_s = -1, whole_peak_mib = -1;
} g_summary;

/// The benchmark's data: the analytic BTF of rank 6 at scale 4, by default at Bonn size.
AnalyticBtfOptions bench_options(int side_px = 256) {
    AnalyticBtfOptions o;
    o.width = o.height = side_px;
    o.rank = 6;
    o.scale = 4.0;
    return o;
}

/// An analytic BTF clipped at 1 like a saturated 8-bit capture.
class ClippedBtf : public BtfSource {
  public:
    explicit ClippedBtf(int side_px = 256) : ClippedBtf(bench_options(side_px)) {}
    explicit ClippedBtf(const AnalyticBtfOptions& o) : m_btf(std::make_unique<AnalyticBtf>(o)) {}
    const BtfShape& shape() const override { return m_btf->shape(); }
    inlight::image::Image read_image(int light, int view) const override {
        inlight::image::Image img = m_btf->read_image(light, view);
        for (float& v : img.pixels) v = std::min(v, 1.0f);
        return img;
    }
    /// The values before clipping.
    const AnalyticBtf& unclipped() const { return *m_btf; }

  private:
    std::unique_ptr<AnalyticBtf> m_btf;
};

const ClippedBtf& btf() {
    static const ClippedBtf b;
    return b;
}

/// The first view group of size k (read once).
const Eigen::MatrixXf& group(int k) {
    static std::map<int, Eigen::MatrixXf> cache;
    auto it = cache.find(k);
    if (it == cache.end()) {
        Eigen::MatrixXf a;
        btf().read_group(view_groups(btf().shape().views, k).front(), a);
        it = cache.emplace(k, std::move(a)).first;
    }
    return it->second;
}

// args: k, method (0 gram, 1 randomized, 2 full SVD)
void BM_FitGroup(benchmark::State& state) {
    const int k = static_cast<int>(state.range(0));
    PcaOptions o;
    o.components = kComponents;
    o.method = state.range(1) == 0 ? PcaMethod::kGram : state.range(1) == 1 ? PcaMethod::kRandomized : PcaMethod::kFullSvd;
    const Eigen::MatrixXf& a0 = group(k);
    double rmse = 0, wall_s = 0, cpu_s = 0;
    const double load_before = load_average();
    for (auto _ : state) {
        state.PauseTiming();
        Eigen::MatrixXf a = a0;
        state.ResumeTiming();
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        const GroupPca g = fit_group(a, {0}, o, 1);
        cpu_s += double(std::clock() - c0) / CLOCKS_PER_SEC;
        wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        rmse = g.rmse(g.components());
    }
    const double groups = static_cast<double>(view_groups(btf().shape().views, k).size());
    const double n = static_cast<double>(state.iterations());
    state.counters["group_s"] = wall_s / n;
    state.counters["group_cpu_s"] = cpu_s / n;  // all threads of the process
    state.counters["btf_s"] = groups * wall_s / n;
    state.counters["btf_cpu_s"] = groups * cpu_s / n;
    state.counters["rmse"] = rmse;
    state.SetLabel(to_string(o.method) + " k=" + std::to_string(k));
    if (k == 1 && (o.method == PcaMethod::kGram || o.method == PcaMethod::kFullSvd))
        (o.method == PcaMethod::kGram ? g_summary.gram : g_summary.full_svd) =
            Measured{cpu_s / n, wall_s / n, rmse, load_before, load_average()};
}

// The whole BTF, streamed by view group (generation of the images counts as reading).
void BM_CompressBonnBtf(benchmark::State& state) {
    PcaOptions o;
    o.components = kComponents;
    o.view_group_size = static_cast<int>(state.range(0));
    CompressStats stats;
    double cpu_s = 0, wall_s = 0;
    const double load_before = load_average();
    for (auto _ : state) {
        const std::clock_t c0 = std::clock();
        const auto t0 = std::chrono::steady_clock::now();
        stats = compress_btf(btf(), o, [](GroupFit&) {});
        cpu_s = double(std::clock() - c0) / CLOCKS_PER_SEC;
        wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    const double rmse = std::sqrt(stats.residual_energy / btf().shape().sample_count());
    if (o.view_group_size == 1) {
        g_summary.whole = Measured{cpu_s, wall_s, rmse, load_before, load_average()};
        g_summary.whole_read_cpu_s = stats.read_cpu_s;
        g_summary.whole_fit_cpu_s = stats.fit_cpu_s;
        g_summary.whole_peak_mib = static_cast<double>(inlight::peak_rss_bytes()) / 1048576.0;
    }
    state.counters["read_cpu_s"] = stats.read_cpu_s;
    state.counters["fit_cpu_s"] = stats.fit_cpu_s;
    state.counters["cpu_s"] = cpu_s;
    state.counters["read_s"] = stats.read_time_s;
    state.counters["fit_s"] = stats.fit_time_s;
    state.counters["rmse"] = rmse;
    state.counters["peak_rss_mib"] = static_cast<double>(inlight::peak_rss_bytes()) / 1048576.0;
}

/// Resets the process's peak resident memory (VmHWM) to the current one (Linux >= 4.0:
/// /proc/self/clear_refs "5"), so each run's peak is its own.
void reset_peak_rss() {
    if (std::FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
        std::fputs("5", f);
        std::fclose(f);
    }
}

// k = 81 (one PCA over the whole BTF, randomized SVD, C = 8) in core (arg 0: the group read
// whole) against out of core (arg > 0: views per block, fit_group_streamed). Peak memory is
// each run's own (reset before it).
void BM_Fit81(benchmark::State& state) {
    // 64 x 64 px: the whole BTF as one group is 322 MB of floats, small enough to hold.
    static const ClippedBtf small(64);
    PcaOptions o;
    o.components = kComponents;
    o.stream_views = static_cast<int>(state.range(0));
    std::vector<int> all(static_cast<size_t>(small.shape().n_views()));
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    GroupPca g;
    StreamStats st;
    double cpu_s = 0;
    uint64_t base = 0, peak = 0;
    for (auto _ : state) {
        reset_peak_rss();
        base = inlight::current_rss_bytes();
        const std::clock_t c0 = std::clock();
        if (o.stream_views > 0) {
            g = fit_group_streamed(small, all, o, 0, &st);
        } else {
            Eigen::MatrixXf a;
            small.read_group(all, a);
            g = fit_group(a, all, o, 0);
        }
        cpu_s = double(std::clock() - c0) / CLOCKS_PER_SEC;
        peak = inlight::peak_rss_bytes();
    }
    state.counters["cpu_s"] = cpu_s;
    state.counters["passes"] = st.passes;
    state.counters["rmse"] = g.rmse(g.components());
    state.counters["peak_rss_mib"] = static_cast<double>(peak) / 1048576.0;
    state.counters["peak_over_start_mib"] = static_cast<double>(peak - std::min(peak, base)) / 1048576.0;
    state.SetLabel(o.stream_views > 0 ? "out of core, " + std::to_string(o.stream_views) + " view(s) per block" : "in core");
}

}  // namespace

BENCHMARK(BM_Fit81)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_FitGroup)->Args({1, 0})->Args({1, 1})->Args({1, 2})->Args({3, 0})->Args({3, 1})->Args({9, 0})
    ->Args({9, 1})->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_CompressBonnBtf)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

namespace {

void print_summary() {
    const Summary& s = g_summary;
    const auto loads = [](const Measured& m) {
        char b[64];
        std::snprintf(b, sizeof b, "load average %.1f -> %.1f", m.load_before, m.load_after);
        return std::string(b);
    };
    std::printf("\nbtf-pca at Bonn size (81 x 81 directions, 256 x 256 px, RGB; analytic BTF clipped at 1), "
                "k = 1, C = 8, %d threads:\n", inlight::parallel::thread_count());
    if (s.whole.cpu_s >= 0)
        std::printf("  whole BTF (81 groups generated, fitted, freed): %.1f CPU s (generating the images %.1f, fitting %.1f), "
                    "%.1f s wall, %s, peak RSS %.0f MiB, RMSE %.6g\n"
                    "    goal <= 60 CPU s (under a minute on 2 free cores): %s\n",
                    s.whole.cpu_s, s.whole_read_cpu_s, s.whole_fit_cpu_s, s.whole.wall_s, loads(s.whole).c_str(),
                    s.whole_peak_mib, s.whole.rmse, s.whole.cpu_s <= 60 ? "met" : "NOT met");
    if (s.gram.cpu_s > 0 && s.full_svd.cpu_s > 0)
        std::printf("  one group: Gram %.3f CPU s (%.2f s wall), full SVD %.2f CPU s (%.2f s wall): %.1fx in CPU time, "
                    "%.1fx in wall time; RMSE %.6g and %.6g (relative difference %.1e), %s\n"
                    "    goal >= 10x the full SVD at equal error (RMSE within 1e-4 relative): %s\n",
                    s.gram.cpu_s, s.gram.wall_s, s.full_svd.cpu_s, s.full_svd.wall_s, s.full_svd.cpu_s / s.gram.cpu_s,
                    s.full_svd.wall_s / s.gram.wall_s, s.gram.rmse, s.full_svd.rmse,
                    std::abs(s.gram.rmse - s.full_svd.rmse) / s.full_svd.rmse, loads(s.gram).c_str(),
                    s.full_svd.cpu_s >= 10 * s.gram.cpu_s && std::abs(s.gram.rmse - s.full_svd.rmse) <= 1e-4 * s.full_svd.rmse
                        ? "met" : "NOT met");
}

}  // namespace

namespace {

/// `btf_bench --write-ubo2003 DIR [--side-px N] [--directions N] [--rank R] [--scale S] [--check]`:
/// writes the benchmark's BTF (by default the analytic BTF of rank 6 at scale 4, 81 x 81
/// directions, 256 x 256 px: the data of the figures above, clipped at 1) as a UBO2003 folder
/// of 8-bit sRGB PNGs, one folder per view as Bonn ships, for btf-pca to decode end to end.
/// --directions N < 81 takes every (81/N)-th dome direction (evenly strided indices) for lights
/// and views alike and writes them to DIR.directions.txt (btf-pca's --light-directions and
/// --view-directions). --check reads every image back as btf-pca does (sRGB-decoded) and reports
/// the RMS and largest difference from the analytic values, the 8-bit quantisation the folder
/// adds, and the largest analytic value before clipping: at scale 1 (values below 0.95) nothing
/// clips, so the BTF matrix has rank <= R and a model of C >= R components is exact up to that
/// quantisation (Eckart-Young). Prints one JSON line. DIR must not exist (nothing is overwritten).
/// Exit 2 on a bad option (named), 1 on a runtime error.
int write_ubo2003_main(int argc, char** argv) {
    auto usage = [&](const std::string& why) {
        std::fprintf(stderr, "btf_bench --write-ubo2003: %s\nusage: %s --write-ubo2003 DIR [--side-px N] "
                     "[--directions N] [--rank R] [--scale S] [--check]\n", why.c_str(), argv[0]);
        return 2;
    };
    if (argc < 3 || argv[2][0] == '-') return usage("DIR missing");
    std::string dir = argv[2];
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    AnalyticBtfOptions o = bench_options();
    int directions = 81;
    bool check = false;
    for (int i = 3; i < argc; ++i) {
        const std::string opt = argv[i];
        if (opt == "--check") {
            check = true;
            continue;
        }
        if (i + 1 >= argc) return usage(opt + ": value missing");
        const char* text = argv[++i];
        char* end = nullptr;
        const double x = std::strtod(text, &end);
        const bool whole = *end == '\0' && std::isfinite(x) && x == std::floor(x);
        if (opt == "--side-px" && whole && x >= 1 && x <= 16384) o.width = o.height = int(x);
        else if (opt == "--directions" && whole && x >= 1 && x <= 81) directions = int(x);
        else if (opt == "--rank" && whole && x >= 1 && x <= 6) o.rank = int(x);
        else if (opt == "--scale" && *end == '\0' && std::isfinite(x) && x > 0) o.scale = x;
        else if (opt == "--side-px" || opt == "--directions" || opt == "--rank" || opt == "--scale")
            return usage(opt + " " + text + ": out of range (side 1..16384, directions 1..81, rank 1..6, scale > 0)");
        else return usage(opt + ": unknown option");
    }
    try {
        namespace stdfs = std::filesystem;
        if (stdfs::exists(dir)) throw inlight::Error(dir + ": exists; the generator writes a new folder only");
        std::string directions_file;
        if (directions < 81) {
            const auto& dome = ubo2003_dome();
            std::vector<Direction> subset;
            for (int i = 0; i < directions; ++i) subset.push_back(dome[size_t(i * 81 / directions)]);
            o.lights = o.views = subset;
            directions_file = dir + ".directions.txt";
            std::ofstream f(directions_file);
            f << "# " << directions << " of the 81 UBO2003 dome directions, evenly strided (btf_bench --write-ubo2003)\n";
            for (const Direction& d : subset) f << d.theta_deg << " " << d.phi_deg << "\n";
            if (!f.flush()) throw inlight::Error(directions_file + ": cannot write");
        }
        const ClippedBtf btf(o);
        const std::clock_t c0 = std::clock();
        const auto t0 = std::chrono::steady_clock::now();
        write_ubo2003(btf, dir);
        const double write_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double write_cpu_s = double(std::clock() - c0) / CLOCKS_PER_SEC;
        uint64_t bytes = 0;
        int64_t files = 0;
        for (const auto& e : stdfs::recursive_directory_iterator(dir))
            if (e.is_regular_file()) bytes += e.file_size(), ++files;
        std::printf("{\"dir\": \"%s\", \"images\": %lld, \"side_px\": %d, \"directions\": %d, \"rank\": %d, "
                    "\"scale\": %.17g, \"directions_file\": \"%s\", \"stored_bytes\": %llu, \"write_s\": %.3f, "
                    "\"write_cpu_s\": %.3f, \"threads\": %d",
                    dir.c_str(), static_cast<long long>(files), o.width, directions, o.rank, o.scale,
                    directions_file.c_str(), static_cast<unsigned long long>(bytes), write_s, write_cpu_s,
                    inlight::parallel::thread_count());
        if (check) {
            OpenOptions oo;
            oo.light_directions = oo.view_directions = directions_file;
            const std::unique_ptr<FolderBtf> files_btf = FolderBtf::open(dir, oo);
            const int n_lights = btf.shape().n_lights();
            // Per image: squared differences, largest difference, largest unclipped value, clipped samples.
            using Sums = std::array<double, 4>;
            const Sums s = inlight::parallel::reduce(
                int64_t(n_lights) * btf.shape().n_views(), 1, Sums{0, 0, 0, 0},
                [&](int64_t b, int64_t e) {
                    Sums x{0, 0, 0, 0};
                    for (int64_t i = b; i < e; ++i) {
                        const int l = int(i % n_lights), v = int(i / n_lights);
                        const inlight::image::Image got = files_btf->read_image(l, v), raw = btf.unclipped().read_image(l, v);
                        for (size_t k = 0; k < got.pixels.size(); ++k) {
                            const double d = double(got.pixels[k]) - std::min(raw.pixels[k], 1.0f);
                            x[0] += d * d;
                            x[1] = std::max(x[1], std::abs(d));
                            x[2] = std::max(x[2], double(raw.pixels[k]));
                            x[3] += raw.pixels[k] > 1.0f;
                        }
                    }
                    return x;
                },
                [](Sums a, const Sums& b) { return Sums{a[0] + b[0], std::max(a[1], b[1]), std::max(a[2], b[2]), a[3] + b[3]}; });
            std::printf(", \"check\": {\"rmse_linear\": %.17g, \"max_abs_linear\": %.17g, \"max_value_unclipped\": %.17g, "
                        "\"clipped_samples\": %.0f, \"samples\": %.0f}",
                        std::sqrt(s[0] / btf.shape().sample_count()), s[1], s[2], s[3], btf.shape().sample_count());
        }
        std::printf("}\n");
    } catch (const std::exception& e) {  // inlight::Error, and std::filesystem's errors
        std::fprintf(stderr, "btf_bench --write-ubo2003: %s\n", e.what());
        return 1;
    }
    return 0;
}

/// `btf_bench --decode-floor PATH [--threads N]`: the floor a btf-pca run is timed against
/// (docs/benchmarks.md): every image of a BTF folder or zip file read and decoded to its
/// stored codes by the decoder btf-pca uses (OpenImageIO's, from the bytes in memory), on N
/// threads (0 = all cores), and nothing else: no conversion to float, no sRGB decode, no
/// copy into groups. Images are the files whose extension is png, jpg, jpeg or exr, as in a
/// BTF folder.
/// Prints one JSON line: images, samples, bytes read, wall and CPU seconds. Exit 2 on a bad
/// option (named), 1 on a runtime error (a file that does not decode, named).
int decode_floor_main(int argc, char** argv) {
    auto usage = [&](const std::string& why) {
        std::fprintf(stderr, "btf_bench --decode-floor: %s\nusage: %s --decode-floor PATH [--threads N]\n", why.c_str(),
                     argv[0]);
        return 2;
    };
    if (argc < 3 || argv[2][0] == '-') return usage("PATH missing");
    const std::string path = argv[2];
    int threads = 0;
    for (int i = 3; i < argc; ++i) {
        const std::string opt = argv[i];
        if (opt != "--threads") return usage(opt + ": unknown option");
        if (i + 1 >= argc) return usage(opt + ": value missing");
        char* end = nullptr;
        const long n = std::strtol(argv[++i], &end, 10);
        if (*end != '\0' || end == argv[i] || n < 0 || n > 1024) return usage(opt + " " + argv[i] + ": not a count in 0..1024");
        threads = int(n);
    }
    namespace stdfs = std::filesystem;
    try {
        if (!stdfs::exists(path)) throw inlight::Error(path + ": no such file or folder");
        auto is_image = [](const std::string& name) {  // the extensions a BTF folder's images have
            const std::string ext = inlight::fs::extension(name);
            return ext == "png" || ext == "jpg" || ext == "jpeg" || ext == "exr";
        };
        std::unique_ptr<ZipArchive> zip;
        std::vector<const ArchiveEntry*> entries;
        std::vector<std::string> files;
        if (is_zip_path(path)) {
            zip = ZipArchive::open(path);
            for (const ArchiveEntry& e : zip->entries())
                if (!e.is_directory && is_image(e.name)) entries.push_back(&e);
        } else {
            for (const auto& e : stdfs::recursive_directory_iterator(path))
                if (e.is_regular_file() && is_image(e.path().filename().string())) files.push_back(e.path().string());
            std::sort(files.begin(), files.end());
        }
        const int64_t n = zip ? int64_t(entries.size()) : int64_t(files.size());
        if (n == 0) throw inlight::Error(path + ": no images (png, jpg, jpeg, exr)");
        inlight::parallel::set_thread_count(threads);
        OIIO::attribute("threads", inlight::parallel::thread_count());
        OIIO::attribute("exr_threads", inlight::parallel::thread_count());
        const std::clock_t c0 = std::clock();
        const auto t0 = std::chrono::steady_clock::now();
        using Sums = std::array<double, 2>;  // samples, bytes read
        const Sums sums = inlight::parallel::reduce(
            n, 1, Sums{0, 0},
            [&](int64_t b, int64_t e) {
                Sums x{0, 0};
                std::vector<unsigned char> codes;
                for (int64_t i = b; i < e; ++i) {
                    std::string name, bytes;
                    if (zip) {
                        name = entries[size_t(i)]->name;
                        bytes = zip->read(*entries[size_t(i)]);
                    } else {
                        name = files[size_t(i)];
                        std::ifstream f(name, std::ios::binary);
                        bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
                        if (!f.good() && !f.eof()) throw inlight::Error(name + ": cannot read");
                    }
                    OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
                    OIIO::ImageSpec config, spec;
                    void* proxy = &memory;
                    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
                    auto in = OIIO::ImageInput::create(inlight::fs::extension(name));  // that reader only, as btf-pca
                    if (!in || !in->open(name, spec, config))
                        throw inlight::Error(path + ": " + name + ": cannot open: " + (in ? in->geterror() : OIIO::geterror()));
                    codes.resize(spec.image_bytes(true));
                    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeUnknown, codes.data()))
                        throw inlight::Error(path + ": " + name + ": cannot decode: " + in->geterror());
                    x[0] += double(spec.image_pixels()) * spec.nchannels;
                    x[1] += double(bytes.size());
                }
                return x;
            },
            [](Sums a, const Sums& b) { return Sums{a[0] + b[0], a[1] + b[1]}; });
        const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double cpu_s = double(std::clock() - c0) / CLOCKS_PER_SEC;
        std::printf("{\"path\": \"%s\", \"images\": %lld, \"samples\": %.0f, \"bytes_read\": %.0f, \"decode_s\": %.3f, "
                    "\"decode_cpu_s\": %.3f, \"threads\": %d}\n",
                    path.c_str(), static_cast<long long>(n), sums[0], sums[1], wall_s, cpu_s,
                    inlight::parallel::thread_count());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "btf_bench --decode-floor: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "--write-ubo2003") == 0) return write_ubo2003_main(argc, argv);
    if (argc >= 2 && std::strcmp(argv[1], "--decode-floor") == 0) return decode_floor_main(argc, argv);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    print_summary();
    return 0;
}
