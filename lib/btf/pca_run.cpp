#include "btf/pca_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numeric>

#include "btf/quantize.h"
#include "core/check.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/json_in.h"
#include "core/json_out.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "image/color.h"

namespace inlight::btf {
namespace {

namespace stdfs = std::filesystem;
using Clock = std::chrono::steady_clock;

int64_t rows_per_block(int64_t cols) { return std::clamp<int64_t>((int64_t(1) << 20) / std::max<int64_t>(cols, 1), 16, 2048); }

/// Sum of f(double(x[i])) in four interleaved partial sums (vectorised; the order is fixed).
template <typename F>
inline __attribute__((always_inline)) double lane_sum(const float* x, int64_t n, F f) {
    double lane[4] = {0, 0, 0, 0};
    int64_t i = 0;
    for (; i + 4 <= n; i += 4)
        for (int k = 0; k < 4; ++k) lane[k] += f(double(x[i + k]));
    double sum = (lane[0] + lane[1]) + (lane[2] + lane[3]);
    for (; i < n; ++i) sum += f(double(x[i]));
    return sum;
}

/// The exact errors of one column's rows after 0..C components of the stored model: `err` (n
/// floats) starts as the centred column x plus the mean's quantisation dm and loses one
/// component (basis[c] x w[c * ldw]) at a time. Adds its energy after c components to s[c],
/// the last residual's absolute sum to s[C + 1], and keeps its largest magnitude in `worst`.
/// An AVX2 clone where the CPU has it (no fused multiply-add, and the sums' lanes fixed: the
/// same bits).
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target_clones("avx2", "default")))
#endif
void residual_energies(const float* x, const float* dm, int64_t n, const float* const* basis, const float* w, int64_t ldw,
                       int C, float* err, double* s, float& worst) {
    const auto square = [](double v) { return v * v; };
    for (int64_t p = 0; p < n; ++p) err[p] = x[p] + dm[p];
    s[0] += lane_sum(err, n, square);
    for (int c = 0; c < C; ++c) {
        const float wc = w[c * ldw];
        const float* b = basis[c];
        for (int64_t p = 0; p < n; ++p) err[p] -= b[p] * wc;
        s[c + 1] += lane_sum(err, n, square);
    }
    s[C + 1] += lane_sum(err, n, [](double v) { return std::fabs(v); });
    for (int64_t p = 0; p < n; ++p) worst = std::max(worst, std::fabs(err[p]));
}

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Display-referred colour errors summed over sampled triples.
struct ColorSums {
    double lab_abs = 0, delta_e2000 = 0, code_abs = 0, code_sq = 0;
    int64_t triples = 0;
    ColorSums& operator+=(const ColorSums& o) {
        lab_abs += o.lab_abs, delta_e2000 += o.delta_e2000, code_abs += o.code_abs, code_sq += o.code_sq;
        triples += o.triples;
        return *this;
    }
    nlohmann::json to_json() const {
        const double n = std::max<int64_t>(triples, 1);
        return {{"mae_lab", lab_abs / (3 * n)}, {"delta_e2000_mean", delta_e2000 / n},
                {"mae_rgb8", code_abs / (3 * n)}, {"rmse_rgb8", std::sqrt(code_sq / (3 * n))},
                {"color_triples", triples}};
    }
};

/// A reference colour's display-referred values, computed once for every model it is compared
/// with: clamped to [0, 1], its CIELAB and its sRGB encoding.
struct TruthColor {
    explicit TruthColor(const Eigen::Vector3d& truth) {
        const Eigen::Vector3d t = truth.cwiseMax(0.0).cwiseMin(1.0);
        lab = image::lab_from_linear_srgb(t);
        for (int c = 0; c < 3; ++c) encoded[c] = image::srgb_encode(float(t[c]));
    }
    Eigen::Vector3d lab;
    float encoded[3];
};

void add_color(ColorSums& s, const TruthColor& truth, Eigen::Vector3d test) {
    test = test.cwiseMax(0.0).cwiseMin(1.0);
    const Eigen::Vector3d lab = image::lab_from_linear_srgb(test);
    s.lab_abs += (lab - truth.lab).cwiseAbs().sum();
    s.delta_e2000 += image::delta_e2000(truth.lab, lab);
    for (int c = 0; c < 3; ++c) {
        const double d = 255.0 * (image::srgb_encode(float(test[c])) - truth.encoded[c]);
        s.code_abs += std::abs(d);
        s.code_sq += d * d;
    }
    ++s.triples;
}

/// The linear colour of a triple of the model's space: clamped to [0, 1] (what a display shows)
/// and, for an sRGB-encoded model, decoded (decode is monotone with fixed points 0 and 1, so the
/// clamp means the same as add_color's clamp of linear values).
Eigen::Vector3d to_linear(Eigen::Vector3d v, FitSpace space) {
    if (space == FitSpace::kSrgb)
        for (int c = 0; c < 3; ++c) v[c] = image::srgb_decode(float(std::clamp(v[c], 0.0, 1.0)));
    if (space == FitSpace::kLab) v = image::linear_srgb_from_lab(v);
    return v;
}

/// A BTF's images in the fit space (sRGB-encoded for FitSpace::kSrgb, CIELAB for kLab): the
/// values the PCA then fits.
class FitSpaceSource : public BtfSource {
  public:
    FitSpaceSource(const BtfSource& linear, FitSpace space) : m_linear(linear), m_space(space) {}
    const BtfShape& shape() const override { return m_linear.shape(); }
    image::Image read_image(int light, int view) const override {
        image::Image img = m_linear.read_image(light, view);
        if (m_space == FitSpace::kSrgb)
            for (float& x : img.pixels) x = image::srgb_encode(x);
        if (m_space == FitSpace::kLab)
            for (size_t i = 0; i + 2 < img.pixels.size(); i += 3) {
                const Eigen::Vector3d lab =
                    image::lab_from_linear_srgb(Eigen::Vector3d(img.pixels[i], img.pixels[i + 1], img.pixels[i + 2]));
                for (int c = 0; c < 3; ++c) img.pixels[i + size_t(c)] = static_cast<float>(lab[c]);
            }
        return img;
    }

  private:
    const BtfSource& m_linear;
    FitSpace m_space;
};

/// What the run keeps of each group after freeing its data.
struct GroupRecord {
    std::vector<int> views;
    int64_t columns = 0;
    /// Display-referred errors of the stored model cut to 0..C components on the group's
    /// sampled triples, against the input and (with a reference) against the reference.
    std::vector<ColorSums> color, color_ref;
    std::string method;
    std::vector<double> sse;     // stored model, after 0..C components
    std::vector<double> energy;  // unquantised energy of each component
    std::vector<uint64_t> component_bytes;
    std::vector<uint64_t> v_bytes;  // each component's V column in weights.bin
    uint64_t mean_bytes = 0;
    double sae = 0, max_abs = 0;
    nlohmann::json manifest;
};

/// btf-pca.json on one line: the app downloads it, and at 64 x 64 px the indented text was
/// 13% of a k = 3, C = 8 folder (compact: 31% fewer bytes). `jq .` shows it indented.
constexpr int kManifestIndent = -1;

std::string group_file(int g, int c, const std::string& ext) {
    char buf[64];
    if (c < 0) std::snprintf(buf, sizeof buf, "g%03d-mean.%s", g, ext.c_str());
    else std::snprintf(buf, sizeof buf, "g%03d-c%02d.%s", g, c, ext.c_str());
    return buf;
}

/// Which fit a run uses: every group in core, or groups larger than `stream_views` views out of
/// core, and the estimates that chose it.
struct MemoryPlan {
    uint64_t budget = 0;
    std::string budget_source;
    int stream_views = 0;          ///< 0: in core
    uint64_t in_core_bytes = 0;    ///< estimate for the largest group held whole
    uint64_t planned_bytes = 0;    ///< estimate for the plan chosen
};

/// Estimate for one group of `views` views held `block` views at a time (block >= views: whole).
uint64_t group_memory_bytes(const BtfShape& shape, const PcaRunOptions& o, bool reference, int views, int block) {
    const int64_t P = shape.pixel_count(), per_view = shape.group_columns(1);
    const int64_t N = per_view * views, held = per_view * std::min(views, block);
    const uint64_t C = uint64_t(std::min<int64_t>(o.pca.components, std::min(P, N)));
    const uint64_t workers = uint64_t(std::max(parallel::thread_count(), 1));
    uint64_t bytes = fit_memory_bytes(P, N, block >= views ? N : held, o.pca, parallel::thread_count());
    bytes += 2 * 4 * uint64_t(P + P * C + N * C) + uint64_t(P) * C;           // stored and thesis copies, codes
    bytes += workers * 4 * uint64_t(rows_per_block(held)) * uint64_t(held);  // error blocks
    if (reference) bytes += 4 * uint64_t(P) * uint64_t(held);
    return bytes;
}

MemoryPlan plan_memory(const BtfShape& shape, const PcaRunOptions& o, bool reference) {
    MemoryPlan m;
    m.budget = o.max_memory_bytes;
    m.budget_source = "--max-memory-mib";
    if (m.budget == 0) {
        m.budget = physical_memory_bytes() / 2;
        m.budget_source = "half of the physical memory";
        if (m.budget == 0) m.budget = std::numeric_limits<uint64_t>::max(), m.budget_source = "none (memory size unknown)";
    }
    int largest = 0;
    for (const auto& g : view_groups(shape.views, o.pca.view_group_size, o.pca.grouping)) largest = std::max(largest, int(g.size()));
    m.in_core_bytes = group_memory_bytes(shape, o, reference, largest, largest);
    auto mib = [](uint64_t b) { return str(std::ceil(double(b) / 1048576.0)); };
    if (o.pca.stream_views > 0) {
        m.stream_views = o.pca.stream_views >= largest ? 0 : o.pca.stream_views;
        m.planned_bytes = group_memory_bytes(shape, o, reference, largest, o.pca.stream_views);
        if (m.planned_bytes > m.budget)
            throw UsageError(str("--stream-views ", o.pca.stream_views, ": needs about ", mib(m.planned_bytes),
                                 " MiB per group, above the memory budget of ", mib(m.budget), " MiB (", m.budget_source, ")"));
        return m;
    }
    m.planned_bytes = m.in_core_bytes;
    if (m.in_core_bytes <= m.budget) return m;
    for (int b = largest - 1; b >= 1; --b) {
        m.planned_bytes = group_memory_bytes(shape, o, reference, largest, b);
        if (m.planned_bytes <= m.budget) {
            m.stream_views = b;
            return m;
        }
    }
    throw UsageError(str("--max-memory-mib: a group of ", largest, " views needs about ", mib(m.in_core_bytes),
                         " MiB in core and ", mib(group_memory_bytes(shape, o, reference, largest, 1)),
                         " MiB out of core at one view per block, above the budget of ", mib(m.budget), " MiB (",
                         m.budget_source, ")"));
}

/// The bytes of the manifest a run keeping per_group[g] components of group g writes: the full
/// manifest with each group's later components and their stream entries dropped and the weights
/// offsets recomputed (the same text, the fit being the same).
uint64_t cut_manifest_bytes(const nlohmann::json& full, const std::vector<int>& per_group,
                            const std::vector<GroupRecord>& groups) {
    nlohmann::json m = full;
    uint64_t offset = 0;
    for (size_t g = 0; g < groups.size(); ++g) {
        nlohmann::json& gj = m["groups"][g];
        nlohmann::json& comps = gj["components"];
        comps.erase(comps.begin() + per_group[g], comps.end());
        gj["weights_offset_bytes"] = offset;
        for (int c = 0; c < per_group[g]; ++c) offset += groups[g].v_bytes[size_t(c)];
    }
    nlohmann::json stream = nlohmann::json::array();
    for (const auto& e : m["stream"])
        if (e[1].get<int>() < per_group[e[0].get<size_t>()]) stream.push_back(e);
    m["stream"] = stream;
    return m.dump(kManifestIndent).size() + 1;
}

}  // namespace

std::string to_string(Codec c) { return c == Codec::kThesis ? "thesis" : "inlight"; }

Codec codec_from_string(const std::string& name) {
    if (name == "inlight") return Codec::kInlight;
    if (name == "thesis") return Codec::kThesis;
    throw UsageError(str("--codec '", name, "': expected inlight or thesis"));
}

namespace {

/// Codec::kThesis fixes the options its method has; anything else is named.
void check_thesis_options(const PcaRunOptions& o) {
    auto need = [](bool ok, const std::string& what) {
        if (!ok) throw UsageError(str("--codec thesis: ", what));
    };
    need(o.fit_space == FitSpace::kSrgb, str("the thesis' PCA fits the 8-bit sRGB values (--fit-space srgb), not --fit-space ",
                                             to_string(o.fit_space)));
    need(o.pca.l1_iterations == 0, "the thesis' fit is the PCA (--fit-norm l2), not --fit-norm l1");
    need(o.pca.grouping == ViewGrouping::kConsecutive, "the thesis groups k consecutive views");
    need(o.weights_format == WeightsFormat::kUint8,
         str("the thesis stores V on 8 bits (--weights-format uint8), not --weights-format ", to_string(o.weights_format)));
    need(o.encoding == ComponentEncoding::kPng8, str("the thesis stores 8-bit PNG (--format png), not --format ", to_string(o.encoding)));
    need(o.quant_noise == 0, str("the thesis maps every component to 256 levels (--quant-noise 0), not --quant-noise ", o.quant_noise));
    need(o.pca.max_rmse < 0, str("the thesis keeps C components per group (no --max-rmse), not --max-rmse ", o.pca.max_rmse));
}

}  // namespace

nlohmann::json compress_to_folder(const BtfSource& source, const PcaRunOptions& o,
                                  uint64_t input_stored_bytes, Report* report, const BtfSource* reference) {
    const auto t_start = Clock::now();
    const bool thesis_codec = o.codec == Codec::kThesis;
    if (thesis_codec) check_thesis_options(o);
    const uint64_t rss_before = current_rss_bytes();
    const BtfShape& shape = source.shape();
    if (reference) {
        const BtfShape& r = reference->shape();
        auto same = [](const std::vector<Direction>& a, const std::vector<Direction>& b) {
            if (a.size() != b.size()) return false;
            for (size_t i = 0; i < a.size(); ++i)
                if (a[i].theta_deg != b[i].theta_deg || a[i].phi_deg != b[i].phi_deg) return false;
            return true;
        };
        if (r.width != shape.width || r.height != shape.height || !same(r.lights, shape.lights) || !same(r.views, shape.views))
            throw Error(str("--reference ", o.reference, ": ", log::count(r.n_lights(), "light"), " x ",
                            log::count(r.n_views(), "view"), " of ", r.width,
                            "x", r.height, " px, the input has ", shape.n_lights(), " x ", shape.n_views(), " of ", shape.width,
                            "x", shape.height, " (or other directions)"));
    }
    const MemoryPlan plan = plan_memory(shape, o, reference != nullptr);
    if (o.pca.l1_iterations > 0 && plan.stream_views > 0)
        throw UsageError(str("--fit-norm l1 refits each group in memory, but a group here is fitted out of core (",
                             plan.stream_views, " views per block, memory budget ", std::ceil(double(plan.budget) / 1048576.0),
                             " MiB from ", plan.budget_source, "): raise --max-memory-mib or use --fit-norm l2"));
    // The values fitted: the images themselves, or in the fit space (sRGB-encoded or CIELAB; the
    // reference too, so that the measurement below sees both in the model's space).
    std::unique_ptr<FitSpaceSource> encoded_source, encoded_reference;
    const BtfSource* src = &source;
    if (o.fit_space != FitSpace::kLinear) {
        encoded_source = std::make_unique<FitSpaceSource>(source, o.fit_space);
        src = encoded_source.get();
        if (reference) {
            encoded_reference = std::make_unique<FitSpaceSource>(*reference, o.fit_space);
            reference = encoded_reference.get();
        }
    }
    const FitSpace space = o.fit_space;
    PcaOptions pca_options = o.pca;
    pca_options.stream_views = plan.stream_views;
    const int64_t P = shape.pixel_count();
    const double samples = shape.sample_count();
    const double total_triples = samples / 3;
    const int64_t stride = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(total_triples / double(std::max<int64_t>(o.color_samples, 1)))));
    const std::string ext = extension_of(o.encoding);
    const std::string dir = o.output;

    std::vector<GroupRecord> groups;
    std::string weights_bin;
    uint64_t weight_values = 0;
    ColorSums ours, thesis, ref_input;
    const std::vector<int>& table = o.table_components;
    std::vector<ColorSums> table_sums(table.size()), table_ref(table.size());
    std::vector<double> table_sse(table.size(), 0.0);
    std::vector<uint64_t> table_bytes(table.size(), 0), table_params(table.size(), 0);
    int sigma_overflows = 0;
    uint64_t thesis_mean_bytes = 0, thesis_u_bytes = 0, thesis_v_bytes = 0;
    double store_s = 0, measure_s = 0;
    int measure_passes = 0;  // passes over the images of out-of-core groups to measure them
    std::map<std::string, int> methods;
    auto write_file = [&](const std::string& name, const std::string& bytes, const std::string& kind) {
        fs::write_text_atomic(dir + "/" + name, bytes);
        if (report) report->add_output(dir + "/" + name, kind, kind == "btf_pca_manifest" ? manifest_color_space(o.fit_space) : "");
    };

    // A bar with an ETA on a terminal, where it stands for the per-group lines (those go to -v);
    // off a terminal (logs, CI) each group still writes its line.
    Progress bar("[btf-pca] fit view groups",
                 static_cast<int64_t>(view_groups(shape.views, o.pca.view_group_size, o.pca.grouping).size()));
    const CompressStats stats = compress_btf(*src, pca_options, [&](GroupFit& fit) {
        const GroupPca& pca = fit.pca;
        const int C = pca.components();
        const int64_t N = pca.columns;
        GroupRecord rec;
        rec.views = pca.views;
        rec.columns = N;
        rec.method = to_string(pca.method);
        ++methods[rec.method];
        auto t0 = Clock::now();
        // Store: mean and components as images, V into weights.bin.
        StoredGroup q;
        q.mean.resize(P);
        q.basis.resize(P, C);
        q.weights.resize(N, C);
        StoredImage meta;
        nlohmann::json gj = {{"views", pca.views}, {"columns", N}, {"method", rec.method},
                             {"weights_offset_bytes", weights_bin.size()}, {"components", nlohmann::json::array()}};
        // The thesis' packing of the same model: what --codec thesis writes, and otherwise the
        // comparison beside ours.
        const ThesisGroup th = pack_thesis(pca, C);
        sigma_overflows += th.sigma_overflows;
        std::string bytes = thesis_codec ? encode_codes(th.mean_codes.data(), shape.width, shape.height, ThesisGroup::kMeanScale,
                                                        0.0f, group_file(fit.index, -1, ext), meta, q.mean.data())
                                         : encode_column(pca.mean.data(), shape.width, shape.height, o.encoding,
                                                         group_file(fit.index, -1, ext), meta, q.mean.data());
        rec.mean_bytes = bytes.size();
        write_file(meta.file, bytes, "btf_pca_mean");
        gj["mean"] = {{"file", meta.file}, {"scale", json_float(meta.scale)}, {"offset", json_float(meta.offset)}, {"bytes", bytes.size()}};
        // PcaRunOptions::quant_noise: rounding `values` values (weighted by their image's
        // squared norm, for V) on a step d adds about values d^2 / 12, so d^2 = 12 F E / values
        // adds F E, E the group's residual energy.
        auto noise_step = [&](double values) {
            return float(std::sqrt(12.0 * o.quant_noise * std::max(pca.residual_energy.back(), 0.0) / values));
        };
        // One quantisation step for the group's components: their C P values.
        const float step = o.quant_noise > 0 && C > 0 ? noise_step(double(C) * double(P)) : 0.0f;
        // The component images are encoded in parallel (each its own file and column of q),
        // then written and recorded in order.
        std::vector<std::string> encoded(static_cast<size_t>(C));
        std::vector<StoredImage> metas(static_cast<size_t>(C));
        parallel::for_chunks(C, 1, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
                const int c = int(i);
                encoded[size_t(c)] =
                    thesis_codec ? encode_codes(th.u_codes[size_t(c)].data(), shape.width, shape.height, th.basis_scale(c),
                                                th.basis_offset(c), group_file(fit.index, c, ext), metas[size_t(c)], q.basis.col(c).data())
                                 : encode_column(pca.basis.col(c).data(), shape.width, shape.height, o.encoding,
                                                 group_file(fit.index, c, ext), metas[size_t(c)], q.basis.col(c).data(), step);
            }
        });
        for (int c = 0; c < C; ++c) {
            bytes = std::move(encoded[size_t(c)]);
            meta = metas[size_t(c)];
            rec.component_bytes.push_back(bytes.size());
            rec.energy.push_back(pca.component_energy(c));
            write_file(meta.file, bytes, "btf_pca_component");
            gj["components"].push_back({{"file", meta.file}, {"scale", json_float(meta.scale)}, {"offset", json_float(meta.offset)},
                                        {"bytes", bytes.size()}, {"energy", json_float(float(pca.component_energy(c)))}});
            float v_scale = ThesisGroup::kWeightScale, v_offset = ThesisGroup::kWeightOffset;
            const size_t v_start = weights_bin.size();
            if (thesis_codec) {
                append_weight_codes(th.v_codes[size_t(c)].data(), N, v_scale, v_offset, weights_bin, q.weights.col(c).data());
            } else {
                // V's step with --quant-noise (entropy-coded V only, where fewer codes cost fewer
                // bytes): rounding V's column by a step d adds about |b|^2 N d^2 / 12 to the
                // error, |b| the norm of the component's image, so d^2 = 12 F E / (C N |b|^2)
                // adds F E over the group's C columns, as the components' step does.
                const double b2 = pca.basis.col(c).cast<double>().squaredNorm();
                const float v_step = o.weights_format == WeightsFormat::kUint8Deflate && o.quant_noise > 0 && b2 > 0
                                         ? noise_step(double(C) * double(N) * b2)
                                         : 0.0f;
                encode_weights_column(pca.weights.col(c).data(), N, o.weights_format, weights_bin, q.weights.col(c).data(),
                                      v_scale, v_offset, v_step);
            }
            rec.v_bytes.push_back(weights_bin.size() - v_start);
            if (is_uint8(o.weights_format)) {
                gj["components"].back()["v_scale"] = json_float(v_scale);
                gj["components"].back()["v_offset"] = json_float(v_offset);
            }
            if (o.weights_format == WeightsFormat::kUint8Deflate) gj["components"].back()["v_bytes"] = rec.v_bytes.back();
        }
        if (thesis_codec)
            gj["thesis"] = {{"factor_u", th.factor_u}, {"factor_v", th.factor_v}, {"sigma_digits", th.sigma_digits}};
        weight_values += uint64_t(N) * uint64_t(C);
        // The bytes of the thesis' own files (a --codec thesis run wrote its mean and U): the
        // mean and each component of U as 8-bit PNG, and V with Sigma in one shared texture: V's
        // codes as a C x N grey PNG, Sigma two decimal digits per 8-bit channel (at least two).
        auto png_bytes = [&](const uint8_t* codes, int w, int h) {
            StoredImage unused;
            std::vector<float> values(static_cast<size_t>(w) * static_cast<size_t>(h));
            return uint64_t(encode_codes(codes, w, h, 1.0f, 0.0f, "t.png", unused, values.data()).size());
        };
        thesis_mean_bytes += thesis_codec ? rec.mean_bytes : png_bytes(th.mean_codes.data(), shape.width, shape.height);
        if (thesis_codec) {
            for (int c = 0; c < C; ++c) thesis_u_bytes += rec.component_bytes[size_t(c)];
        } else {
            std::vector<uint64_t> u_bytes(static_cast<size_t>(C));
            parallel::for_chunks(C, 1, [&](int64_t b, int64_t e) {
                for (int64_t c = b; c < e; ++c) u_bytes[size_t(c)] = png_bytes(th.u_codes[size_t(c)].data(), shape.width, shape.height);
            });
            for (uint64_t x : u_bytes) thesis_u_bytes += x;
        }
        if (C > 0) {
            std::vector<uint8_t> v_image;
            for (const auto& col : th.v_codes) v_image.insert(v_image.end(), col.begin(), col.end());
            thesis_v_bytes += png_bytes(v_image.data(), int(N), C);
        }
        for (int64_t d : th.sigma_digits) thesis_v_bytes += std::max<uint64_t>(2, (std::to_string(d).size() + 1) / 2);
        const StoredGroup thd = th.decoded();
        store_s += seconds_since(t0);

        // Errors of the stored model, one block of the group's columns at a time: the whole
        // centred group when it is in memory, else each block of `stream_views` views read again
        // and centred as fit_group_streamed centres it (the same floats).
        t0 = Clock::now();
        const Eigen::VectorXf dmean = pca.mean - q.mean;
        const size_t n_sums = 2 + size_t(C + 1) * (reference ? 2 : 1);
        std::vector<double> sums(size_t(C) + 3, 0.0);
        // Sums: [0] the thesis' packing, [1] the input against the reference, [2 + c] ours cut to
        // c = 0..C components; with a reference: [3 + C + c] ours cut to c against it.
        using Sums = std::vector<ColorSums>;
        Sums cs(n_sums);
        // `blk`: the centred columns [j0, j0 + blk.cols()) of the group; `ref`: the reference's.
        auto measure = [&](int64_t j0, const Eigen::MatrixXf& blk, const Eigen::MatrixXf& ref) {
            const int64_t nb = blk.cols();
            // Exact errors after 0..C components, row block by row block.
            const std::vector<double> s_blk = parallel::reduce(
                P, rows_per_block(nb), std::vector<double>(size_t(C) + 3, 0.0),
                [&](int64_t b, int64_t e) {
                    // Column by column: the residual of one column's rows [b, e) stays in L1
                    // while the components are taken off it one by one (the whole block, 4 MiB,
                    // went through memory twice per component).
                    std::vector<double> s(size_t(C) + 3, 0.0);
                    const int64_t n = e - b;
                    std::vector<float> err(static_cast<size_t>(n));
                    std::vector<const float*> basis(static_cast<size_t>(C));
                    for (int c = 0; c < C; ++c) basis[size_t(c)] = q.basis.col(c).data() + b;
                    float worst = 0;
                    for (int64_t j = 0; j < nb; ++j)
                        residual_energies(blk.col(j).data() + b, dmean.data() + b, n, basis.data(), q.weights.data() + j0 + j,
                                          q.weights.rows(), C, err.data(), s.data(), worst);
                    s[size_t(C) + 2] = double(worst);
                    return s;
                },
                [](std::vector<double> a, const std::vector<double>& b) {
                    for (size_t i = 0; i + 1 < a.size(); ++i) a[i] += b[i];
                    a.back() = std::max(a.back(), b.back());
                    return a;
                });
            for (size_t i = 0; i + 1 < sums.size(); ++i) sums[i] += s_blk[i];
            sums.back() = std::max(sums.back(), s_blk.back());

            // Display-referred errors on the strided triples (t = k stride over the group's
            // pixels x colour columns) that fall in this block, ours and the thesis' packing.
            const int64_t t_begin = P * (j0 / 3), t_end = P * ((j0 + nb) / 3);
            const int64_t k_begin = (t_begin + stride - 1) / stride, k_end = (t_end + stride - 1) / stride;
            const Sums cs_blk = parallel::reduce(
                k_end - k_begin, 4096, Sums(n_sums),
                [&](int64_t b, int64_t e) {
                    Sums s(n_sums);
                    for (int64_t k = k_begin + b; k < k_begin + e; ++k) {
                        const int64_t t = k * stride, p = t % P, j = (t / P) * 3, jb = j - j0;
                        Eigen::Vector3d truth, th3;  // the model's space
                        Eigen::Matrix<double, 3, Eigen::Dynamic> prefix(3, C + 1);  // after 0..C components
                        for (int ch = 0; ch < 3; ++ch) {
                            truth[ch] = double(blk(p, jb + ch)) + pca.mean[p];
                            prefix(ch, 0) = q.mean[p];
                            for (int c = 0; c < C; ++c)
                                prefix(ch, c + 1) = prefix(ch, c) + double(q.basis(p, c)) * q.weights(j + ch, c);
                            th3[ch] = thd.mean[p] + double(thd.basis.row(p).dot(thd.weights.row(j + ch)));
                        }
                        const Eigen::Vector3d truth_lin = to_linear(truth, space);
                        const TruthColor truth_color(truth_lin);
                        add_color(s[0], truth_color, to_linear(th3, space));
                        for (int c = 0; c <= C; ++c) add_color(s[2 + size_t(c)], truth_color, to_linear(prefix.col(c), space));
                        if (reference) {
                            const Eigen::Vector3d r3 =
                                to_linear(Eigen::Vector3d(ref(p, jb), ref(p, jb + 1), ref(p, jb + 2)), space);
                            const TruthColor ref_color(r3);
                            add_color(s[1], ref_color, truth_lin);
                            for (int c = 0; c <= C; ++c)
                                add_color(s[3 + size_t(C + c)], ref_color, to_linear(prefix.col(c), space));
                        }
                    }
                    return s;
                },
                [](Sums x, const Sums& y) {
                    for (size_t i = 0; i < x.size(); ++i) x[i] += y[i];
                    return x;
                });
            for (size_t i = 0; i < cs.size(); ++i) cs[i] += cs_blk[i];
        };
        Eigen::MatrixXf ref;
        if (fit.centred.size() > 0) {
            if (reference) reference->read_group(pca.views, ref);
            measure(0, fit.centred, ref);
        } else {
            const size_t per = static_cast<size_t>(plan.stream_views);
            const int64_t cols_per_view = shape.group_columns(1);
            Eigen::MatrixXf blk;
            for (size_t v0 = 0; v0 < pca.views.size(); v0 += per) {
                const std::vector<int> part(pca.views.begin() + std::ptrdiff_t(v0),
                                            pca.views.begin() + std::ptrdiff_t(std::min(pca.views.size(), v0 + per)));
                src->read_group(part, blk);
                parallel::for_chunks(P, rows_per_block(blk.cols()), [&](int64_t b, int64_t e) {
                    for (int64_t j = 0; j < blk.cols(); ++j) blk.col(j).segment(b, e - b) -= pca.mean.segment(b, e - b);
                });
                if (reference) reference->read_group(part, ref);
                measure(int64_t(v0) * cols_per_view, blk, ref);
            }
            ++measure_passes;
        }
        rec.sse.assign(sums.begin(), sums.begin() + C + 1);
        rec.sae = sums[size_t(C) + 1];
        rec.max_abs = sums[size_t(C) + 2];
        rec.color.assign(cs.begin() + 2, cs.begin() + 3 + C);
        if (reference) rec.color_ref.assign(cs.begin() + 3 + C, cs.end());
        ours += rec.color[size_t(C)];
        thesis += cs[0];
        if (reference) ref_input += cs[1];
        for (size_t i = 0; i < table.size(); ++i) {
            const int c = std::min(table[i], C);
            table_sums[i] += rec.color[size_t(c)];
            if (reference) table_ref[i] += rec.color_ref[size_t(c)];
            table_sse[i] += rec.sse[size_t(c)];
            table_bytes[i] += rec.mean_bytes;
            for (int x = 0; x < c; ++x) table_bytes[i] += rec.component_bytes[size_t(x)] + rec.v_bytes[size_t(x)];
            table_params[i] += uint64_t(4) * (uint64_t(P) * (c + 1) + uint64_t(N) * c);
        }
        measure_s += seconds_since(t0);
        rec.manifest = std::move(gj);
        groups.push_back(std::move(rec));
        const std::string line = str("[btf-pca] group ", fit.index + 1, "/", fit.count, ": ",
                                     log::count(C, "component"), " (", to_string(pca.method), "), rmse ",
                                     std::sqrt(groups.back().sse.back() / (double(P) * N)));
        if (bar.drawing()) log::verbose(line);
        else log::info(line);
        bar.add();
    });

    // Stream order: components by the energy they remove, largest first, across groups.
    std::vector<std::pair<int, int>> stream;
    for (size_t g = 0; g < groups.size(); ++g)
        for (size_t c = 0; c < groups[g].energy.size(); ++c) stream.emplace_back(int(g), int(c));
    if (thesis_codec)  // the thesis: component 0 of every group, then component 1, ...
        std::stable_sort(stream.begin(), stream.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
    else
        std::stable_sort(stream.begin(), stream.end(), [&](const auto& x, const auto& y) {
            return groups[size_t(x.first)].energy[size_t(x.second)] > groups[size_t(y.first)].energy[size_t(y.second)];
        });

    nlohmann::json manifest = {{"format", "inlight-btf-pca"}, {"version", 1}, {"width", shape.width},
                               {"height", shape.height}, {"color_space", manifest_color_space(o.fit_space)},
                               {"codec", to_string(o.codec)}, {"view_group_size", o.pca.view_group_size},
                               {"view_grouping", to_string(o.pca.grouping)}, {"component_format", to_string(o.encoding)},
                               {"weights", {{"file", "weights.bin"}, {"dtype", weights_dtype(o.weights_format)}, {"layout", "per group N x C column-major"}}},
                               {"lights", nlohmann::json::array()}, {"views", nlohmann::json::array()},
                               {"groups", nlohmann::json::array()}, {"stream", nlohmann::json::array()}};
    if (o.irradiance_w_m2 > 0) manifest["irradiance_w_m2"] = o.irradiance_w_m2;
    for (const auto& d : shape.lights) manifest["lights"].push_back({d.theta_deg, d.phi_deg});
    for (const auto& d : shape.views) manifest["views"].push_back({d.theta_deg, d.phi_deg});
    for (const auto& g : groups) manifest["groups"].push_back(g.manifest);
    for (const auto& [g, c] : stream) manifest["stream"].push_back({g, c});
    const std::string manifest_text = dump_finite(manifest, kManifestIndent, "btf-pca.json");
    write_file("weights.bin", weights_bin, "btf_pca_weights");
    write_file("btf-pca.json", manifest_text, "btf_pca_manifest");

    // The streaming curve: manifest, weights and means first, then one component at a time.
    uint64_t means = 0, components = 0;
    for (const auto& g : groups) {
        means += g.mean_bytes;
        for (uint64_t b : g.component_bytes) components += b;
    }
    std::vector<size_t> sent(groups.size(), 0);
    double sse = 0;
    for (const auto& g : groups) sse += g.sse[0];
    uint64_t bytes = manifest_text.size() + weights_bin.size() + means;
    nlohmann::json curve = {{"components_sent", {0}}, {"bytes_sent", {bytes}}, {"rmse_linear", {std::sqrt(sse / samples)}}};
    std::string tsv = "# components_sent\tbytes_sent\trmse_linear\n" + str(0, "\t", bytes, "\t", std::sqrt(sse / samples), "\n");
    for (size_t i = 0; i < stream.size(); ++i) {
        const auto [g, c] = stream[i];
        GroupRecord& r = groups[size_t(g)];
        sse += r.sse[size_t(c) + 1] - r.sse[sent[size_t(g)]];
        sent[size_t(g)] = size_t(c) + 1;
        bytes += r.component_bytes[size_t(c)];
        const double rmse = std::sqrt(std::max(sse, 0.0) / samples);
        curve["components_sent"].push_back(i + 1);
        curve["bytes_sent"].push_back(bytes);
        curve["rmse_linear"].push_back(rmse);
        tsv += str(i + 1, "\t", bytes, "\t", rmse, "\n");
    }
    write_file("streaming.tsv", tsv, "btf_pca_streaming_table");
    write_file("streaming.gp",
               "# gnuplot streaming.gp -> streaming.svg: RMSE after each streamed component\n"
               "set terminal svg size 800,480\nset output 'streaming.svg'\n"
               "set xlabel 'bytes sent (KiB)'\nset ylabel 'RMSE (linear sRGB)'\nset logscale y\nset grid\n"
               "plot 'streaming.tsv' using ($2/1024):3 with linespoints pt 7 ps 0.4 title 'btf-pca stream'\n",
               "btf_pca_streaming_plot");

    // Totals.
    double total_sse = 0, total_sae = 0, max_abs = 0, unquantised = stats.residual_energy;
    std::vector<int> per_group;
    for (const auto& g : groups) {
        total_sse += g.sse.back();
        total_sae += g.sae;
        max_abs = std::max(max_abs, g.max_abs);
        per_group.push_back(static_cast<int>(g.energy.size()));
    }
    const uint64_t raw8 = static_cast<uint64_t>(samples);
    const uint64_t params32 = uint64_t(4) * (uint64_t(P) * (stats.components + stats.groups) + weight_values);
    const uint64_t stored = manifest_text.size() + weights_bin.size() + means + components;
    const uint64_t thesis_stored = thesis_mean_bytes + thesis_u_bytes + thesis_v_bytes;
    nlohmann::json m;
    m["btf"] = {{"width", shape.width}, {"height", shape.height}, {"lights", shape.n_lights()},
                {"views", shape.n_views()}, {"samples", samples}};
    m["pca"] = {{"codec", to_string(o.codec)}, {"view_group_size", o.pca.view_group_size},
                {"view_grouping", to_string(o.pca.grouping)}, {"groups", stats.groups},
                {"components_max", o.pca.components}, {"max_rmse", o.pca.max_rmse},
                {"components_total", stats.components}, {"components_per_group", per_group},
                {"methods", methods}, {"component_format", to_string(o.encoding)},
                {"fit_space", to_string(o.fit_space)}, {"fit_norm", o.pca.l1_iterations > 0 ? "l1" : "l2"},
                {"l1_iterations", o.pca.l1_iterations}, {"weights_format", to_string(o.weights_format)},
                {"quant_noise", o.quant_noise}};
    m["time"] = {{"read_s", stats.read_time_s}, {"fit_s", stats.fit_time_s}, {"read_cpu_s", stats.read_cpu_s},
                 {"fit_cpu_s", stats.fit_cpu_s}, {"store_s", store_s},
                 {"measure_s", measure_s}, {"total_s", seconds_since(t_start)}};
    m["peak_rss_bytes"] = stats.peak_rss_bytes;
    m["peak_rss_mib"] = stats.peak_rss_bytes / 1048576.0;
    m["memory"] = {{"fit", plan.stream_views > 0 ? "out-of-core" : "in-core"},
                   {"stream_views", plan.stream_views},
                   {"groups_out_of_core", stats.streamed_groups},
                   {"passes_over_images", stats.stream_passes + measure_passes},
                   {"budget_mib", plan.budget == std::numeric_limits<uint64_t>::max() ? -1.0 : plan.budget / 1048576.0},
                   {"budget_source", plan.budget_source},
                   {"estimate_in_core_mib", plan.in_core_bytes / 1048576.0},
                   {"estimate_mib", plan.planned_bytes / 1048576.0},
                   {"rss_before_mib", rss_before / 1048576.0},
                   {"peak_rss_mib", stats.peak_rss_bytes / 1048576.0}};
    nlohmann::json err = ours.to_json();
    err.update({{"rmse_linear", std::sqrt(total_sse / samples)}, {"mae_linear", total_sae / samples},
                {"max_abs_linear", max_abs}, {"rmse_linear_unquantised", std::sqrt(unquantised / samples)}});
    m["error"] = err;
    // The units of rmse_linear, mae_linear, max_abs_linear and the streaming curve: the model's.
    m["error_space"] = manifest_color_space(o.fit_space);
    m["bytes"] = {{"raw_8bit", raw8}, {"parameters_float32", params32}, {"stored", stored},
                  {"components", components}, {"means", means}, {"weights", weights_bin.size()},
                  {"manifest", manifest_text.size()}, {"input_files", input_stored_bytes}};
    m["compression_ratio"] = {{"raw_8bit_to_parameters_float32", double(raw8) / params32},
                              {"raw_8bit_to_stored", double(raw8) / stored},
                              {"input_files_to_stored", input_stored_bytes ? double(input_stored_bytes) / stored : 0.0}};
    nlohmann::json th = thesis.to_json();
    th.update({{"stored_bytes", thesis_stored}, {"mean_png_bytes", thesis_mean_bytes}, {"u_png_bytes", thesis_u_bytes},
               {"v_sigma_bytes", thesis_v_bytes}, {"sigma_overflows", sigma_overflows}});
    m["thesis_packing"] = th;
    m["packing_gain"] = {
        {"rmse_rgb8_thesis_over_ours", thesis.code_sq > 0 ? std::sqrt(thesis.code_sq / std::max(ours.code_sq, 1e-300)) : 0.0},
        {"mae_lab_thesis_over_ours", ours.lab_abs > 0 ? thesis.lab_abs / ours.lab_abs : 0.0},
        {"stored_bytes_ours_over_thesis", double(stored) / std::max<uint64_t>(thesis_stored, 1)}};
    m["streaming"] = curve;
    nlohmann::json rows = nlohmann::json::array();
    for (size_t i = 0; i < table.size(); ++i) {
        std::vector<int> per;
        for (const auto& g : groups) per.push_back(std::min(table[i], int(g.energy.size())));
        const uint64_t manifest_i = cut_manifest_bytes(manifest, per, groups);
        const uint64_t b = table_bytes[i] + manifest_i;
        nlohmann::json row = table_sums[i].to_json();
        row.update({{"components", table[i]}, {"rmse_linear", std::sqrt(table_sse[i] / samples)}, {"manifest_bytes", manifest_i},
                    {"stored_bytes", b}, {"parameters_float32_bytes", table_params[i]},
                    {"raw_8bit_to_parameters_float32", double(raw8) / table_params[i]},
                    {"raw_8bit_to_stored", double(raw8) / b},
                    {"input_files_to_stored", input_stored_bytes ? double(input_stored_bytes) / b : 0.0}});
        if (reference) row["vs_reference"] = table_ref[i].to_json();
        rows.push_back(row);
    }
    m["table"] = rows;
    // Equal bytes: the longest stream prefix within each row's bytes (one global error budget).
    nlohmann::json equal = nlohmann::json::array();
    for (size_t i = 0; i < table.size(); ++i) {
        std::vector<int> per(groups.size(), 0);
        uint64_t b = 0;
        for (const auto& g : groups) b += g.mean_bytes;
        for (const auto& [g, c] : stream) {
            const GroupRecord& r = groups[size_t(g)];
            const uint64_t cost = r.component_bytes[size_t(c)] + r.v_bytes[size_t(c)];
            if (b + cost > table_bytes[i]) break;
            b += cost;
            per[size_t(g)] = std::max(per[size_t(g)], c + 1);
        }
        ColorSums cs, cr;
        double row_sse = 0;
        uint64_t params = 0;
        int64_t total = 0;
        for (size_t g = 0; g < groups.size(); ++g) {
            const auto c = size_t(per[g]);
            cs += groups[g].color[c];
            if (reference) cr += groups[g].color_ref[c];
            row_sse += groups[g].sse[c];
            params += uint64_t(4) * (uint64_t(P) * (c + 1) + uint64_t(groups[g].columns) * c);
            total += per[g];
        }
        const uint64_t manifest_i = cut_manifest_bytes(manifest, per, groups);
        b += manifest_i;
        nlohmann::json row = cs.to_json();
        row.update({{"components", table[i]}, {"byte_budget", table_bytes[i]}, {"manifest_bytes", manifest_i},
                    {"components_total", total}, {"components_per_group", per},
                    {"components_min", per.empty() ? 0 : *std::min_element(per.begin(), per.end())},
                    {"components_max", per.empty() ? 0 : *std::max_element(per.begin(), per.end())},
                    {"rmse_linear", std::sqrt(row_sse / samples)}, {"stored_bytes", b},
                    {"parameters_float32_bytes", params},
                    {"raw_8bit_to_parameters_float32", double(raw8) / double(std::max<uint64_t>(params, 1))},
                    {"raw_8bit_to_stored", double(raw8) / b},
                    {"input_files_to_stored", input_stored_bytes ? double(input_stored_bytes) / b : 0.0}});
        if (reference) row["vs_reference"] = cr.to_json();
        equal.push_back(row);
    }
    m["table_equal_bytes"] = equal;
    if (reference) m["reference"] = {{"path", o.reference}, {"input", ref_input.to_json()}};
    return m;
}

namespace {

// The console summary (docs/report.md, "Console summary") from the run's metrics: components
// chosen, bytes stored and the compression ratio, and the model's error against the input.
void print_summary(const nlohmann::json& m) {
    const std::string tool = "btf-pca";
    const nlohmann::json& p = m["pca"];
    const auto per = p["components_per_group"].get<std::vector<int>>();
    const int lo = per.empty() ? 0 : *std::min_element(per.begin(), per.end());
    const int hi = per.empty() ? 0 : *std::max_element(per.begin(), per.end());
    const double max_rmse = p["max_rmse"].get<double>();
    log::summary(tool, "components",
                 str(log::count(p["components_total"].get<int64_t>(), "component"), " over ",
                     log::count(p["groups"].get<int>(), "view group"), " (",
                     lo == hi ? str(lo) : str(lo, " to ", hi), " per group",
                     max_rmse >= 0 ? str(", fewest within --max-rmse ", log::num(max_rmse)) : "", ")"));
    const nlohmann::json& b = m["bytes"];
    log::summary(tool, "stored", str(b["stored"].get<uint64_t>(), " bytes, compression ratio ",
                                     log::num(m["compression_ratio"]["raw_8bit_to_stored"].get<double>()),
                                     " (raw 8-bit samples / stored bytes)"));
    const nlohmann::json& e = m["error"];
    log::summary(tool, "error (model vs input)",
                 str("RMSE ", log::num(e["rmse_linear"].get<double>()), " (",
                     m["error_space"].get<std::string>(), "), MAE Lab ",
                     log::num(e["mae_lab"].get<double>()), ", mean Delta E 2000 ",
                     log::num(e["delta_e2000_mean"].get<double>()), ", RMSE 8-bit ",
                     log::num(e["rmse_rgb8"].get<double>()), " codes"));
}

}  // namespace

void run_pca(const PcaRunOptions& o, Report& report) {
    if (o.codec == Codec::kThesis) check_thesis_options(o);  // before any work
    std::error_code ec;
    const stdfs::path in = stdfs::weakly_canonical(o.input, ec), out = stdfs::weakly_canonical(o.output, ec);
    if (fs::same_file(o.input, o.output))
        throw UsageError(str("-o ", o.output, ": is the input ", o.input));
    const std::string in_s = in.string() + "/", out_s = out.string() + "/";
    if (out_s.compare(0, in_s.size(), in_s) == 0)
        throw UsageError(str("-o ", o.output, ": lies inside the input folder ", o.input));
    if (stdfs::is_directory(o.input)) fs::declare_input(o.input, "input");
    else report.add_input(o.input);
    for (const auto& f : {o.open.light_directions, o.open.view_directions})
        if (!f.empty()) report.add_input(f);
    if (!o.reference.empty()) {
        if (fs::same_file(o.reference, o.output)) throw UsageError(str("-o ", o.output, ": is the --reference ", o.reference));
        if (stdfs::is_directory(o.reference)) fs::declare_input(o.reference, "--reference");
        else report.add_input(o.reference);
    }
    for (const char* f : {"btf-pca.json", "weights.bin", "streaming.tsv", "streaming.gp"})
        fs::declare_output(o.output + "/" + f, "-o");
    std::unique_ptr<FolderBtf> btf;
    {
        ScopedStage stage(report, "index " + o.input);
        btf = FolderBtf::open(o.input, o.open);
    }
    const auto& idx = btf->index();
    log::info(str("[btf-pca] ", o.input, ": ", log::count(idx.shape.n_lights(), "light"), " x ",
                  log::count(idx.shape.n_views(), "view"), " of ",
                  idx.shape.width, "x", idx.shape.height, " px (", idx.format, ", ", idx.bits_per_channel, "-bit)"));
    std::unique_ptr<FolderBtf> ref;
    if (!o.reference.empty()) {
        ScopedStage stage(report, "index " + o.reference);
        ref = FolderBtf::open(o.reference, o.open);
    }
    PcaRunOptions run = o;
    const std::string capture = o.input + "/capture.json";
    if (stdfs::is_directory(o.input) && stdfs::is_regular_file(capture)) {
        // The capture's irradiance travels with the compressed BTF (btf-pca.json).
        report.add_input(capture);
        const nlohmann::json meta = json_in::read_file(capture);
        const auto it = meta.is_object() ? meta.find("irradiance_w_m2") : meta.end();
        if (it == meta.end() || !it->is_number() || !std::isfinite(it->get<double>()) || !(it->get<double>() > 0))
            throw Error(str(capture, ": irradiance_w_m2 must be a finite number > 0"));
        run.irradiance_w_m2 = it->get<double>();
    }
    ScopedStage stage(report, "compress");
    nlohmann::json m = compress_to_folder(*btf, run, idx.stored_bytes, &report, ref.get());
    m["input"] = {{"path", o.input}, {"format", idx.format}, {"bits_per_channel", idx.bits_per_channel},
                  {"zip", idx.is_zip}, {"stored_bytes", idx.stored_bytes}, {"ignored_files", idx.ignored.size()}};
    print_summary(m);
    report.metrics() = m;
}

}  // namespace inlight::btf
