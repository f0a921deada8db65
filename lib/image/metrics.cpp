#include "image/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "image/color.h"

namespace inlight::image {
namespace {

constexpr int64_t kGrainPx = 4096;  // pixels per chunk: fixed, so sums do not depend on threads

// Number of colour channels: alpha (the last of 2 or 4) excluded.
int colour_channels(int channels) {
    return (channels == 2 || channels == 4) ? channels - 1 : channels;
}

void check_comparable(const Image& test, const Image& ref, const char* what) {
    if (test.width != ref.width || test.height != ref.height) {
        throw Error(str(what, ": image sizes differ: test ", test.width, "x", test.height,
                        ", reference ", ref.width, "x", ref.height));
    }
    if (test.channels != ref.channels) {
        throw Error(str(what, ": channel counts differ: test ", test.channels, ", reference ",
                        ref.channels));
    }
    if (test.color_space != ref.color_space) {
        throw Error(str(what, ": colour spaces differ: test ", to_string(test.color_space),
                        ", reference ", to_string(ref.color_space)));
    }
    const size_t n = ref.pixel_count() * static_cast<size_t>(ref.channels);
    if (test.pixels.size() != n || ref.pixels.size() != n) {
        throw Error(str(what, ": pixel buffers do not match the image size (test ",
                        test.pixels.size(), ", reference ", ref.pixels.size(), ", expected ", n,
                        " values)"));
    }
}

// The XYZ conversion for the colour spaces that have one; null otherwise.
const Eigen::Matrix3d* xyz_matrix(ColorSpace cs) {
    static const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
    switch (cs) {
        case ColorSpace::kLinearSrgb:
            return &xyz_from_linear_srgb_matrix();
        case ColorSpace::kLinearRec2020:
            return &xyz_from_linear_rec2020_matrix();
        case ColorSpace::kXyzD65:
            return &identity;
        default:
            return nullptr;
    }
}

Eigen::Vector3d lab_at(const Image& img, size_t pixel, const Eigen::Matrix3d& xyz_from_rgb,
                       double exposure) {
    const float* p = &img.pixels[pixel * static_cast<size_t>(img.channels)];
    const Eigen::Vector3d rgb(p[0], p[1], p[2]);
    return lab_from_xyz(xyz_from_rgb * (exposure * rgb));
}

struct Sums {
    double abs = 0, sq = 0, rel = 0, max_rel = 0;
    double de76 = 0, de2000 = 0, max_de2000 = 0;
    double peak = -std::numeric_limits<double>::infinity();
};

Sums combine(Sums a, const Sums& b) {
    a.abs += b.abs;
    a.sq += b.sq;
    a.rel += b.rel;
    a.max_rel = std::max(a.max_rel, b.max_rel);
    a.de76 += b.de76;
    a.de2000 += b.de2000;
    a.max_de2000 = std::max(a.max_de2000, b.max_de2000);
    a.peak = std::max(a.peak, b.peak);
    return a;
}

}  // namespace

bool supports_delta_e(const Image& img) {
    return img.channels >= 3 && xyz_matrix(img.color_space) != nullptr;
}

Metrics compare(const Image& test, const Image& ref, const CompareOptions& options) {
    check_comparable(test, ref, "compare");
    const int nc = ref.channels;
    const bool with_de = supports_delta_e(ref);
    const Eigen::Matrix3d* m = xyz_matrix(ref.color_space);
    const double floor = options.rel_floor;

    const Sums s = parallel::reduce(
        static_cast<int64_t>(ref.pixel_count()), kGrainPx, Sums{},
        [&](int64_t begin, int64_t end) {
            Sums c;
            for (int64_t p = begin; p < end; ++p) {
                for (int k = 0; k < nc; ++k) {
                    const size_t i = static_cast<size_t>(p) * nc + k;
                    const double r = ref.pixels[i], d = std::fabs(test.pixels[i] - r);
                    c.abs += d;
                    c.sq += d * d;
                    const double rel = d / std::max(std::fabs(r), floor);
                    c.rel += rel;
                    c.max_rel = std::max(c.max_rel, rel);
                    c.peak = std::max(c.peak, r);
                }
                if (with_de) {
                    const Eigen::Vector3d lt = lab_at(test, p, *m, options.exposure);
                    const Eigen::Vector3d lr = lab_at(ref, p, *m, options.exposure);
                    c.de76 += delta_e76(lt, lr);
                    const double de = delta_e2000(lt, lr);
                    c.de2000 += de;
                    c.max_de2000 = std::max(c.max_de2000, de);
                }
            }
            return c;
        },
        combine);

    const double samples = static_cast<double>(ref.pixel_count()) * nc;
    const double pixels = static_cast<double>(ref.pixel_count());
    Metrics out;
    out.mae = s.abs / samples;
    out.rmse = std::sqrt(s.sq / samples);
    out.psnr_db = out.rmse == 0 ? std::numeric_limits<double>::infinity()
                                : 20.0 * std::log10(s.peak / out.rmse);
    out.mean_rel = s.rel / samples;
    out.max_rel = s.max_rel;
    if (with_de) {
        out.mean_de76 = s.de76 / pixels;
        out.mean_de2000 = s.de2000 / pixels;
        out.max_de2000 = s.max_de2000;
    }
    return out;
}

Image relative_error_map(const Image& test, const Image& ref, double rel_floor) {
    check_comparable(test, ref, "relative_error_map");
    Image out(ref.width, ref.height, 1, ColorSpace::kData);
    const int nc = ref.channels, cc = colour_channels(nc);
    parallel::for_chunks(static_cast<int64_t>(ref.pixel_count()), kGrainPx,
                         [&](int64_t begin, int64_t end) {
                             for (int64_t p = begin; p < end; ++p) {
                                 double worst = 0;
                                 for (int k = 0; k < cc; ++k) {
                                     const size_t i = static_cast<size_t>(p) * nc + k;
                                     const double r = ref.pixels[i];
                                     const double d = std::fabs(test.pixels[i] - r);
                                     worst = std::max(worst, d / std::max(std::fabs(r), rel_floor));
                                 }
                                 out.pixels[static_cast<size_t>(p)] = static_cast<float>(worst);
                             }
                         });
    return out;
}

Image delta_e2000_map(const Image& test, const Image& ref, double exposure) {
    check_comparable(test, ref, "delta_e2000_map");
    if (!supports_delta_e(ref)) {
        throw Error(str("delta_e2000_map: needs 3+ channels in linear_srgb, linear_rec2020 or ",
                        "xyz_d65, got ", ref.channels, " channels in ",
                        to_string(ref.color_space)));
    }
    const Eigen::Matrix3d& m = *xyz_matrix(ref.color_space);
    Image out(ref.width, ref.height, 1, ColorSpace::kData);
    parallel::for_chunks(
        static_cast<int64_t>(ref.pixel_count()), kGrainPx, [&](int64_t begin, int64_t end) {
            for (int64_t p = begin; p < end; ++p) {
                const double de =
                    delta_e2000(lab_at(test, p, m, exposure), lab_at(ref, p, m, exposure));
                out.pixels[static_cast<size_t>(p)] = static_cast<float>(de);
            }
        });
    return out;
}

Image heat_map(const Image& scalar, double max_value) {
    if (scalar.channels != 1) {
        throw Error(str("heat_map: needs a 1-channel image, got ", scalar.channels, " channels"));
    }
    if (!(max_value > 0)) throw Error(str("heat_map: max_value must be > 0, got ", max_value));
    // matplotlib's viridis at t = i/8, sRGB-encoded 8-bit (van der Walt and Smith, 2015).
    static constexpr unsigned char kViridis[9][3] = {
        {0x44, 0x01, 0x54}, {0x47, 0x2d, 0x7b}, {0x3b, 0x52, 0x8b},
        {0x2c, 0x72, 0x8e}, {0x21, 0x91, 0x8c}, {0x28, 0xae, 0x80},
        {0x5e, 0xc9, 0x62}, {0xad, 0xdc, 0x30}, {0xfd, 0xe7, 0x25}};
    Image out(scalar.width, scalar.height, 3, ColorSpace::kLinearSrgb);
    parallel::for_chunks(
        static_cast<int64_t>(scalar.pixel_count()), kGrainPx, [&](int64_t begin, int64_t end) {
            for (int64_t p = begin; p < end; ++p) {
                const double v = scalar.pixels[static_cast<size_t>(p)] / max_value;
                const double t = std::isnan(v) ? 1.0 : std::clamp(v, 0.0, 1.0);
                const double x = t * 8.0;
                const int i = std::min(static_cast<int>(x), 7);
                const double f = x - i;
                for (int k = 0; k < 3; ++k) {
                    const double enc =
                        ((1.0 - f) * kViridis[i][k] + f * kViridis[i + 1][k]) / 255.0;
                    out.pixels[static_cast<size_t>(p) * 3 + k] =
                        srgb_decode(static_cast<float>(enc));
                }
            }
        });
    return out;
}

}  // namespace inlight::image
