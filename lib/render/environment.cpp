#include "render/environment.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/conventions.h"
#include "core/error.h"

namespace inlight::render {

image::Image load_latlong(const std::string& path) {
    image::Image img = image::read_image(path);
    if (img.width != 2 * img.height) {
        throw Error(str(path, ": expected a 2:1 lat-long map, got ", img.width, "x", img.height));
    }
    return img;
}

EnvironmentLight::EnvironmentLight(const image::Image& latlong,
                                   const Eigen::Matrix3d& world_from_env, double intensity,
                                   const std::string& source)
    : m_width(latlong.width), m_height(latlong.height), m_world_from_env(world_from_env) {
    if (latlong.width != 2 * latlong.height || latlong.height < 1) {
        throw Error(str(source, ": expected a 2:1 lat-long map, got ", latlong.width, "x",
                        latlong.height));
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
