#include "calib/maps.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/check.h"
#include "core/error.h"
#include "core/number.h"
#include "core/parallel.h"

namespace inlight::calib {

namespace {

/// Rows per parallel chunk: fixed, so results do not depend on the thread count.
constexpr int64_t kRowGrain = 8;

/// Solid angle of the spherical triangle of unit vectors a, b, c (Van Oosterom-Strackee).
double triangle_solid_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
    const double num = std::abs(a.dot(b.cross(c)));
    const double den = 1 + a.dot(b) + b.dot(c) + c.dot(a);
    return 2 * std::atan2(num, den);
}

double polar_angle(const Eigen::Vector3d& d) { return std::atan2(std::hypot(d.x(), d.y()), d.z()); }

double median_of(std::vector<float>& v) {
    const size_t n = v.size();
    std::nth_element(v.begin(), v.begin() + static_cast<ptrdiff_t>(n / 2), v.end());
    const double hi = v[n / 2];
    if (n % 2) return hi;
    const double lo = *std::max_element(v.begin(), v.begin() + static_cast<ptrdiff_t>(n / 2));
    return 0.5 * (lo + hi);
}

}  // namespace

Eigen::Matrix3d default_device_from_camera() { return Eigen::Vector3d(-1, -1, 1).asDiagonal(); }

DirectionMaps compute_maps(const CameraModel& camera, const MapOptions& opt) {
    INLIGHT_CHECK(camera.width > 0 && camera.height > 0) << "camera size not set";
    const int w = camera.width, h = camera.height;
    const Unprojector unproject(camera);
    const double max_theta =
        opt.max_theta > 0 ? std::min(opt.max_theta, unproject.max_theta()) : unproject.max_theta();

    // Rays through the pixel corners (x - 0.5, y - 0.5), x in [0, w], y in [0, h].
    const int cw = w + 1;
    std::vector<Eigen::Vector3d> corner(static_cast<size_t>(cw) * (h + 1));
    std::vector<uint8_t> corner_ok(corner.size(), 0);
    parallel::for_chunks(h + 1, kRowGrain, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x <= w; ++x) {
                const auto ray = unproject(Eigen::Vector2d(x - 0.5, static_cast<double>(y) - 0.5));
                const size_t i = static_cast<size_t>(y) * cw + x;
                if (ray) {
                    corner[i] = *ray;
                    corner_ok[i] = 1;
                }
            }
        }
    });

    DirectionMaps maps;
    maps.max_theta = max_theta;
    maps.directions = image::Image(w, h, 3, image::ColorSpace::kData);
    maps.solid_angle = image::Image(w, h, 1, image::ColorSpace::kData);
    maps.mask = image::Image(w, h, 1, image::ColorSpace::kData);
    const double r2 = opt.circle.radius_px * opt.circle.radius_px;

    parallel::for_chunks(h, kRowGrain, [&](int64_t y0, int64_t y1) {
        for (int64_t yy = y0; yy < y1; ++yy) {
            const int y = static_cast<int>(yy);
            for (int x = 0; x < w; ++x) {
                if (opt.circle.radius_px > 0) {
                    const double dx = x - opt.circle.cx, dy = y - opt.circle.cy;
                    if (dx * dx + dy * dy > r2) continue;
                }
                const auto ray = unproject(Eigen::Vector2d(x, y));
                if (!ray || polar_angle(*ray) > max_theta) continue;
                const size_t i00 = static_cast<size_t>(y) * cw + x, i10 = i00 + 1, i01 = i00 + cw,
                             i11 = i01 + 1;
                double omega;
                if (corner_ok[i00] && corner_ok[i10] && corner_ok[i01] && corner_ok[i11]) {
                    omega = triangle_solid_angle(corner[i00], corner[i10], corner[i11]) +
                            triangle_solid_angle(corner[i00], corner[i11], corner[i01]);
                } else {
                    // A corner is outside the model's domain (the pixel straddles its edge):
                    // the area element |d_x x d_y| at the centre, by central differences.
                    constexpr double kH = 0.25;
                    const auto xp = unproject(Eigen::Vector2d(x + kH, y));
                    const auto xm = unproject(Eigen::Vector2d(x - kH, y));
                    const auto yp = unproject(Eigen::Vector2d(x, y + kH));
                    const auto ym = unproject(Eigen::Vector2d(x, y - kH));
                    if (!xp || !xm || !yp || !ym) continue;
                    omega = ((*xp - *xm) / (2 * kH)).cross((*yp - *ym) / (2 * kH)).norm();
                }
                const Eigen::Vector3d d = opt.device_from_camera * *ray;
                for (int c = 0; c < 3; ++c) maps.directions.at(x, y, c) = static_cast<float>(d[c]);
                maps.solid_angle.at(x, y, 0) = static_cast<float>(omega);
                maps.mask.at(x, y, 0) = 1.0f;
            }
        }
    });

    struct Sum {
        double omega = 0;
        int64_t count = 0;
    };
    const Sum total = parallel::reduce(
        h, kRowGrain, Sum{},
        [&](int64_t y0, int64_t y1) {
            Sum s;
            for (int64_t y = y0; y < y1; ++y) {
                for (int x = 0; x < w; ++x) {
                    s.omega += maps.solid_angle.at(x, static_cast<int>(y), 0);
                    s.count += maps.mask.at(x, static_cast<int>(y), 0) > 0 ? 1 : 0;
                }
            }
            return s;
        },
        [](Sum a, const Sum& b) {
            a.omega += b.omega;
            a.count += b.count;
            return a;
        });
    maps.covered_solid_angle_sr = total.omega;
    maps.valid_pixels = total.count;
    return maps;
}

DirectionMaps downscale_maps(const DirectionMaps& full, int width, int height) {
    const int fw = full.mask.width, fh = full.mask.height;
    if (width < 1 || height < 1 || width > fw || height > fh) {
        throw UsageError(
            str("downscaled size ", width, "x", height, " must lie within 1x1 and ", fw, "x", fh));
    }
    DirectionMaps out;
    out.max_theta = full.max_theta;
    out.directions = image::Image(width, height, 3, image::ColorSpace::kData);
    out.solid_angle = image::Image(width, height, 1, image::ColorSpace::kData);
    out.mask = image::Image(width, height, 1, image::ColorSpace::kData);
    auto begin_of = [](int i, int full_n, int n) {
        return static_cast<int>(static_cast<int64_t>(i) * full_n / n);
    };
    parallel::for_chunks(height, 4, [&](int64_t y0, int64_t y1) {
        std::vector<float> comp[3];
        for (int64_t yy = y0; yy < y1; ++yy) {
            const int Y = static_cast<int>(yy);
            const int ya = begin_of(Y, fh, height), yb = begin_of(Y + 1, fh, height);
            for (int X = 0; X < width; ++X) {
                const int xa = begin_of(X, fw, width), xb = begin_of(X + 1, fw, width);
                for (auto& c : comp) c.clear();
                double omega = 0;
                int total = 0, valid = 0;
                for (int y = ya; y < yb; ++y) {
                    for (int x = xa; x < xb; ++x) {
                        ++total;
                        if (full.mask.at(x, y, 0) <= 0) continue;
                        ++valid;
                        omega += full.solid_angle.at(x, y, 0);
                        for (int c = 0; c < 3; ++c) comp[c].push_back(full.directions.at(x, y, c));
                    }
                }
                if (2 * valid <= total) continue;
                Eigen::Vector3d d;
                for (int c = 0; c < 3; ++c) d[c] = median_of(comp[c]);
                if (d.norm() < 1e-6) {  // degenerate median: fall back to the mean
                    d.setZero();
                    for (int y = ya; y < yb; ++y) {
                        for (int x = xa; x < xb; ++x) {
                            for (int c = 0; c < 3; ++c) d[c] += full.directions.at(x, y, c);
                        }
                    }
                }
                d.normalize();
                for (int c = 0; c < 3; ++c) out.directions.at(X, Y, c) = static_cast<float>(d[c]);
                out.solid_angle.at(X, Y, 0) = static_cast<float>(omega);
                out.mask.at(X, Y, 0) = 1.0f;
            }
        }
    });
    double sum = 0;
    int64_t count = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            sum += out.solid_angle.at(x, y, 0);
            count += out.mask.at(x, y, 0) > 0 ? 1 : 0;
        }
    }
    out.covered_solid_angle_sr = sum;
    out.valid_pixels = count;
    return out;
}

std::vector<std::string> write_maps(const std::string& dir, const DirectionMaps& maps) {
    const std::filesystem::path d(dir);
    const std::string dirs = (d / "directions.exr").string();
    const std::string omega = (d / "solid_angle.exr").string();
    const std::string mask = (d / "mask.png").string();
    image::WriteOptions exr;
    exr.exr_half = false;
    image::write_image(dirs, maps.directions, exr);
    image::write_image(omega, maps.solid_angle, exr);
    image::WriteOptions png;
    png.bits = 8;
    png.encode_srgb = false;
    image::write_image(mask, maps.mask, png);
    return {dirs, omega, mask};
}

std::vector<Eigen::Vector2i> parse_sizes(const std::string& spec, const std::string& flag) {
    const std::string context = str(flag, " '", spec, "'");
    std::vector<Eigen::Vector2i> sizes;
    for (const std::string& item : split(spec, ',')) {
        const size_t x = item.find_first_of("xX");
        if (x == std::string::npos) {
            throw UsageError(str(context, ": expected WxH[,WxH...], e.g. 200x126; got '", item, "'"));
        }
        const auto w = parse_integer(item.substr(0, x), str(context, ": width"), 1, kMaxMapSidePx);
        const auto h = parse_integer(item.substr(x + 1), str(context, ": height"), 1, kMaxMapSidePx);
        sizes.emplace_back(static_cast<int>(w), static_cast<int>(h));
    }
    return sizes;
}

void accumulate_max(GrayImage& brightest, const GrayImage& image) {
    if (brightest.pixels.empty()) {
        brightest = image;
        return;
    }
    INLIGHT_CHECK(brightest.width == image.width && brightest.height == image.height);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        brightest.pixels[i] = std::max(brightest.pixels[i], image.pixels[i]);
    }
}

ImageCircle detect_image_circle(const GrayImage& brightest, double cx, double cy) {
    INLIGHT_CHECK(!brightest.pixels.empty()) << "no images";
    const int w = brightest.width, h = brightest.height;
    std::vector<uint8_t> sorted = brightest.pixels;
    std::nth_element(sorted.begin(),
                     sorted.begin() + static_cast<ptrdiff_t>(sorted.size() * 99 / 100),
                     sorted.end());
    const double p99 = sorted[sorted.size() * 99 / 100];
    const double threshold = std::max(12.0, 0.08 * p99);
    double r_max = 0;
    for (double x : {0.0, w - 1.0}) {
        for (double y : {0.0, h - 1.0}) r_max = std::max(r_max, std::hypot(x - cx, y - cy));
    }
    const int rings = static_cast<int>(std::ceil(r_max)) + 1;
    std::vector<int64_t> lit(static_cast<size_t>(rings), 0), all(static_cast<size_t>(rings), 0);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const size_t r = static_cast<size_t>(std::hypot(x - cx, y - cy));
            ++all[r];
            if (brightest.at(x, y) > threshold) ++lit[r];
        }
    }
    int last_lit = -1;
    for (int r = rings - 1; r >= 0; --r) {
        if (all[static_cast<size_t>(r)] > 0 &&
            2 * lit[static_cast<size_t>(r)] >= all[static_cast<size_t>(r)]) {
            last_lit = r;
            break;
        }
    }
    ImageCircle c;
    if (last_lit < 0 || last_lit + 2 >= static_cast<int>(r_max)) return c;  // lit to the corners
    c.cx = cx;
    c.cy = cy;
    c.radius_px = last_lit + 1;
    return c;
}

}  // namespace inlight::calib
