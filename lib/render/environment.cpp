#include "render/environment.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "envmap/environment.h"

namespace inlight::render {

image::Image load_latlong(const std::string& path) {
    return load_environment_latlong(path, "latlong");
}

namespace {

/// Nearest texel of a cube strip (faces of n x n) in direction d (OpenGL ES 3.0 table 3.21,
/// the inverse of envmap::cube_direction).
Eigen::Vector2i cube_texel(const Eigen::Vector3d& d, int n) {
    const Eigen::Vector3d a = d.cwiseAbs();
    int face;
    double sc, tc, ma;
    if (a.x() >= a.y() && a.x() >= a.z()) {
        face = d.x() > 0 ? 0 : 1;
        ma = a.x();
        sc = d.x() > 0 ? -d.z() : d.z();
        tc = -d.y();
    } else if (a.y() >= a.z()) {
        face = d.y() > 0 ? 2 : 3;
        ma = a.y();
        sc = d.x();
        tc = d.y() > 0 ? d.z() : -d.z();
    } else {
        face = d.z() > 0 ? 4 : 5;
        ma = a.z();
        sc = d.z() > 0 ? d.x() : -d.x();
        tc = -d.y();
    }
    const double s = 0.5 * (sc / ma + 1), t = 0.5 * (tc / ma + 1);
    const int i = std::clamp(static_cast<int>(s * n), 0, n - 1);
    const int j = std::clamp(static_cast<int>(t * n), 0, n - 1);
    return {face * n + i, j};
}

/// Nearest pixel of an s x s angular map (envmap::angular_direction, Debevec's definition: the
/// centre looks along +z, r = theta / pi, v up) in direction d.
Eigen::Vector2i angular_texel(const Eigen::Vector3d& d, int size) {
    const double r = std::acos(std::clamp(d.z(), -1.0, 1.0)) / kPi;
    const double len = std::hypot(d.x(), d.y());
    const double u = len > 0 ? r * d.x() / len : 0.0, v = len > 0 ? r * d.y() / len : 0.0;
    const int x = std::clamp(static_cast<int>((u + 1) * 0.5 * size), 0, size - 1);
    const int y = std::clamp(static_cast<int>((1 - v) * 0.5 * size), 0, size - 1);
    return {x, y};
}

}  // namespace

Eigen::Vector2i environment_texel(envmap::Layout layout, const Eigen::Vector3d& dir, int width,
                                  int height) {
    switch (layout) {
        case envmap::Layout::kCube:
            return cube_texel(dir, height);
        case envmap::Layout::kAngular:
            return angular_texel(dir, width);
        default: {
            const Eigen::Vector2d uv = latlong_uv(dir);
            return {std::clamp(static_cast<int>(uv[0] * width), 0, width - 1),
                    std::clamp(static_cast<int>(uv[1] * height), 0, height - 1)};
        }
    }
}

image::Image load_environment_latlong(const std::string& path, const std::string& layout_name,
                                      int latlong_height) {
    envmap::LoadOptions lo;
    lo.layout = envmap::layout_from_string(layout_name);
    if (lo.layout == envmap::Layout::kFisheye) {
        throw UsageError(str(path,
                             ": a fisheye frame covers part of the sphere; the path tracer "
                             "needs a full environment (latlong, cube or angular)"));
    }
    envmap::Environment env = envmap::load_environment(path, lo);
    if (lo.layout == envmap::Layout::kLatLong && latlong_height <= 0)
        return std::move(env.radiance);
    const image::Image& src = env.radiance;
    const int h = latlong_height > 0                      ? latlong_height
                  : lo.layout == envmap::Layout::kCube    ? 2 * src.height
                  : lo.layout == envmap::Layout::kAngular ? std::max(1, src.width / 2)
                                                          : src.height;
    const int w = 2 * h;
    constexpr int kSub = 4;
    image::Image out(w, h, 3);
    parallel::for_chunks(h, 1, [&](int64_t r0, int64_t r1) {
        for (int64_t row = r0; row < r1; ++row) {
            const double z0 = std::cos(kPi * row / h), z1 = std::cos(kPi * (row + 1) / h);
            for (int col = 0; col < w; ++col) {
                Eigen::Vector3d sum = Eigen::Vector3d::Zero();
                for (int a = 0; a < kSub; ++a) {
                    const double z = z0 + (a + 0.5) / kSub * (z1 - z0);
                    const double rr = std::sqrt(std::max(0.0, 1 - z * z));
                    for (int b = 0; b < kSub; ++b) {
                        const double phi = kPi * (1.0 - 2.0 * (col + (b + 0.5) / kSub) / w);
                        const Eigen::Vector3d d(rr * std::cos(phi), rr * std::sin(phi), z);
                        const Eigen::Vector2i t =
                            environment_texel(lo.layout, d, src.width, src.height);
                        for (int c = 0; c < 3; ++c) sum[c] += src.at(t[0], t[1], c);
                    }
                }
                for (int c = 0; c < 3; ++c) {
                    out.at(col, static_cast<int>(row), c) =
                        static_cast<float>(sum[c] / (kSub * kSub));
                }
            }
        }
    });
    return out;
}

EnvironmentLight::EnvironmentLight(const image::Image& latlong,
                                   const Eigen::Matrix3d& world_from_env, double intensity,
                                   const std::string& source)
    : m_width(latlong.width), m_height(latlong.height), m_world_from_env(world_from_env) {
    if (latlong.width != 2 * latlong.height || latlong.height < 1) {
        throw Error(
            str(source, ": expected a 2:1 lat-long map, got ", latlong.width, "x", latlong.height));
    }
    if (latlong.channels < 3) {
        throw Error(str(source, ": expected at least 3 channels (RGB), got ", latlong.channels));
    }
    if (latlong.color_space != image::ColorSpace::kLinearSrgb) {
        throw Error(str(source, ": expected linear_srgb radiance, got ",
                        image::to_string(latlong.color_space)));
    }
    if (!(intensity >= 0) || !std::isfinite(intensity)) {
        throw Error(str(source, ": intensity must be finite and >= 0, got ", intensity));
    }
    const double det = world_from_env.determinant();
    INLIGHT_CHECK(std::abs(det - 1.0) < 1e-9) << "world_from_env is not a rotation, det " << det;

    m_rgb.resize(static_cast<size_t>(m_width) * m_height * 3);
    m_row_solid_angle.resize(static_cast<size_t>(m_height));
    std::vector<double> weights(static_cast<size_t>(m_width) * m_height);
    for (int row = 0; row < m_height; ++row) {
        const double omega = latlong_pixel_solid_angle(row, m_width, m_height);
        m_row_solid_angle[static_cast<size_t>(row)] = omega;
        for (int col = 0; col < m_width; ++col) {
            double w = 0;
            for (int c = 0; c < 3; ++c) {
                const float v = latlong.at(col, row, c);
                if (!std::isfinite(v)) {
                    throw Error(str(source, ": non-finite radiance at pixel (", col, ", ", row,
                                    ") channel ", c));
                }
                const float scaled = static_cast<float>(v * intensity);
                m_rgb[(static_cast<size_t>(row) * m_width + col) * 3 + c] = scaled;
                static constexpr double kY[3] = {0.2126, 0.7152, 0.0722};  // Rec.709 luminance
                w += kY[c] * std::abs(static_cast<double>(scaled));
            }
            weights[static_cast<size_t>(row) * m_width + col] = w * omega;
        }
    }
    m_dist = Distribution2D(weights, m_width, m_height);
    m_pdf.assign(weights.size(), 0.0);
    if (m_dist.total() > 0) {
        for (int row = 0; row < m_height; ++row) {
            for (int col = 0; col < m_width; ++col) {
                m_pdf[static_cast<size_t>(row) * m_width + col] =
                    m_dist.pmf(col, row) / m_row_solid_angle[static_cast<size_t>(row)];
            }
        }
    }
}

EnvironmentLight EnvironmentLight::constant(const Eigen::Vector3d& radiance) {
    image::Image img(2, 1, 3);
    for (int col = 0; col < 2; ++col) {
        for (int c = 0; c < 3; ++c) img.at(col, 0, c) = static_cast<float>(radiance[c]);
    }
    return EnvironmentLight(img, Eigen::Matrix3d::Identity(), 1.0, "constant environment");
}

Eigen::Vector3d EnvironmentLight::pixel(int col, int row) const {
    const float* p = &m_rgb[(static_cast<size_t>(row) * m_width + col) * 3];
    return {p[0], p[1], p[2]};
}

Eigen::Vector2i EnvironmentLight::pixel_of(const Eigen::Vector3d& dir) const {
    const Eigen::Vector2d uv = latlong_uv(m_world_from_env.transpose() * dir);
    const int col = std::clamp(static_cast<int>(uv[0] * m_width), 0, m_width - 1);
    const int row = std::clamp(static_cast<int>(uv[1] * m_height), 0, m_height - 1);
    return {col, row};
}

Eigen::Vector3d EnvironmentLight::eval(const Eigen::Vector3d& dir) const {
    const Eigen::Vector2i p = pixel_of(dir);
    return pixel(p[0], p[1]);
}

EnvironmentLight::Sample EnvironmentLight::sample(const Eigen::Vector2d& u) const {
    Sample s;
    if (!(m_dist.total() > 0)) return s;
    int col = 0, row = 0;
    Eigen::Vector2d uc;
    m_dist.sample(u, &col, &row, &uc);
    const double z0 = std::cos(kPi * row / m_height);
    const double z1 = std::cos(kPi * (row + 1) / m_height);
    const double z = z0 + uc[1] * (z1 - z0);
    const double phi = kPi * (1.0 - 2.0 * (col + uc[0]) / m_width);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    s.dir = m_world_from_env * Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
    s.radiance = pixel(col, row);
    s.pdf = m_pdf[static_cast<size_t>(row) * m_width + col];
    return s;
}

double EnvironmentLight::pdf(const Eigen::Vector3d& dir) const {
    const Eigen::Vector2i p = pixel_of(dir);
    return m_pdf[static_cast<size_t>(p[1]) * m_width + p[0]];
}

Eigen::Vector3d EnvironmentLight::mean_radiance() const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int row = 0; row < m_height; ++row) {
        for (int col = 0; col < m_width; ++col) {
            sum += pixel(col, row) * m_row_solid_angle[static_cast<size_t>(row)];
        }
    }
    return sum / (4.0 * kPi);
}

}  // namespace inlight::render
