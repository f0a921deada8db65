#include "calib/response.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>

#include "core/check.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/json_in.h"
#include "core/json_out.h"
#include "core/log.h"

namespace inlight::calib {

namespace {

int code_at(const image::Image& img, size_t pixel, int channel) {
    return static_cast<int>(
        img.pixels[pixel * static_cast<size_t>(img.channels) + static_cast<size_t>(channel)]);
}

void check_codes(const image::Image& img, const std::string& what) {
    for (float v : img.pixels) {
        if (!(v >= 0 && v <= 255) || v != std::floor(v)) {
            throw Error(str(what, ": codes must be integers in 0..255, found ", v));
        }
    }
}

void check_bracket(const std::vector<image::Image>& codes, const std::vector<double>& exposures_s) {
    if (codes.size() < 2) throw Error(str("need at least 2 exposures, got ", codes.size()));
    if (codes.size() != exposures_s.size()) {
        throw Error(str(log::count(int64_t(codes.size()), "image"), " but ",
                        log::count(int64_t(exposures_s.size()), "exposure time")));
    }
    for (size_t j = 0; j < codes.size(); ++j) {
        if (!(exposures_s[j] > 0)) {
            throw Error(str("exposure ", j, ": time must be positive, got ", exposures_s[j]));
        }
        if (codes[j].width != codes[0].width || codes[j].height != codes[0].height ||
            codes[j].channels != codes[0].channels) {
            throw Error(str("exposure ", j, ": ", codes[j].width, "x", codes[j].height, "x",
                            codes[j].channels, " differs from exposure 0's ", codes[0].width, "x",
                            codes[0].height, "x", codes[0].channels));
        }
        check_codes(codes[j], str("exposure ", j));
    }
    const auto [lo, hi] = std::minmax_element(exposures_s.begin(), exposures_s.end());
    if (*lo == *hi) throw Error("all exposure times are equal: a bracket needs different ones");
}

std::vector<std::string> channel_names(int channels) {
    if (channels == 1) return {"y"};
    std::vector<std::string> names = {"r", "g", "b", "a"};
    names.resize(static_cast<size_t>(channels));
    for (int c = 4; c < channels; ++c) names[static_cast<size_t>(c)] = str("c", c);
    return names;
}

}  // namespace

double hat_weight(int code) { return code <= 127 ? code : 255 - code; }

double ResponseCurve::radiance(int channel, int code, double exposure_s) const {
    INLIGHT_CHECK(channel >= 0 && channel < channels());
    INLIGHT_CHECK(code >= 0 && code < kCodes);
    return std::exp(log_exposure[static_cast<size_t>(channel)][static_cast<size_t>(code)]) /
           exposure_s;
}

ResponseFit recover_response(const std::vector<image::Image>& codes,
                             const std::vector<double>& exposures_s, const ResponseOptions& opt) {
    check_bracket(codes, exposures_s);
    const int p = static_cast<int>(codes.size());
    const int channels = codes[0].channels;
    const size_t pixels = codes[0].pixel_count();
    const int n =
        opt.samples > 0 ? opt.samples : std::clamp(4 * kCodes / std::max(1, p - 1), 64, 1024);
    // The exposure in the middle of the bracket stratifies the samples.
    std::vector<size_t> order(static_cast<size_t>(p));
    for (size_t j = 0; j < order.size(); ++j) order[j] = j;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return exposures_s[a] < exposures_s[b]; });
    const size_t mid = order[static_cast<size_t>(p / 2)];

    ResponseFit fit;
    fit.curve.channel_names = channel_names(channels);
    fit.curve.log_exposure.resize(static_cast<size_t>(channels));
    fit.samples = n;
    for (int c = 0; c < channels; ++c) {
        // Candidates: pixels seen with non-zero weight in at least two exposures.
        std::vector<std::vector<size_t>> bucket(kCodes);
        for (size_t i = 0; i < pixels; ++i) {
            int weighted = 0;
            for (int j = 0; j < p; ++j)
                weighted += hat_weight(code_at(codes[static_cast<size_t>(j)], i, c)) > 0;
            if (weighted >= 2) bucket[static_cast<size_t>(code_at(codes[mid], i, c))].push_back(i);
        }
        std::mt19937_64 rng(opt.seed * 7919ULL + static_cast<uint64_t>(c));
        for (auto& b : bucket) std::shuffle(b.begin(), b.end(), rng);
        std::vector<size_t> samples;
        for (size_t round = 0; static_cast<int>(samples.size()) < n; ++round) {
            bool any = false;
            for (const auto& b : bucket) {
                if (round < b.size() && static_cast<int>(samples.size()) < n) {
                    samples.push_back(b[round]);
                    any = true;
                }
            }
            if (!any) break;
        }
        const int ns = static_cast<int>(samples.size());
        if (ns * (p - 1) < kCodes - 1) {
            throw Error(str("channel ", fit.curve.channel_names[static_cast<size_t>(c)], ": only ",
                            ns,
                            " usable pixels (seen unclipped in two exposures); the bracket "
                            "must overlap more"));
        }

        // Normal equations over g (256) and ln E (ns); ln E's block is diagonal, so it is
        // eliminated (Schur complement) and g solved from a 256 x 256 system.
        Eigen::MatrixXd gg = Eigen::MatrixXd::Zero(kCodes, kCodes);
        Eigen::VectorXd bg = Eigen::VectorXd::Zero(kCodes);
        Eigen::MatrixXd ge = Eigen::MatrixXd::Zero(kCodes, ns);  // g-E coupling
        Eigen::VectorXd ee = Eigen::VectorXd::Zero(ns), be = Eigen::VectorXd::Zero(ns);
        for (int i = 0; i < ns; ++i) {
            for (int j = 0; j < p; ++j) {
                const int z =
                    code_at(codes[static_cast<size_t>(j)], samples[static_cast<size_t>(i)], c);
                const double w2 = hat_weight(z) * hat_weight(z);
                const double lt = std::log(exposures_s[static_cast<size_t>(j)]);
                gg(z, z) += w2;
                ge(z, i) -= w2;
                ee[i] += w2;
                bg[z] += w2 * lt;
                be[i] -= w2 * lt;
            }
        }
        gg(kReferenceCode, kReferenceCode) += 1;  // g(128) = 0
        for (int z = 1; z < kCodes - 1; ++z) {
            const double a = opt.lambda * hat_weight(z);
            const double row[3] = {a, -2 * a, a};
            for (int u = 0; u < 3; ++u) {
                for (int v = 0; v < 3; ++v) gg(z - 1 + u, z - 1 + v) += row[u] * row[v];
            }
        }
        Eigen::MatrixXd schur = gg;
        Eigen::VectorXd rhs = bg;
        for (int i = 0; i < ns; ++i) {
            schur.noalias() -= ge.col(i) * ge.col(i).transpose() / ee[i];
            rhs -= ge.col(i) * (be[i] / ee[i]);
        }
        const Eigen::VectorXd g = schur.ldlt().solve(rhs);
        if (!g.allFinite()) throw Error("response recovery failed: singular system");
        const double shift = g[kReferenceCode];
        auto& out = fit.curve.log_exposure[static_cast<size_t>(c)];
        for (int z = 0; z < kCodes; ++z) out[static_cast<size_t>(z)] = g[z] - shift;

        double num = 0, den = 0;
        for (int i = 0; i < ns; ++i) {
            const double ln_e = (be[i] - ge.col(i).dot(g)) / ee[i] - shift;
            for (int j = 0; j < p; ++j) {
                const int z =
                    code_at(codes[static_cast<size_t>(j)], samples[static_cast<size_t>(i)], c);
                const double w2 = hat_weight(z) * hat_weight(z);
                const double r = out[static_cast<size_t>(z)] - ln_e -
                                 std::log(exposures_s[static_cast<size_t>(j)]);
                num += w2 * r * r;
                den += w2;
            }
        }
        fit.fit_rms_log.push_back(den > 0 ? std::sqrt(num / den) : 0.0);
    }
    return fit;
}

MergeResult merge_radiance(const std::vector<image::Image>& codes,
                           const std::vector<double>& exposures_s, const ResponseCurve& curve) {
    check_bracket(codes, exposures_s);
    const int channels = codes[0].channels;
    if (channels != curve.channels()) {
        throw Error(str("bracket has ", channels, " channels, response curve ", curve.channels()));
    }
    const size_t shortest = static_cast<size_t>(
        std::min_element(exposures_s.begin(), exposures_s.end()) - exposures_s.begin());
    const size_t longest = static_cast<size_t>(
        std::max_element(exposures_s.begin(), exposures_s.end()) - exposures_s.begin());
    MergeResult m;
    m.radiance =
        image::Image(codes[0].width, codes[0].height, channels, image::ColorSpace::kRawCamera);
    m.saturated = image::Image(codes[0].width, codes[0].height, 1, image::ColorSpace::kData);
    for (size_t i = 0; i < codes[0].pixel_count(); ++i) {
        bool clipped = false;
        for (int c = 0; c < channels; ++c) {
            const auto& g = curve.log_exposure[static_cast<size_t>(c)];
            double num = 0, den = 0;
            for (size_t j = 0; j < codes.size(); ++j) {
                const int z = code_at(codes[j], i, c);
                const double w = hat_weight(z);
                num += w * (g[static_cast<size_t>(z)] - std::log(exposures_s[j]));
                den += w;
            }
            double ln_e;
            if (den > 0) {
                ln_e = num / den;
            } else if (code_at(codes[shortest], i, c) == kCodes - 1) {
                ln_e = g[kCodes - 1] - std::log(exposures_s[shortest]);
                clipped = true;
            } else {
                ln_e = g[static_cast<size_t>(code_at(codes[longest], i, c))] -
                       std::log(exposures_s[longest]);
            }
            m.radiance.pixels[i * static_cast<size_t>(channels) + static_cast<size_t>(c)] =
                static_cast<float>(std::exp(ln_e));
        }
        if (clipped) {
            m.saturated.pixels[i] = 1;
            ++m.saturated_pixels;
        }
    }
    return m;
}

FrameRadiance radiance_from_frame(const image::Image& codes, const ResponseCurve& curve,
                                  double exposure_s, const image::Image* solid_angle_sr,
                                  const image::Image* mask, int saturation_code) {
    if (!(exposure_s > 0)) throw Error(str("exposure time must be positive, got ", exposure_s));
    if (codes.channels != curve.channels()) {
        throw Error(
            str("frame has ", codes.channels, " channels, response curve ", curve.channels()));
    }
    for (const image::Image* aux : {solid_angle_sr, mask}) {
        if (aux &&
            (aux->width != codes.width || aux->height != codes.height || aux->channels != 1)) {
            throw Error(str("frame is ", codes.width, "x", codes.height, " but a ",
                            aux == mask ? "mask" : "solid-angle map", " is ", aux->width, "x",
                            aux->height, "x", aux->channels, " (need 1 channel, same size)"));
        }
    }
    check_codes(codes, "frame");
    const int channels = codes.channels;
    FrameRadiance f;
    f.radiance = image::Image(codes.width, codes.height, channels, image::ColorSpace::kRawCamera);
    f.saturated = image::Image(codes.width, codes.height, 1, image::ColorSpace::kData);
    f.clipped_light_lower_bound.assign(static_cast<size_t>(channels), 0.0);
    f.unclipped_light.assign(static_cast<size_t>(channels), 0.0);
    int64_t counted = 0;
    for (size_t i = 0; i < codes.pixel_count(); ++i) {
        if (mask && !(mask->pixels[i] > 0)) continue;
        ++counted;
        bool sat = false;
        for (int c = 0; c < channels; ++c) sat = sat || code_at(codes, i, c) >= saturation_code;
        const double omega = solid_angle_sr ? solid_angle_sr->pixels[i] : 1.0;
        for (int c = 0; c < channels; ++c) {
            const double l = curve.radiance(c, code_at(codes, i, c), exposure_s);
            // A curve or exposure that takes radiance past the float range was blamed on the
            // frame's pixels ("pixel is Inf; pass --nonfinite zero").
            if (!(std::abs(l) <= std::numeric_limits<float>::max())) {
                throw Error(str("the response curve gives radiance ", l, " for code ",
                                code_at(codes, i, c), " at an exposure of ", exposure_s,
                                " s: past the float range (check the curve and --exposure-s)"));
            }
            f.radiance.pixels[i * static_cast<size_t>(channels) + static_cast<size_t>(c)] =
                static_cast<float>(l);
            (sat ? f.clipped_light_lower_bound : f.unclipped_light)[static_cast<size_t>(c)] +=
                l * omega;
        }
        if (sat) {
            f.saturated.pixels[i] = 1;
            ++f.saturated_pixels;
        }
    }
    f.saturated_fraction = counted > 0 ? static_cast<double>(f.saturated_pixels) / counted : 0.0;
    return f;
}

image::Image read_codes(const std::string& path) {
    const image::ImageInfo info = image::read_info(path);
    if (info.is_float || info.bits_per_channel != 8) {
        throw Error(str(path, ": response recovery needs 8-bit images, this one has ",
                        info.bits_per_channel, info.is_float ? "-bit float" : "-bit", " channels"));
    }
    image::ReadOptions ro;
    ro.decode_srgb = false;
    image::Image img = image::read_image(path, ro);
    for (float& v : img.pixels) v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f);
    img.color_space = image::ColorSpace::kData;
    return img;
}

void write_response(const std::string& path, const ResponseFit& fit, double lambda,
                    const std::vector<double>& exposures_s,
                    const std::vector<std::string>& images) {
    nlohmann::json j;
    j["format"] = "inlight_response";
    j["version"] = 1;
    j["method"] = "debevec_malik_1997";
    j["definition"] = "g[c][z] = ln(radiance * exposure_s) of code z in channel c; g[c][128] = 0";
    j["channels"] = fit.curve.channel_names;
    j["reference_code"] = kReferenceCode;
    j["weighting"] = "hat";
    j["lambda"] = lambda;
    j["samples"] = fit.samples;
    j["exposures_s"] = exposures_s;
    j["images"] = images;
    j["fit_rms_log"] = fit.fit_rms_log;
    nlohmann::json g = nlohmann::json::array();
    for (const auto& curve : fit.curve.log_exposure)
        g.push_back(std::vector<double>(curve.begin(), curve.end()));
    j["g"] = g;
    fs::write_text_atomic(path, dump_finite(j, 1, path));
}

namespace {
constexpr double kMaxLogExposure = 80;  ///< |g| of a response curve (e^80 ~ 5.5e34)
}  // namespace

ResponseCurve read_response(const std::string& path) {
    const nlohmann::json j = json_in::read_file(path);
    // j.value() throws when the key holds another type (a duplicate "format" key holding an
    // array was found by response_fuzz): compare only a string.
    const auto format = j.is_object() ? j.find("format") : j.end();
    if (format == j.end() || !format->is_string() || *format != "inlight_response") {
        throw Error(str(path, ": not an inlight response file (format != inlight_response)"));
    }
    ResponseCurve curve;
    try {
        curve.channel_names = j.at("channels").get<std::vector<std::string>>();
        for (const auto& g : j.at("g")) {
            const auto v = g.get<std::vector<double>>();
            if (v.size() != static_cast<size_t>(kCodes)) {
                throw Error(str(path, ": each curve needs ", kCodes, " values, got ", v.size()));
            }
            std::array<double, kCodes> a{};
            std::copy(v.begin(), v.end(), a.begin());
            // g is ln(exposure): a value past +-kMaxLogExposure is no camera's (e^80 ~ 5e34).
            for (size_t k = 0; k < v.size(); ++k) {
                if (!(std::abs(v[k]) <= kMaxLogExposure)) {
                    throw Error(str(path, ": curve ", curve.log_exposure.size(), ", code ", k, ": g = ",
                                    v[k], " is outside [-", kMaxLogExposure, ", ", kMaxLogExposure,
                                    "] (ln exposure)"));
                }
            }
            curve.log_exposure.push_back(a);
        }
    } catch (const nlohmann::json::exception& e) {
        throw Error(str(path, ": bad response file (", e.what(), ")"));
    }
    if (curve.log_exposure.empty() || curve.log_exposure.size() != curve.channel_names.size()) {
        throw Error(str(path, ": ", curve.log_exposure.size(), " curves for ",
                        curve.channel_names.size(), " channels"));
    }
    return curve;
}

}  // namespace inlight::calib
