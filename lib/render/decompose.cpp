#include "render/decompose.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "render/realtime_lights.h"
#include "sh/sh.h"

namespace inlight::render {

namespace {

double luma(const Eigen::Vector3d& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/// A map pixel of the exact integrals: centre direction (world) and summed L Omega of its block.
struct MapSample {
    Eigen::Vector3d dir, l_omega;
};

/// The environment on a lat-long grid of about `height` rows: box-filtered by an integer factor
/// when the map is finer, or split into cells that each lie inside one map pixel (height a
/// multiple of the map's) when it is coarser, so the piecewise-constant map is kept exactly.
std::vector<MapSample> coarse_map(const EnvironmentLight& env, int height, int& w, int& h) {
    height = std::max(1, height);
    std::vector<MapSample> out;
    if (env.height() < height) {
        h = ((height + env.height() - 1) / env.height()) * env.height();
        w = 2 * h;
        for (int r = 0; r < h; ++r) {
            for (int c = 0; c < w; ++c) {
                const Eigen::Vector3d dir =
                    env.world_from_env() * latlong_direction((c + 0.5) / w, (r + 0.5) / h);
                out.push_back({dir, env.eval(dir) * latlong_pixel_solid_angle(r, w, h)});
            }
        }
        return out;
    }
    int f = std::max(1, env.height() / height);
    while (env.height() % f != 0 || env.width() % f != 0) --f;
    h = env.height() / f;
    w = env.width() / f;
    out.reserve(static_cast<size_t>(w) * static_cast<size_t>(h));
    for (int r = 0; r < h; ++r) {
        for (int c = 0; c < w; ++c) {
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            for (int y = r * f; y < (r + 1) * f; ++y)
                for (int x = c * f; x < (c + 1) * f; ++x)
                    sum += env.pixel(x, y) * env.pixel_solid_angle(y);
            out.push_back(
                {env.world_from_env() * latlong_direction((c + 0.5) / w, (r + 0.5) / h), sum});
        }
    }
    return out;
}

/// Diffuse irradiance integral sum L Omega max(0, n.w) (albedo / pi applied by the caller).
Eigen::Vector3d exact_irradiance(const std::vector<MapSample>& map, const Eigen::Vector3d& n) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    for (const auto& s : map) {
        const double c = n.dot(s.dir);
        if (c > 0) e += s.l_omega * c;
    }
    return e;
}

/// Specular integral sum L Omega f_s(n; view, w) max(0, n.w).
Eigen::Vector3d exact_specular(const std::vector<MapSample>& map, const Eigen::Vector3d& n,
                               const brdf::Material& m, const Eigen::Vector3d& view) {
    if (m.specular == brdf::Model::kLambert) return Eigen::Vector3d::Zero();
    const Eigen::Matrix3d local_from_world = brdf::world_from_local(n).transpose();
    const Eigen::Vector3d wo = local_from_world * view;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    if (wo.z() <= 0) return s;
    for (const auto& p : map) {
        const double c = n.dot(p.dir);
        if (c <= 0) continue;
        s += p.l_omega.cwiseProduct(brdf::eval_specular(m, wo, local_from_world * p.dir)) * c;
    }
    return s;
}

/// Per-pixel luminance of every term (averaged over the pixel's fragments).
struct Terms {
    /// [pixel * bands + b - 1]: M0 diffuse, M0 and M1 specular, of the SH part only.
    std::vector<double> d0, s0, s1;
    std::vector<double> d2, s2, s2r, s3, coarse;  ///< [pixel]
    /// [pixel]: the lights as the model shades them and their exact integrals as caps.
    std::vector<double> ld_model, ls_model, ld_exact, ls_exact;
};

std::vector<double> plus(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> out(a.size());
    for (size_t i = 0; i < a.size(); ++i) out[i] = a[i] + b[i];
    return out;
}

double rel_rms(const std::vector<double>& a, const std::vector<double>& b, double mean_y) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(sum / static_cast<double>(std::max<size_t>(1, a.size()))) / mean_y;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Eigen::Vector3d cap_specular_exact(const envmap::DirectionalLight& light, const Eigen::Vector3d& n,
                                   const Eigen::Vector3d& view, const brdf::Material& material) {
    if (material.specular == brdf::Model::kLambert) return Eigen::Vector3d::Zero();
    const Eigen::Matrix3d local_from_world = brdf::world_from_local(n).transpose();
    const Eigen::Vector3d wo = local_from_world * view;
    if (wo.z() <= 0) return Eigen::Vector3d::Zero();
    const Eigen::Vector3d d = light.direction.normalized();
    auto term = [&](const Eigen::Vector3d& w) -> Eigen::Vector3d {
        const double c = n.dot(w);
        if (c <= 0) return Eigen::Vector3d::Zero();
        return brdf::eval_specular(material, wo, local_from_world * w) * c;
    };
    const double one_minus_cos = 1 - std::cos(light.angular_radius);
    if (!(one_minus_cos > 0)) return light.flux.cwiseProduct(term(d));
    // Cells of equal solid angle Omega / N: the radiance Phi / Omega times it is Phi / N.
    const Eigen::Vector3d t1 = d.unitOrthogonal(), t2 = d.cross(t1);
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int i = 0; i < kCapQuadratureRings; ++i) {
        const double u = 1 - one_minus_cos * (i + 0.5) / kCapQuadratureRings;
        const double r = std::sqrt(std::max(0.0, 1 - u * u));
        for (int j = 0; j < kCapQuadratureSectors; ++j) {
            const double phi = 2 * kPi * (j + 0.5) / kCapQuadratureSectors;
            s += term(u * d + r * (std::cos(phi) * t1 + std::sin(phi) * t2));
        }
    }
    return light.flux.cwiseProduct(s) / (kCapQuadratureRings * kCapQuadratureSectors);
}

Decomposition decompose_error(const Scene& scene, const RenderResult& truth,
                              const RealtimeLighting& lighting, const DecomposeOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const int nb = options.max_bands;
    if (nb < 1 || sh::count(nb) > lighting.coeffs.rows())
        throw UsageError(str("decompose: max_bands ", nb, " needs that many lighting bands"));
    if (lighting.tables.size() != scene.desc().materials.size())
        throw UsageError("decompose: one BRDF table per material is needed");
    if (options.supersample < 1 || options.map_height < 2)
        throw UsageError("decompose: supersample must be >= 1 and map_height >= 2");
    const Camera& cam = scene.camera();
    const int w = cam.width_px, h = cam.height_px, ss = options.supersample;
    if (truth.radiance.width != w || truth.radiance.height != h)
        throw UsageError("decompose: the truth's size differs from the camera's");

    Decomposition d;
    const std::vector<MapSample> map =
        coarse_map(scene.environment(), options.map_height, d.map_width, d.map_height);
    int cw = 0, ch = 0;
    const std::vector<MapSample> half = coarse_map(scene.environment(), d.map_height / 2, cw, ch);
    const auto npx = static_cast<size_t>(w) * static_cast<size_t>(h);
    Terms t;
    for (auto* v : {&t.d0, &t.s0, &t.s1}) v->assign(npx * static_cast<size_t>(nb), 0.0);
    for (auto* v : {&t.d2, &t.s2, &t.s2r, &t.s3, &t.coarse, &t.ld_model, &t.ls_model,
                    &t.ld_exact, &t.ls_exact})
        v->assign(npx, 0.0);
    d.lights = static_cast<int>(lighting.lights.size());
    const double inv = 1.0 / (ss * ss);

    parallel::for_chunks(h, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < w; ++x) {
                const size_t p =
                    static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
                for (int sy = 0; sy < ss; ++sy) {
                    for (int sx = 0; sx < ss; ++sx) {
                        const Ray ray = cam.generate_ray(x + (sx + 0.5) / ss,
                                                         static_cast<double>(y) + (sy + 0.5) / ss);
                        SurfaceHit hit;
                        if (!scene.accel().intersect(ray, &hit)) {  // every model shows the map
                            const double bg = inv * luma(scene.environment().eval(ray.dir));
                            for (int b = 0; b < nb; ++b) t.d0[p * nb + b] += bg;
                            t.d2[p] += bg;
                            t.coarse[p] += bg;
                            continue;
                        }
                        const SurfaceMaterial& sm = scene.material(hit.shape);
                        const ShadingPoint sp = shade(sm, hit, -ray.dir);
                        const auto mi = static_cast<size_t>(scene.material_index(hit.shape));
                        const brdf::Table& table = lighting.tables[mi];
                        const Eigen::Vector3d n = sp.world_from_local.col(2);
                        const bool spec = sp.brdf.specular != brdf::Model::kLambert;
                        // M0 and M1 per band count.
                        Eigen::MatrixXd b_exact;
                        if (spec) {
                            brdf::BakeOptions bo = options.bake;
                            bo.sh_bands = table.sh_bands;
                            bo.view = table.view;
                            b_exact = brdf::project_normal(scene.desc().materials[mi].brdf, n, bo);
                        }
                        for (int b = 1; b <= nb; ++b) {
                            RealtimeOptions ro;
                            ro.sh_bands = b;
                            const Eigen::Vector3d diff = shade_realtime(
                                n, sp.brdf.albedo, false, lighting.coeffs, nullptr, ro);
                            const Eigen::Vector3d all = shade_realtime(n, sp.brdf.albedo, spec,
                                                                       lighting.coeffs, &table, ro);
                            Eigen::Vector3d s1 = Eigen::Vector3d::Zero();
                            if (spec) {
                                const int k_spec = sh::count(std::min(b, table.sh_bands));
                                for (int c = 0; c < 3; ++c)
                                    for (int k = 0; k < k_spec; ++k)
                                        s1[c] += lighting.coeffs(k, c) * b_exact(c, k);
                            }
                            const size_t i =
                                p * static_cast<size_t>(nb) + static_cast<size_t>(b - 1);
                            t.d0[i] += inv * luma(diff);
                            t.s0[i] += inv * luma(all - diff);
                            t.s1[i] += inv * luma(s1);
                        }
                        // The lights: as the model shades them (M0, M1) and as exact caps
                        // (M1x), with the fragment's material as the model uses.
                        for (const auto& l : lighting.lights) {
                            const Eigen::Vector3d albedo_pi = sp.brdf.albedo * kInvPi;
                            envmap::DirectionalLight cap = l;
                            cap.shading = envmap::LightShading::kCap;
                            t.ld_model[p] +=
                                inv * luma(albedo_pi.cwiseProduct(envmap::light_irradiance(l, n)));
                            t.ld_exact[p] += inv * luma(albedo_pi.cwiseProduct(
                                                       envmap::light_irradiance(cap, n)));
                            if (spec) {
                                t.ls_model[p] +=
                                    inv * luma(envmap::light_specular(l, n, table.view, sp.brdf));
                                t.ls_exact[p] +=
                                    inv * luma(cap_specular_exact(l, n, table.view, sp.brdf));
                            }
                        }
                        // M2, M2r, M3: exact integrals over the map.
                        const Eigen::Vector3d albedo_pi = sp.brdf.albedo * kInvPi;
                        const double d2 = luma(albedo_pi.cwiseProduct(exact_irradiance(map, n)));
                        brdf::Material base = scene.desc().materials[mi].brdf;  // the table's
                        base.albedo = sp.brdf.albedo;
                        const Eigen::Vector3d view = -ray.dir;
                        const double s2 = luma(exact_specular(map, n, base, table.view));
                        const bool textured =
                            base.alpha != sp.brdf.alpha || base.report_r != sp.brdf.report_r;
                        const double s2r =
                            textured ? luma(exact_specular(map, n, sp.brdf, table.view)) : s2;
                        const bool moved = (view - table.view).norm() > 1e-12;
                        const double s3 = moved ? luma(exact_specular(map, n, sp.brdf, view)) : s2r;
                        t.d2[p] += inv * d2;
                        t.s2[p] += inv * s2;
                        t.s2r[p] += inv * s2r;
                        t.s3[p] += inv * s3;
                        t.coarse[p] +=
                            inv * luma(albedo_pi.cwiseProduct(exact_irradiance(half, n)) +
                                       exact_specular(half, n, sp.brdf, view));
                    }
                }
            }
        }
    });

    // Luminance of the truth and the composite models.
    std::vector<double> yt(npx), m2(npx), m2r(npx), m3(npx);
    double mean_y = 0;
    for (size_t p = 0; p < npx; ++p) {
        const float* px = &truth.radiance.pixels[p * static_cast<size_t>(truth.radiance.channels)];
        yt[p] = luma({px[0], px[1], px[2]});
        mean_y += yt[p] / static_cast<double>(npx);
        m3[p] = t.d2[p] + t.s3[p];
    }
    if (!(mean_y > 0)) throw Error("decompose: the truth is black");
    d.mean_truth_luminance = mean_y;
    for (int b = 1; b <= nb; ++b) {
        std::vector<double> d0(npx), s0(npx), s1(npx), m0(npx);
        for (size_t p = 0; p < npx; ++p) {
            const size_t i = p * static_cast<size_t>(nb) + static_cast<size_t>(b - 1);
            d0[p] = t.d0[i];
            s0[p] = t.s0[i];
            s1[p] = t.s1[i];
            m0[p] = d0[p] + s0[p];
        }
        DecompositionBands db;
        db.sh_bands = b;
        // M0 adds the lights as the model shades them; M1x (= M1 without lights) their caps.
        db.total = rel_rms(plus(plus(m0, t.ld_model), t.ls_model), yt, mean_y);
        db.grid_interpolation = rel_rms(s0, s1, mean_y);
        db.sh_truncation_diffuse = rel_rms(plus(d0, t.ld_exact), t.d2, mean_y);
        db.sh_truncation_specular = rel_rms(plus(s1, t.ls_exact), t.s2, mean_y);
        d.by_bands.push_back(db);
    }
    d.light_shading_diffuse = rel_rms(t.ld_model, t.ld_exact, mean_y);
    d.light_shading_specular = rel_rms(t.ls_model, t.ls_exact, mean_y);
    d.roughness_texture = rel_rms(t.s2, t.s2r, mean_y);
    d.fixed_view = rel_rms(t.s2r, t.s3, mean_y);
    d.truth_noise = std::isfinite(truth.rel_error) ? truth.rel_error : 0.0;
    d.exact_vs_truth = rel_rms(m3, yt, mean_y);
    d.visibility = std::sqrt(
        std::max(0.0, d.exact_vs_truth * d.exact_vs_truth - d.truth_noise * d.truth_noise));
    d.map_discretisation = rel_rms(m3, t.coarse, mean_y);
    if (ss > 1) {
        RealtimeOptions ro;
        ro.sh_bands = std::min(3, nb);
        ro.supersample = ss;
        const image::Image a = render_realtime(scene, lighting, ro);
        ro.supersample = 4 * ss;
        const image::Image b = render_realtime(scene, lighting, ro);
        std::vector<double> ya(npx), yb(npx);
        for (size_t p = 0; p < npx; ++p) {
            ya[p] = luma({a.pixels[3 * p], a.pixels[3 * p + 1], a.pixels[3 * p + 2]});
            yb[p] = luma({b.pixels[3 * p], b.pixels[3 * p + 1], b.pixels[3 * p + 2]});
        }
        d.pixel_footprint = rel_rms(ya, yb, mean_y);
    }
    d.time_s = seconds_since(t0);
    return d;
}

nlohmann::json to_json(const Decomposition& d) {
    nlohmann::json bands = nlohmann::json::array();
    for (const auto& b : d.by_bands) {
        const double sum = b.grid_interpolation + b.sh_truncation_diffuse +
                           b.sh_truncation_specular + d.light_shading_diffuse +
                           d.light_shading_specular + d.roughness_texture + d.fixed_view +
                           d.visibility + d.truth_noise;
        const double model =
            std::sqrt(std::max(0.0, b.total * b.total - d.truth_noise * d.truth_noise));
        bands.push_back({{"sh_bands", b.sh_bands},
                         {"total", b.total},
                         {"model_error_noise_removed", model},
                         {"grid_interpolation", b.grid_interpolation},
                         {"sh_truncation_diffuse", b.sh_truncation_diffuse},
                         {"sh_truncation_specular", b.sh_truncation_specular},
                         {"sum_of_parts", sum},
                         {"noise_to_model_error", model > 0 ? d.truth_noise / model : 0.0}});
    }
    return {{"metric", "relative RMS of luminance: sqrt(mean (Y_a - Y_b)^2) / mean Y_truth"},
            {"by_sh_bands", bands},
            {"lights", d.lights},
            {"light_shading_diffuse", d.light_shading_diffuse},
            {"light_shading_specular", d.light_shading_specular},
            {"roughness_texture", d.roughness_texture},
            {"fixed_view", d.fixed_view},
            {"visibility", d.visibility},
            {"truth_noise", d.truth_noise},
            {"exact_unshadowed_vs_truth", d.exact_vs_truth},
            {"map_discretisation", d.map_discretisation},
            {"pixel_footprint", d.pixel_footprint},
            {"map_width", d.map_width},
            {"map_height", d.map_height},
            {"mean_truth_luminance", d.mean_truth_luminance},
            {"time_s", d.time_s}};
}

}  // namespace inlight::render
