#include "btf/interp_run.h"

#include <cmath>
#include <filesystem>

#include "btf/compressed.h"
#include "btf/synthetic.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/parallel.h"
#include "image/color.h"

namespace inlight::btf {
namespace stdfs = std::filesystem;

std::unique_ptr<BtfSource> open_raw_or_compressed(const std::string& path, const OpenOptions& options) {
    if (stdfs::is_regular_file(stdfs::path(path) / "btf-pca.json")) return CompressedBtf::open(path);
    return FolderBtf::open(path, options);
}

ImageErrors image_errors(const image::Image& test, const image::Image& truth) {
    if (test.width != truth.width || test.height != truth.height || test.channels != 3 || truth.channels != 3)
        throw Error(str("image errors: ", test.width, "x", test.height, "x", test.channels, " against a truth of ",
                        truth.width, "x", truth.height, "x", truth.channels));
    double sq = 0, sum_truth = 0, sum_test = 0, lab = 0, de = 0, code_sq = 0;
    const size_t n = truth.pixel_count();
    for (size_t p = 0; p < n; ++p) {
        Eigen::Vector3d t, x;
        for (int c = 0; c < 3; ++c) {
            t[c] = truth.pixels[3 * p + size_t(c)];
            x[c] = test.pixels[3 * p + size_t(c)];
            sq += (x[c] - t[c]) * (x[c] - t[c]);
            sum_truth += t[c];
            sum_test += x[c];
        }
        t = t.cwiseMax(0.0).cwiseMin(1.0);
        x = x.cwiseMax(0.0).cwiseMin(1.0);
        const Eigen::Vector3d lt = image::lab_from_linear_srgb(t), lx = image::lab_from_linear_srgb(x);
        lab += (lx - lt).cwiseAbs().sum();
        de += image::delta_e2000(lt, lx);
        for (int c = 0; c < 3; ++c) {
            const double d = 255.0 * (image::srgb_encode(float(x[c])) - image::srgb_encode(float(t[c])));
            code_sq += d * d;
        }
    }
    ImageErrors e;
    const double nd = std::max<double>(double(n), 1);
    e.rmse = std::sqrt(sq / (3 * nd));
    e.rel_rmse = sum_truth > 0 ? e.rmse / (sum_truth / (3 * nd)) : 0.0;
    e.mean_rel_diff = sum_truth > 0 ? std::abs(sum_test - sum_truth) / sum_truth : 0.0;
    e.mae_lab = lab / (3 * nd);
    e.delta_e2000_mean = de / nd;
    e.rmse_rgb8 = std::sqrt(code_sq / (3 * nd));
    return e;
}

namespace {

nlohmann::json to_json(const ImageErrors& e) {
    return {{"rmse", e.rmse}, {"rel_rmse", e.rel_rmse}, {"mean_rel_diff", e.mean_rel_diff}, {"mae_lab", e.mae_lab},
            {"delta_e2000_mean", e.delta_e2000_mean}, {"rmse_rgb8", e.rmse_rgb8}};
}

nlohmann::json to_json(const DirectionWeights& w) {
    nlohmann::json idx = nlohmann::json::array(), wt = nlohmann::json::array();
    for (int i = 0; i < w.count; ++i) {
        idx.push_back(w.index[size_t(i)]);
        wt.push_back(w.weight[size_t(i)]);
    }
    return {{"directions", idx}, {"weights", wt}, {"outside_deg", w.outside_deg}};
}

/// The truth image of a pair: EXR, else PNG, in UBO2003 naming under `dir`.
image::Image read_truth(const std::string& dir, const DirectionPair& p) {
    for (const char* ext : {"exr", "png"}) {
        UboWriteOptions names;
        names.extension = ext;
        const std::string path = ubo2003_path(dir, p.light, p.view, names);
        if (stdfs::is_regular_file(path)) return image::read_image(path);
    }
    UboWriteOptions names;
    names.extension = "exr";
    throw Error(str("--truth ", dir, ": no image of light (", p.light.theta_deg, ", ", p.light.phi_deg, ") view (",
                    p.view.theta_deg, ", ", p.view.phi_deg, ") deg: expected ",
                    ubo2003_path(dir, p.light, p.view, names), " or .png"));
}

}  // namespace

void run_interpolation(const InterpRunOptions& o, Report& report) {
    std::vector<DirectionPair> pairs;
    try {
        pairs = read_direction_pairs(o.pairs);
    } catch (const Error& e) {
        throw UsageError(str("--pairs: ", e.what()));
    }
    report.add_input(o.pairs);
    if (stdfs::is_directory(o.input)) fs::declare_input(o.input, "input");
    else report.add_input(o.input);
    if (!o.truth.empty()) fs::declare_input(o.truth, "--truth");
    fs::declare_output(o.output, "-o");
    std::unique_ptr<BtfSource> btf;
    {
        ScopedStage stage(report, "open " + o.input);
        btf = open_raw_or_compressed(o.input, o.open);
    }
    const BtfShape& s = btf->shape();
    const auto lights = make_interpolator(o.scheme, s.lights), views = make_interpolator(o.scheme, s.views);
    std::vector<image::Image> truths(pairs.size());
    if (!o.truth.empty()) {  // every truth image is checked before any output is written
        ScopedStage stage(report, "read truth");
        for (size_t i = 0; i < pairs.size(); ++i) truths[i] = read_truth(o.truth, pairs[i]);
    }
    ScopedStage stage(report, "interpolate");
    nlohmann::json rows = nlohmann::json::array();
    ImageErrors mean;
    int outside = 0;
    image::WriteOptions wo;
    wo.bits = 32;
    UboWriteOptions names;
    names.extension = "exr";
    for (size_t i = 0; i < pairs.size(); ++i) {
        const Eigen::Vector3d l = pairs[i].light.vector(), v = pairs[i].view.vector();
        const DirectionWeights wl = lights->weights(l), wv = views->weights(v);
        const image::Image img = btf->combine(interpolation_terms(*lights, *views, l, v));
        const std::string path = ubo2003_path(o.output, pairs[i].light, pairs[i].view, names);
        image::write_image(path, img, wo);
        nlohmann::json row = {{"light_deg", {pairs[i].light.theta_deg, pairs[i].light.phi_deg}},
                              {"view_deg", {pairs[i].view.theta_deg, pairs[i].view.phi_deg}},
                              {"light", to_json(wl)}, {"view", to_json(wv)}};
        if (wl.outside_deg > 0 || wv.outside_deg > 0) ++outside;
        if (!o.truth.empty()) {
            const ImageErrors e = image_errors(img, truths[i]);
            row["errors"] = to_json(e);
            mean.rmse += e.rmse / double(pairs.size());
            mean.rel_rmse += e.rel_rmse / double(pairs.size());
            mean.mean_rel_diff += e.mean_rel_diff / double(pairs.size());
            mean.mae_lab += e.mae_lab / double(pairs.size());
            mean.delta_e2000_mean += e.delta_e2000_mean / double(pairs.size());
            mean.rmse_rgb8 += e.rmse_rgb8 / double(pairs.size());
        }
        rows.push_back(row);
    }
    report.add_output(o.output, "btf_images", "linear_srgb");
    nlohmann::json m = {{"scheme", to_string(o.scheme)},
                        {"input", o.input},
                        {"compressed", dynamic_cast<const CompressedBtf*>(btf.get()) != nullptr},
                        {"pairs", pairs.size()},
                        {"pairs_outside_measured_region", outside},
                        {"per_pair", rows}};
    if (!o.truth.empty()) m["mean_errors"] = to_json(mean);
    report.metrics()["interpolation"] = m;
    log::summary("btf-pca", "interpolated",
                 str(log::count(int64_t(pairs.size()), "pair"), " (", to_string(o.scheme), ")",
                     o.truth.empty() ? std::string()
                                     : str(", vs --truth: mean MAE Lab ", log::num(mean.mae_lab),
                                           ", mean Delta E 2000 ", log::num(mean.delta_e2000_mean),
                                           ", relative RMSE ", log::num(mean.rel_rmse))));
}

}  // namespace inlight::btf
