#include "render/reference.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"

namespace inlight::render {

Eigen::Vector3d brute_force_irradiance(const EnvironmentLight& env, const Eigen::Vector3d& n,
                                       int sub) {
    const int w = env.width(), h = env.height();
    const Eigen::Vector3d n_env = env.world_from_env().transpose() * n;
    // Per cell column: the (cos phi, sin phi) of its centre, shared by every row.
    std::vector<double> cos_phi(static_cast<size_t>(w) * sub), sin_phi(cos_phi.size());
    for (int col = 0; col < w; ++col) {
        for (int b = 0; b < sub; ++b) {
            const double phi = kPi * (1.0 - 2.0 * (col + (b + 0.5) / sub) / w);
            cos_phi[static_cast<size_t>(col) * sub + b] = std::cos(phi);
            sin_phi[static_cast<size_t>(col) * sub + b] = std::sin(phi);
        }
    }
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    for (int row = 0; row < h; ++row) {
        const double z0 = std::cos(kPi * row / h), z1 = std::cos(kPi * (row + 1) / h);
        const double cell = env.pixel_solid_angle(row) / (sub * sub);
        for (int a = 0; a < sub; ++a) {
            const double z = z0 + (a + 0.5) / sub * (z1 - z0);
            const double r = std::sqrt(std::max(0.0, 1 - z * z));
            const double cz = n_env.z() * z, rx = r * n_env.x(), ry = r * n_env.y();
            // The horizon: a row whose every cell is below it adds nothing.
            if (cz + std::hypot(rx, ry) <= 0) continue;
            for (int col = 0; col < w; ++col) {
                double cos_sum = 0;
                for (int b = 0; b < sub; ++b) {
                    const size_t k = static_cast<size_t>(col) * sub + b;
                    const double c = cz + rx * cos_phi[k] + ry * sin_phi[k];
                    if (c > 0) cos_sum += c;
                }
                if (cos_sum > 0) e += env.pixel(col, row) * (cos_sum * cell);
            }
        }
    }
    return e;
}

IrradianceTable::IrradianceTable(const EnvironmentLight& env, int sub)
    : m_cols(env.width() * sub), m_rows(env.height() * sub),
      m_env_from_world(env.world_from_env().transpose()) {
    const int h = env.height();
    m_z.resize(static_cast<size_t>(m_rows));
    m_prefix.assign(static_cast<size_t>(m_rows) * (m_cols + 1) * 9, 0.0);
    for (int row = 0; row < h; ++row) {
        const double z0 = std::cos(kPi * row / h), z1 = std::cos(kPi * (row + 1) / h);
        const double cell = env.pixel_solid_angle(row) / (sub * sub);
        for (int a = 0; a < sub; ++a) {
            const int r = row * sub + a;
            const double z = z0 + (a + 0.5) / sub * (z1 - z0);
            m_z[static_cast<size_t>(r)] = z;
            const double rho = std::sqrt(std::max(0.0, 1 - z * z));
            double* p = &m_prefix[static_cast<size_t>(r) * (m_cols + 1) * 9];
            for (int j = 0; j < m_cols; ++j) {
                const double phi = kPi * (1.0 - 2.0 * (j + 0.5) / m_cols);
                const Eigen::Vector3d l = env.pixel(j / sub, row) * cell;
                for (int c = 0; c < 3; ++c) {
                    p[(j + 1) * 9 + c] = p[j * 9 + c] + l[c];
                    p[(j + 1) * 9 + 3 + c] = p[j * 9 + 3 + c] + l[c] * rho * std::cos(phi);
                    p[(j + 1) * 9 + 6 + c] = p[j * 9 + 6 + c] + l[c] * rho * std::sin(phi);
                }
            }
        }
    }
}

Eigen::Vector3d IrradianceTable::irradiance(const Eigen::Vector3d& n) const {
    const Eigen::Vector3d ne = m_env_from_world * n;
    const double rxy = std::hypot(ne.x(), ne.y()), phi0 = std::atan2(ne.y(), ne.x());
    const double two_pi = 2 * kPi;
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    for (int r = 0; r < m_rows; ++r) {
        const double z = m_z[static_cast<size_t>(r)];
        const double rho = std::sqrt(std::max(0.0, 1 - z * z));
        const double cz = ne.z() * z, amp = rxy * rho;  // c(phi) = cz + amp cos(phi - phi0)
        if (cz + amp <= 0) continue;                    // the whole row below the horizon
        const double* p = &m_prefix[static_cast<size_t>(r) * (m_cols + 1) * 9];
        // Sums of the 9 values over columns [j0, j1) (0 <= j0 <= j1 <= m_cols).
        double s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        auto add = [&](int j0, int j1) {
            for (int k = 0; k < 9; ++k) s[k] += p[j1 * 9 + k] - p[j0 * 9 + k];
        };
        if (cz - amp >= 0) {
            add(0, m_cols);  // the whole row above it
        } else {
            // Cells with |phi_j - phi0| < delta (mod 2 pi); phi_j = pi - 2 pi (j + 0.5) / cols,
            // so j + 0.5 = (pi - phi) cols / (2 pi): the open interval (ta, tb) of j.
            const double delta = std::acos(std::clamp(-cz / amp, -1.0, 1.0));
            const double ta = (kPi - phi0 - delta) * m_cols / two_pi - 0.5;
            const double tb = ta + delta * m_cols / kPi;
            auto lo = static_cast<int64_t>(std::floor(ta)) + 1;
            auto hi = static_cast<int64_t>(std::ceil(tb));  // exclusive
            if (hi - lo > m_cols) hi = lo + m_cols;
            if (hi > lo) {
                const int64_t shift = ((lo % m_cols) + m_cols) % m_cols - lo;
                lo += shift;
                hi += shift;
                if (hi <= m_cols) {
                    add(static_cast<int>(lo), static_cast<int>(hi));
                } else {
                    add(static_cast<int>(lo), m_cols);
                    add(0, static_cast<int>(hi - m_cols));
                }
            }
        }
        for (int c = 0; c < 3; ++c) e[c] += cz * s[c] + ne.x() * s[3 + c] + ne.y() * s[6 + c];
    }
    return e;
}

int brute_force_subdivision(int height) {
    const double pixel_deg = 180.0 / std::max(1, height);
    return std::max(1, static_cast<int>(std::ceil(pixel_deg / kMaxCellDeg - 1e-9)));
}

std::vector<uint8_t> object_pixels(const Scene& scene) {
    const Camera& cam = scene.camera();
    std::vector<uint8_t> mask(static_cast<size_t>(cam.width_px) * cam.height_px, 0);
    parallel::for_chunks(cam.height_px, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < cam.width_px; ++x) {
                SurfaceHit hit;
                const Ray ray = cam.generate_ray(x + 0.5, static_cast<double>(y) + 0.5);
                mask[static_cast<size_t>(y) * cam.width_px + x] = scene.accel().intersect(ray, &hit);
            }
        }
    });
    return mask;
}

ConvergenceReference irradiance_reference(const Scene& scene) {
    const SceneDesc& d = scene.desc();
    const auto refuse = [&d](const std::string& why) {
        return UsageError(str(d.source.empty() ? "scene" : d.source,
                              ": the brute-force irradiance reference needs one untextured "
                              "Lambert sphere (no interreflection): ", why));
    };
    if (d.objects.size() != 1 || d.objects[0].shape.kind != ShapeKind::kSphere)
        throw refuse("the scene must hold exactly one object, a sphere");
    const SurfaceMaterial& m = scene.material(0);
    if (m.brdf.specular != brdf::Model::kLambert) throw refuse(str("material '", m.name, "' is not lambert"));
    if (m.albedo_texture || m.normal_texture || m.roughness_texture)
        throw refuse(str("material '", m.name, "' has a texture"));
    const Camera& cam = scene.camera();
    const EnvironmentLight& env = scene.environment();
    const IrradianceTable table(env, brute_force_subdivision(env.height()));
    ConvergenceReference ref;
    ref.kind = "brute_force_irradiance";
    ref.radiance = image::Image(cam.width_px, cam.height_px, 3, image::ColorSpace::kLinearSrgb);
    ref.std_error = image::Image(cam.width_px, cam.height_px, 3, image::ColorSpace::kData);
    ref.object_mask = object_pixels(scene);
    const Eigen::Vector3d albedo_over_pi = m.brdf.albedo * kInvPi;
    parallel::for_chunks(cam.height_px, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < cam.width_px; ++x) {
                const Ray ray = cam.generate_ray(x + 0.5, static_cast<double>(y) + 0.5);
                SurfaceHit hit;
                const Eigen::Vector3d l =
                    scene.accel().intersect(ray, &hit)
                        ? Eigen::Vector3d(albedo_over_pi.cwiseProduct(
                              table.irradiance(hit.ng)))
                        : env.eval(ray.dir);
                for (int c = 0; c < 3; ++c) ref.radiance.at(x, static_cast<int>(y), c) = static_cast<float>(l[c]);
            }
        }
    });
    return ref;
}

ConvergenceReference file_reference(const Scene& scene, const std::string& path) {
    const Camera& cam = scene.camera();
    auto read = [&cam](const std::string& file) {
        image::Image img = image::read_image(file);
        if (img.width != cam.width_px || img.height != cam.height_px || img.channels < 3)
            throw Error(str(file, ": reference is ", img.width, "x", img.height, "x",
                            img.channels, ", the render is ", cam.width_px, "x", cam.height_px,
                            "x3"));
        image::Image rgb(img.width, img.height, 3, img.color_space);
        for (size_t i = 0; i < static_cast<size_t>(img.width) * img.height; ++i) {
            for (size_t c = 0; c < 3; ++c) {
                const float v = img.pixels[i * img.channels + c];
                if (!std::isfinite(v))
                    throw Error(str(file, ": pixel ", i % img.width, ",", i / img.width,
                                    " is not finite"));
                rgb.pixels[i * 3 + c] = v;
            }
        }
        return rgb;
    };
    ConvergenceReference ref;
    ref.kind = "file";
    ref.radiance = read(path);
    const std::filesystem::path p(path);
    const std::string se = (p.parent_path() / (p.stem().string() + "_stderr.exr")).string();
    ref.std_error = std::filesystem::exists(se)
                        ? read(se)
                        : image::Image(cam.width_px, cam.height_px, 3, image::ColorSpace::kData);
    ref.object_mask = object_pixels(scene);
    return ref;
}

}  // namespace inlight::render
