#include "render/realtime.h"

#include <algorithm>
#include <cmath>

#include "brdf/bake.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/log.h"
#include "core/parallel.h"
#include "envmap/project.h"
#include "render/mip.h"
#include "render/realtime_lights.h"
#include "sh/sh.h"

namespace inlight::render {

constexpr EnumName<RealtimeMode> kRealtimeModeNames[] = {{RealtimeMode::kConsistent, "consistent"},
                                                         {RealtimeMode::kSeed, "seed"}};

RealtimeMode realtime_mode_from_string(const std::string& name) {
    return enum_from_string(kRealtimeModeNames, name, "real-time mode");
}

std::string to_string(RealtimeMode mode) { return enum_to_string(kRealtimeModeNames, mode); }

Eigen::MatrixXd project_environment(const EnvironmentLight& env, int sh_bands) {
    image::Image img(env.width(), env.height(), 3);
    for (int row = 0; row < env.height(); ++row) {
        for (int col = 0; col < env.width(); ++col) {
            const Eigen::Vector3d p = env.pixel(col, row);
            for (int c = 0; c < 3; ++c) img.at(col, row, c) = static_cast<float>(p[c]);
        }
    }
    envmap::Environment e;
    e.layout = envmap::Layout::kLatLong;
    e.radiance = std::move(img);
    e.world_from_input = env.world_from_env();
    envmap::ProjectOptions po;
    po.sh_bands = sh_bands;
    return envmap::project(e, po).coeffs;
}

namespace {

/// The report's shader, section 2.6, for one channel: M is the channel's irradiance matrix
/// (built from L exactly as sh::irradiance_matrix), brdf[0..9) the BRDF coefficients at n.
double seed_specular(const Eigen::Matrix4d& m_in, const float* brdf, const Eigen::Vector4d& n4) {
    // GLSL indexes mat4 as [column][row]; M and the products are symmetric, so [i][j] = (i, j).
    const double c5l20 = (m_in(2, 2) / 0.743125) * 0.247708;
    const double c4l00 = m_in(3, 3) + c5l20;
    static constexpr int kIndex[4][4] = {{8, 4, 7, 3}, {4, 8, 5, 1}, {7, 5, 6, 2}, {3, 1, 2, -1}};
    Eigen::Matrix4d m;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            m(i, j) = kIndex[i][j] >= 0 ? m_in(i, j) * brdf[kIndex[i][j]] : 0.0;
        }
    }
    m(3, 3) = c4l00 * brdf[0] - c5l20 * brdf[6];
    return n4.dot(m * n4);
}

}  // namespace

namespace {

/// What the shader receives as uniforms: per-frame, not per-fragment.
struct Uniforms {
    Eigen::Matrix4d matrices[3];  ///< R&H irradiance matrix per channel (3 bands)
    Eigen::MatrixXd a_l;          ///< A_l L_lm per channel, for the series at other band counts
    const Eigen::MatrixXd* coeffs = nullptr;
};

Uniforms make_uniforms(const Eigen::MatrixXd& coeffs, int bands) {
    Uniforms u;
    u.coeffs = &coeffs;
    if (coeffs.rows() >= 9) {
        for (int c = 0; c < 3; ++c) u.matrices[c] = sh::irradiance_matrix(coeffs.col(c).data());
    }
    u.a_l = coeffs.topRows(sh::count(bands));
    for (int l = 0; l < bands; ++l) {
        u.a_l.middleRows(l * l, 2 * l + 1) *= sh::cosine_zonal(l);
    }
    return u;
}

/// The band l of SH coefficient k = l (l + 1) + m.
int band_of(int k) {
    int l = static_cast<int>(std::sqrt(static_cast<double>(k)));
    while (l * l > k) --l;
    while ((l + 1) * (l + 1) <= k) ++l;
    return l;
}

Eigen::Vector3d shade_fragment(const Eigen::Vector3d& n, const Eigen::Vector3d& albedo,
                               bool has_specular, const Uniforms& u, const brdf::Table* table,
                               const RealtimeOptions& options, double normal_length) {
    const int bands = options.sh_bands;
    const Eigen::MatrixXd& coeffs = *u.coeffs;
    const Eigen::Vector4d n4(n.x(), n.y(), n.z(), 1.0);
    float b[3][sh::count(brdf::kMaxBakeBands)] = {};
    const bool specular = has_specular && table != nullptr;
    int k_spec = 0;
    const bool seed = options.mode == RealtimeMode::kSeed;
    if (specular) {
        k_spec = sh::count(std::min(bands, table->sh_bands));
        // The report's getBRDF takes phi = atan(y / x), which loses the quadrant: a normal with
        // x < 0 reads the table at its mirror (-x, -y, z). (At x = y = 0 it divides 0 by 0; the
        // pole's value, the limit from every side, is taken there.)
        const Eigen::Vector3d nb = seed && n.x() < 0 ? Eigen::Vector3d(-n.x(), -n.y(), n.z()) : n;
        for (int c = 0; c < table->channels; ++c) lookup(*table, nb.cast<float>(), c, b[c]);
    }
    auto table_channel = [&](int c) { return table && table->channels == 3 ? c : 0; };

    Eigen::Vector3d out;
    if (seed) {
        // The report's L_lm carry the Condon-Shortley phase of its Figure 6 while its matrix
        // (R&H eq. 12) assumes none: the odd-m terms change sign, E(x, y, z) -> E(-x, -y, z).
        // (In the specular products L_lm B_lm the phases of L and B cancel.)
        const Eigen::Vector4d n4_slip(-n.x(), -n.y(), n.z(), 1.0);
        double mean_irradiance = 0;
        Eigen::Vector3d spec = Eigen::Vector3d::Zero();
        for (int c = 0; c < 3; ++c) {
            mean_irradiance += n4_slip.dot(u.matrices[c] * n4_slip) / 3.0;
            if (specular) spec[c] = seed_specular(u.matrices[c], b[table_channel(c)], n4) * 0.05;
        }
        return albedo * (mean_irradiance * 0.3) + spec;
    }
    // Band factors of the normal's spread (1 when there is none: the plain sums below).
    const bool spread = options.normal_variance != NormalVariance::kNone && normal_length < 1;
    const double inv_kappa = spread ? vmf_inv_kappa(normal_length) : 0.0;
    double f_diffuse[sh::kMaxBands], f_spec[brdf::kMaxBakeBands];
    for (int l = 0; l < sh::kMaxBands; ++l) f_diffuse[l] = vmf_band_factor(l, inv_kappa);
    const bool spec_spread = spread && options.normal_variance == NormalVariance::kDiffuseSpecular;
    for (int l = 0; l < brdf::kMaxBakeBands; ++l)
        f_spec[l] = vmf_band_factor(l, spec_spread ? options.specular_spread * inv_kappa : 0.0);
    double y[sh::count(sh::kMaxBands)];
    if (bands != 3 || spread) sh::eval(bands, n, y);
    for (int c = 0; c < 3; ++c) {
        double e = 0;
        if (bands == 3) {
            e = n4.dot(u.matrices[c] * n4);
            if (spread) {
                // Bands 0 and 1 of E apart, band 2 the rest: f2 E + (1 - f2) E0 + (f1 - f2) E1.
                const double e0 = u.a_l(0, c) * y[0];
                const double e1 = u.a_l(1, c) * y[1] + u.a_l(2, c) * y[2] + u.a_l(3, c) * y[3];
                e = f_diffuse[2] * e + (1 - f_diffuse[2]) * e0 + (f_diffuse[1] - f_diffuse[2]) * e1;
            }
        } else {
            for (int k = 0; k < sh::count(bands); ++k)
                e += u.a_l(k, c) * y[k] * f_diffuse[band_of(k)];
        }
        double s = 0;
        const double* l = coeffs.col(c).data();
        const float* bc = b[table_channel(c)];
        for (int k = 0; k < k_spec; ++k) s += l[k] * bc[k] * f_spec[band_of(k)];
        out[c] = albedo[c] * kInvPi * e + s;
    }
    return out;
}

}  // namespace

Eigen::Vector2d primitive_uv(const Scene& scene, const SurfaceHit& hit, const Ray& ray) {
    const Shape& s = scene.accel().shapes().at(static_cast<size_t>(hit.shape));
    if (s.kind == ShapeKind::kPatch) {  // the plane z = centre z, uv affine in x and y
        const double t = (s.center.z() - ray.origin.z()) / ray.dir.z();
        const Eigen::Vector3d p = ray.origin + t * ray.dir;
        return {(p.x() - (s.center.x() - 0.5 * s.size.x())) / s.size.x(),
                ((s.center.y() + 0.5 * s.size.y()) - p.y()) / s.size.y()};
    }
    if (s.kind == ShapeKind::kMesh) {
        const TriangleMesh& mesh = *s.mesh;
        if (mesh.uvs.empty()) return hit.uv;
        const Eigen::Vector3i tri = mesh.triangles.at(static_cast<size_t>(hit.prim));
        const Eigen::Vector3d& p0 = mesh.positions[static_cast<size_t>(tri[0])];
        const Eigen::Vector3d& p1 = mesh.positions[static_cast<size_t>(tri[1])];
        const Eigen::Vector3d& p2 = mesh.positions[static_cast<size_t>(tri[2])];
        const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
        const double t = n.dot(p0 - ray.origin) / n.dot(ray.dir);
        const Eigen::Vector3d p = ray.origin + t * ray.dir;
        // Barycentrics on the triangle's plane (outside it too: the extrapolation).
        const double inv = 1.0 / n.squaredNorm();
        const double b1 = n.dot((p - p0).cross(p2 - p0)) * inv;
        const double b2 = n.dot((p1 - p0).cross(p - p0)) * inv;
        return (1 - b1 - b2) * mesh.uvs[static_cast<size_t>(tri[0])] +
               b1 * mesh.uvs[static_cast<size_t>(tri[1])] + b2 * mesh.uvs[static_cast<size_t>(tri[2])];
    }
    // Curved shapes (no plane; a GPU draws their tessellation): the ray's own hit on the same
    // shape, else the uv at `hit` (no derivative).
    SurfaceHit next;
    return scene.accel().intersect(ray, &next) && next.shape == hit.shape ? next.uv : hit.uv;
}

Eigen::Vector3d shade_realtime(const Eigen::Vector3d& n, const Eigen::Vector3d& albedo,
                               bool has_specular, const Eigen::MatrixXd& coeffs,
                               const brdf::Table* table, const RealtimeOptions& options,
                               double normal_length) {
    return shade_fragment(n, albedo, has_specular, make_uniforms(coeffs, options.sh_bands), table,
                          options, normal_length);
}

image::Image render_realtime(const Scene& scene, const RealtimeLighting& lighting,
                             const RealtimeOptions& options) {
    if (options.sh_bands < 1 || sh::count(options.sh_bands) > lighting.coeffs.rows()) {
        throw UsageError(str("real-time model: ", log::count(options.sh_bands, "band"),
                             " asked, lighting has ", log::count(lighting.coeffs.rows(), "coefficient")));
    }
    if (options.mode == RealtimeMode::kSeed && options.sh_bands != 3) {
        throw UsageError(
            str("real-time model: the seed (report) mode exists for 3 bands only, got ",
                options.sh_bands));
    }
    if (options.mode == RealtimeMode::kSeed && !lighting.lights.empty())
        throw UsageError("real-time model: the seed (report) mode has no analytic lights");
    if (options.supersample < 1) throw UsageError("real-time model: supersample must be >= 1");
    if (!(options.specular_spread > 0) || !std::isfinite(options.specular_spread))
        throw UsageError("real-time model: specular_spread must be a finite number > 0");
    const Camera& cam = scene.camera();
    const int w = cam.width_px, h = cam.height_px, ss = options.supersample;
    image::Image img(w, h, 3, image::ColorSpace::kLinearSrgb);
    const Uniforms uniforms = make_uniforms(lighting.coeffs, options.sh_bands);
    // Mip atlases of the material textures, as the exported variant ships them (8-bit levels).
    const bool trilinear = options.texture_filter == TextureFilter::kTrilinear;
    std::vector<MipAtlas> albedo_mips(scene.materials().size()), normal_mips(albedo_mips.size());
    if (trilinear) {
        for (size_t i = 0; i < albedo_mips.size(); ++i) {
            const SurfaceMaterial& m = scene.materials()[i];
            if (m.albedo_texture)
                albedo_mips[i] = build_mip_atlas(*m.albedo_texture, TextureKind::kColor, true,
                                                  options.mip_filter);
            if (m.normal_texture)
                normal_mips[i] = build_mip_atlas(*m.normal_texture, TextureKind::kNormalMap, true,
                                                  options.mip_filter);
        }
    }
    // The GPU's uv derivatives (render/mip.h, "Derivatives"): differences across the 2 x 2
    // quad of the fragment grid (ss fragments per pixel side), columns paired from the left,
    // rows from the bottom (GL's window y), the partner's uv read on the hit primitive's plane.
    const int grid_h = h * ss;
    auto fragment_ray = [&](int gx, int gy) { return cam.generate_ray((gx + 0.5) / ss, (gy + 0.5) / ss); };
    auto quad_duv = [&](int gx, int gy, const SurfaceHit& at, Eigen::Vector2d* dx, Eigen::Vector2d* dy) {
        const int px = gx ^ 1, py = grid_h - 1 - ((grid_h - 1 - gy) ^ 1);
        // (A partner outside an odd-sized image is a helper fragment too: its ray all the same.)
        *dx = primitive_uv(scene, at, fragment_ray(px, gy)) - at.uv;
        *dy = primitive_uv(scene, at, fragment_ray(gx, py)) - at.uv;
    };
    parallel::for_chunks(h, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < w; ++x) {
                Eigen::Vector3d sum = Eigen::Vector3d::Zero();
                for (int sy = 0; sy < ss; ++sy) {
                    for (int sx = 0; sx < ss; ++sx) {
                        const int gx = x * ss + sx, gy = static_cast<int>(y) * ss + sy;
                        const Ray ray = fragment_ray(gx, gy);
                        SurfaceHit hit;
                        if (!scene.accel().intersect(ray, &hit)) {
                            sum += scene.environment().eval(ray.dir);
                            continue;
                        }
                        const SurfaceMaterial& m = scene.material(hit.shape);
                        const auto mi = static_cast<size_t>(scene.material_index(hit.shape));
                        FilteredLookup fl;
                        if (trilinear && (m.albedo_texture || m.normal_texture)) {
                            fl.albedo = m.albedo_texture ? &albedo_mips[mi] : nullptr;
                            fl.normal = m.normal_texture ? &normal_mips[mi] : nullptr;
                            quad_duv(gx, gy, hit, &fl.duv_dx, &fl.duv_dy);
                            fl.box_matched_lod = options.box_matched_lod;
                        }
                        const brdf::Table* table =
                            mi < lighting.tables.size() ? &lighting.tables[mi] : nullptr;
                        // The model's view is the table's (else +z, the device's), as the
                        // exported shader's VIEW: it also decides when a mapped normal faces
                        // away and falls back to the geometric one.
                        const Eigen::Vector3d model_view =
                            table ? table->view.normalized() : Eigen::Vector3d::UnitZ();
                        const ShadingPoint sp = shade(m, hit, model_view, trilinear ? &fl : nullptr);
                        const Eigen::Vector3d n = sp.world_from_local.col(2);
                        const bool has_specular = sp.brdf.specular != brdf::Model::kLambert;
                        sum += shade_fragment(n, sp.brdf.albedo, has_specular, uniforms, table,
                                              options, sp.normal_length);
                        if (!lighting.lights.empty())
                            sum += shade_lights(lighting.lights, n, sp.brdf,
                                                has_specular && table ? &table->view : nullptr);
                    }
                }
                sum /= static_cast<double>(ss * ss);
                for (int c = 0; c < 3; ++c)
                    img.at(x, static_cast<int>(y), c) = static_cast<float>(sum[c]);
            }
        }
    });
    return img;
}

}  // namespace inlight::render
