#include "envmap/light_fit.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "envmap/validate.h"
#include "sh/sh.h"

namespace inlight::envmap {

namespace {

/// P_0 .. P_n at t (Bonnet's recurrence).
std::vector<double> legendre(int n, double t) {
    std::vector<double> p(static_cast<size_t>(n + 1));
    p[0] = 1;
    if (n > 0) p[1] = t;
    for (int l = 2; l <= n; ++l)
        p[static_cast<size_t>(l)] = ((2 * l - 1) * t * p[static_cast<size_t>(l - 1)] -
                                     (l - 1) * p[static_cast<size_t>(l - 2)]) /
                                    l;
    return p;
}

// Below this radius the closed form of k_l cancels (P_{l-1} - P_{l+1} over 1 - cos alpha ~ 5e-7):
// the cap's mean of P_l(t) ~ 1 - l(l+1)(1 - t)/2 gives k_l = 1 - l(l+1)(1 - cos alpha)/4, whose
// next term, O((l^2 (1 - cos alpha))^2) < 1e-8 for l < 64, is below double-rounded use.
constexpr double kSeriesRadius = 1e-3;

/// One light's geometry and its high-pass irradiance per unit flux.
struct Lobe {
    Eigen::Vector3d direction;
    double alpha;
    std::vector<double> low;  ///< A_l k_l(alpha) (2l + 1) / (4 pi), l < sh_bands

    LightShading shading;
    Lobe(const Eigen::Vector3d& d, double a, int sh_bands, LightShading sh_)
        : direction(d), alpha(a), shading(sh_) {
        const std::vector<double> k = cap_zonal_factors(sh_bands, a);
        for (int l = 0; l < sh_bands; ++l)
            low.push_back(sh::cosine_zonal(l) * k[static_cast<size_t>(l)] * (2 * l + 1) /
                          (4 * kPi));
    }
    /// H_b[e](n . d) for unit flux.
    double high_pass(const Eigen::Vector3d& n) const {
        DirectionalLight unit;
        unit.direction = direction;
        unit.flux = Eigen::Vector3d::Ones();
        unit.angular_radius = alpha;
        unit.shading = shading;
        const double t = std::clamp(n.dot(direction), -1.0, 1.0);
        const std::vector<double> p = legendre(static_cast<int>(low.size()), t);
        double e = light_irradiance(unit, n)[0];
        for (size_t l = 0; l < low.size(); ++l) e -= low[l] * p[l];
        return e;
    }
};

/// Columns H_b[e_j](n_i) for each light.
Eigen::MatrixXd design(const std::vector<Lobe>& lobes, const std::vector<Eigen::Vector3d>& normals) {
    Eigen::MatrixXd h(static_cast<Eigen::Index>(normals.size()),
                      static_cast<Eigen::Index>(lobes.size()));
    for (size_t j = 0; j < lobes.size(); ++j)
        for (size_t i = 0; i < normals.size(); ++i)
            h(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
                lobes[j].high_pass(normals[i]);
    return h;
}

/// Per light: direction, radius and luminance flux; the LM moves them.
struct Geometry {
    std::vector<Eigen::Vector3d> direction;
    std::vector<double> alpha, flux_y;
};

/// A cap moved by p[0], p[1] (tangent offsets of its direction) and p[2] (its radius, kept in
/// [0, alpha_max]).
void move_cap(const Eigen::Vector3d& d, double alpha, const double* p, double alpha_max,
              Eigen::Vector3d& d_out, double& alpha_out) {
    const Eigen::Vector3d t1 = d.unitOrthogonal();
    const Eigen::Vector3d t2 = d.cross(t1);
    d_out = (d + p[0] * t1 + p[1] * t2).normalized();
    alpha_out = std::clamp(alpha + p[2], 0.0, alpha_max);
}

/// The last columns computed for each light of one fit, keyed by the light's index and the exact
/// bits of its direction and radius. The LM's central differences move one parameter at a time
/// (levenberg_marquardt below): a light they do not move gets the same direction and radius, bit
/// for bit, in all but two of its 2 x (parameters) evaluations, so its column (a few hundred
/// cosines and square roots) is looked up, not recomputed. A column is a function of exactly that
/// key within one fit, so the result is bit-identical to recomputing it.
class ColumnCache {
  public:
    template <typename Compute>
    const Eigen::VectorXd& get(int light, const Eigen::Vector3d& d, double alpha, Compute&& compute) {
        for (auto& e : m_entries)
            if (e.light == light && e.direction == d && e.alpha == alpha) return e.column;
        if (m_entries.size() >= kCapacity) m_entries.erase(m_entries.begin());
        m_entries.push_back({light, d, alpha, compute()});
        return m_entries.back().column;
    }

  private:
    // Per light: the unmoved state's column and those of the latest trials (oldest dropped).
    static constexpr size_t kCapacity = 64;
    struct Entry {
        int light;
        Eigen::Vector3d direction;
        double alpha;
        Eigen::VectorXd column;
    };
    std::vector<Entry> m_entries;
};

/// Levenberg-Marquardt on `state` (np parameters moved by moved(state, step)) minimising
/// |residual(state)|^2, whose value at the start is `cost` (updated). Returns the iterations.
template <typename State, typename Residual, typename Move>
int levenberg_marquardt(State& g, int np, const Residual& residual, const Move& moved,
                        int max_iterations, double& cost) {
    // Central differences: the step (radians, or relative flux) is far above the rounding of the
    // residual (~1e-16 relative) and below the curvature's scale (the cap's horizon band, >= the
    // radius; radii under the step act as points).
    constexpr double kStep = 1e-4;
    double damping = 1e-3;
    int iterations = 0;
    for (int it = 0; it < max_iterations; ++it) {
        const Eigen::VectorXd r0 = residual(g);
        Eigen::MatrixXd jac(r0.size(), np);
        for (int q = 0; q < np; ++q) {
            Eigen::VectorXd p = Eigen::VectorXd::Zero(np);
            p[q] = kStep;
            const Eigen::VectorXd rp = residual(moved(g, p));
            p[q] = -kStep;
            jac.col(q) = (rp - residual(moved(g, p))) / (2 * kStep);
        }
        const Eigen::MatrixXd a = jac.transpose() * jac;
        const Eigen::VectorXd grad = jac.transpose() * r0;
        bool improved = false;
        for (int attempt = 0; attempt < 12 && !improved; ++attempt) {
            Eigen::MatrixXd ad = a;
            for (int q = 0; q < np; ++q) ad(q, q) = a(q, q) * (1 + damping) + 1e-15;
            const Eigen::VectorXd step = -ad.ldlt().solve(grad);
            if (!step.allFinite()) break;
            const State trial = moved(g, step);
            const double c = residual(trial).squaredNorm();
            if (c < cost) {
                // Stop once a step gains under 1e-9 of the cost: the optimum to double precision.
                const bool converged = cost - c < 1e-9 * cost;
                g = trial;
                cost = c;
                damping = std::max(damping * 0.3, 1e-9);
                improved = !converged;
                if (converged) it = max_iterations;
            } else {
                damping *= 10;
            }
        }
        iterations = it + 1;
        if (!improved) break;
    }
    return iterations;
}

}  // namespace

std::pair<DirectionalLight, DirectionalLight> split_light(const DirectionalLight& light, int axis) {
    const Eigen::Vector3d t1 = light.direction.unitOrthogonal();
    const Eigen::Vector3d t = axis == 0 ? t1 : Eigen::Vector3d(light.direction.cross(t1));
    const double offset = std::max(light.angular_radius, kMinSplitRadius) / 2;
    std::pair<DirectionalLight, DirectionalLight> out{light, light};
    out.first.direction = (light.direction + std::tan(offset) * t).normalized();
    out.second.direction = (light.direction - std::tan(offset) * t).normalized();
    out.first.angular_radius = out.second.angular_radius = light.angular_radius / 2;
    out.first.flux = out.second.flux = light.flux / 2;
    return out;
}

std::vector<double> cap_zonal_factors(int sh_bands, double alpha) {
    if (sh_bands < 1) throw UsageError("cap_zonal_factors: sh_bands must be >= 1");
    std::vector<double> k(static_cast<size_t>(sh_bands), 1.0);
    const double one_minus_c = 1 - std::cos(alpha);
    if (alpha < kSeriesRadius) {
        for (int l = 1; l < sh_bands; ++l)
            k[static_cast<size_t>(l)] = 1 - l * (l + 1) * one_minus_c / 4;
        return k;
    }
    const std::vector<double> p = legendre(sh_bands, std::cos(alpha));
    for (int l = 1; l < sh_bands; ++l)
        k[static_cast<size_t>(l)] =
            (p[static_cast<size_t>(l - 1)] - p[static_cast<size_t>(l + 1)]) /
            ((2 * l + 1) * one_minus_c);
    return k;
}

Eigen::MatrixXd cap_coefficients(const DirectionalLight& light, int sh_bands) {
    const std::vector<double> k = cap_zonal_factors(sh_bands, light.angular_radius);
    const std::vector<double> y = sh::eval(sh_bands, light.direction);
    Eigen::MatrixXd c(sh::count(sh_bands), 3);
    for (int l = 0; l < sh_bands; ++l)
        for (int m = -l; m <= l; ++m) {
            const auto i = static_cast<size_t>(sh::index(l, m));
            c.row(static_cast<Eigen::Index>(i)) =
                (k[static_cast<size_t>(l)] * y[i]) * light.flux.transpose();
        }
    return c;
}

std::vector<Eigen::Vector3d> fit_normals(int count) {
    // Any rotation that moves the axes and the Fibonacci lattice off themselves will do.
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    std::vector<Eigen::Vector3d> out = validation_normals(count);
    for (auto& n : out) n = turn * n;
    return out;
}

LightFitResult fit_lights(const std::vector<DirectionalLight>& start, int sh_bands,
                          const Eigen::MatrixXd& map_coeffs,
                          const std::vector<Eigen::Vector3d>& normals,
                          const Eigen::MatrixXd& e_ref, const LightFitOptions& options) {
    const int k = static_cast<int>(start.size());
    const auto nn = static_cast<Eigen::Index>(normals.size());
    if (k < 1 || sh_bands < 1 || map_coeffs.rows() < sh::count(sh_bands) ||
        map_coeffs.cols() != 3 || e_ref.rows() != nn || e_ref.cols() != 3 || nn < 4 * k)
        throw UsageError("fit_lights: lights, bands, coefficients or normals do not agree");
    const double alpha_max = options.max_radius_deg * kPi / 180;

    // What the lights must carry: the reference minus the map's own b bands, per channel.
    const Eigen::MatrixXd high =
        e_ref - sh_irradiance(map_coeffs.topRows(sh::count(sh_bands)), sh_bands, normals);
    Eigen::VectorXd high_y(nn);
    for (Eigen::Index i = 0; i < nn; ++i)
        high_y[i] = luminance(high(i, 0), high(i, 1), high(i, 2));

    auto lobes_of = [&](const Geometry& g) {
        std::vector<Lobe> lobes;
        for (int j = 0; j < k; ++j)
            lobes.emplace_back(g.direction[static_cast<size_t>(j)], g.alpha[static_cast<size_t>(j)],
                               sh_bands, start[static_cast<size_t>(j)].shading);
        return lobes;
    };
    ColumnCache cache;
    auto residual = [&](const Geometry& g) {
        Eigen::VectorXd r = high_y;
        for (int j = 0; j < k; ++j) {
            const auto js = static_cast<size_t>(j);
            const Eigen::VectorXd& h = cache.get(j, g.direction[js], g.alpha[js], [&] {
                const Lobe lobe(g.direction[js], g.alpha[js], sh_bands, start[js].shading);
                Eigen::VectorXd col(nn);
                for (Eigen::Index i = 0; i < nn; ++i)
                    col[i] = lobe.high_pass(normals[static_cast<size_t>(i)]);
                return col;
            });
            r -= g.flux_y[js] * h;
        }
        return r;
    };
    // Parameters per light: tangent offsets (u, v) of d, alpha offset, log-scale of Phi_Y.
    auto moved = [&](const Geometry& g, const Eigen::VectorXd& p) {
        Geometry o = g;
        for (int j = 0; j < k; ++j) {
            const auto js = static_cast<size_t>(j);
            move_cap(g.direction[js], g.alpha[js], &p[4 * j], alpha_max, o.direction[js], o.alpha[js]);
            o.flux_y[js] = g.flux_y[js] * std::exp(std::clamp(p[4 * j + 3], -5.0, 5.0));
        }
        return o;
    };

    Geometry g;
    for (const auto& l : start) {
        g.direction.push_back(l.direction.normalized());
        g.alpha.push_back(std::clamp(l.angular_radius, 0.0, alpha_max));
        g.flux_y.push_back(std::max(luminance_flux(l), 1e-12));
    }
    LightFitResult out;
    double cost = residual(g).squaredNorm();
    out.rms_start = std::sqrt(cost / static_cast<double>(nn));
    out.iterations = levenberg_marquardt(g, 4 * k, residual, moved, options.max_iterations, cost);

    // Each channel's flux at the fitted geometry (linear least squares, negatives clamped).
    const Eigen::MatrixXd h = design(lobes_of(g), normals);
    const Eigen::MatrixXd hth = h.transpose() * h;
    out.lights = start;
    Eigen::MatrixXd flux(k, 3);
    for (int c = 0; c < 3; ++c) flux.col(c) = hth.ldlt().solve(h.transpose() * high.col(c));
    for (int j = 0; j < k; ++j) {
        auto& l = out.lights[static_cast<size_t>(j)];
        l.direction = g.direction[static_cast<size_t>(j)];
        l.angular_radius = g.alpha[static_cast<size_t>(j)];
        l.fitted = true;
        for (int c = 0; c < 3; ++c) l.flux[c] = std::max(0.0, flux(j, c));
        if (!l.flux.allFinite()) l.flux = Eigen::Vector3d::Zero();
    }
    Eigen::VectorXd r = high_y;
    for (int j = 0; j < k; ++j) r -= luminance_flux(out.lights[static_cast<size_t>(j)]) * h.col(j);
    out.rms_fitted = std::sqrt(r.squaredNorm() / static_cast<double>(nn));
    if (!(out.rms_fitted <= out.rms_start)) {  // clamped negative channels: keep the start
        out.lights = start;
        out.rms_fitted = out.rms_start;
    }
    out.coeffs = map_coeffs.topRows(sh::count(sh_bands));
    for (const auto& l : out.lights) out.coeffs -= cap_coefficients(l, sh_bands);
    return out;
}

LightFitResult fit_lights_free_sh(const std::vector<DirectionalLight>& start, int sh_bands,
                                  const std::vector<Eigen::Vector3d>& normals,
                                  const Eigen::MatrixXd& e_ref, const Eigen::VectorXd& weights,
                                  const LightFitOptions& options) {
    const int k = static_cast<int>(start.size());
    const auto nn = static_cast<Eigen::Index>(normals.size());
    if (k < 1 || sh_bands < 1 || e_ref.rows() != nn || e_ref.cols() != 3 ||
        weights.size() != nn || !(weights.array() >= 0).all())
        throw UsageError("fit_lights_free_sh: lights, bands, weights or normals do not agree");
    const double alpha_max = options.max_radius_deg * kPi / 180;
    const Eigen::VectorXd sw = weights.cwiseSqrt();
    // The weighted SH columns A_l Y_lm(n) (A_l != 0), orthonormalised once: Q.
    int nc = 0;
    for (int l = 0; l < sh_bands; ++l)
        if (sh::cosine_zonal(l) != 0) nc += 2 * l + 1;
    if (nn < nc + 4 * k)
        throw UsageError("fit_lights_free_sh: too few normals for the unknowns");
    Eigen::MatrixXd a_sh(nn, nc);
    std::vector<double> y(static_cast<size_t>(sh::count(sh_bands)));
    for (Eigen::Index i = 0; i < nn; ++i) {
        sh::eval(sh_bands, normals[static_cast<size_t>(i)], y.data());
        int col = 0;
        for (int l = 0; l < sh_bands; ++l) {
            const double al = sh::cosine_zonal(l);
            if (al == 0) continue;
            for (int m = -l; m <= l; ++m)
                a_sh(i, col++) = sw[i] * al * y[static_cast<size_t>(sh::index(l, m))];
        }
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a_sh);
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(nn, nc);
    const auto project_out = [&](const Eigen::MatrixXd& m) -> Eigen::MatrixXd {
        return m - q * (q.transpose() * m);
    };
    Eigen::VectorXd target(nn);
    for (Eigen::Index i = 0; i < nn; ++i)
        target[i] = sw[i] * luminance(e_ref(i, 0), e_ref(i, 1), e_ref(i, 2));
    const Eigen::VectorXd target_perp = project_out(target);

    struct Shape {
        std::vector<Eigen::Vector3d> direction;
        std::vector<double> alpha;
    };
    // The weighted unit-flux light columns with the SH part projected out.
    ColumnCache cache;
    const auto columns = [&](const Shape& g) {
        Eigen::MatrixXd c(nn, k);
        for (int j = 0; j < k; ++j) {
            const auto js = static_cast<size_t>(j);
            c.col(j) = cache.get(j, g.direction[js], g.alpha[js], [&] {
                DirectionalLight unit = start[js];
                unit.direction = g.direction[js];
                unit.angular_radius = g.alpha[js];
                unit.flux = Eigen::Vector3d::Ones();
                Eigen::VectorXd col(nn);
                for (Eigen::Index i = 0; i < nn; ++i)
                    col[i] = sw[i] * light_irradiance(unit, normals[static_cast<size_t>(i)])[0];
                return col;
            });
        }
        return Eigen::MatrixXd(project_out(c));
    };
    const auto fluxes = [&](const Eigen::MatrixXd& c) -> Eigen::VectorXd {
        return c.colPivHouseholderQr().solve(target_perp);
    };
    const auto residual = [&](const Shape& g) -> Eigen::VectorXd {
        const Eigen::MatrixXd c = columns(g);
        const Eigen::VectorXd f = fluxes(c);
        return target_perp - c * f;
    };
    const auto moved = [&](const Shape& g, const Eigen::VectorXd& p) {
        Shape o = g;
        for (int j = 0; j < k; ++j) {
            const auto js = static_cast<size_t>(j);
            move_cap(g.direction[js], g.alpha[js], &p[3 * j], alpha_max, o.direction[js], o.alpha[js]);
        }
        return o;
    };
    Shape g;
    for (const auto& l : start) {
        g.direction.push_back(l.direction.normalized());
        g.alpha.push_back(std::clamp(l.angular_radius, 0.0, alpha_max));
    }
    LightFitResult out;
    double cost = residual(g).squaredNorm();
    out.rms_start = std::sqrt(cost / static_cast<double>(nn));
    out.iterations = levenberg_marquardt(g, 3 * k, residual, moved, options.max_iterations, cost);
    out.rms_fitted = std::sqrt(cost / static_cast<double>(nn));
    const Eigen::VectorXd f = fluxes(columns(g));
    out.lights = start;
    for (int j = 0; j < k; ++j) {
        auto& l = out.lights[static_cast<size_t>(j)];
        l.direction = g.direction[static_cast<size_t>(j)];
        l.angular_radius = g.alpha[static_cast<size_t>(j)];
        l.fitted = true;
        // The luminance flux as a grey light; the caller fits each channel.
        l.flux = Eigen::Vector3d::Constant(std::max(0.0, f[j]));
    }
    return out;
}

std::vector<LightSetFit> fit_light_sets(const std::vector<DirectionalLight>& regions,
                                        int max_lights, int sh_bands,
                                        const Eigen::MatrixXd& map_coeffs,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        const Eigen::MatrixXd& e_ref,
                                        const LightFitOptions& options,
                                        const LightSetRefine& refine) {
    const int nr = static_cast<int>(regions.size());
    if (max_lights < 0 || max_lights > nr)
        throw UsageError(str("fit_light_sets: ", max_lights, " lights from ", nr, " regions"));
    std::vector<LightSetFit> out;
    for (int k = 1; k <= max_lights; ++k) {
        // The starts: (light set, region indices).
        std::vector<std::pair<std::vector<DirectionalLight>, std::vector<int>>> starts;
        std::vector<int> strongest(static_cast<size_t>(k));
        for (int j = 0; j < k; ++j) strongest[static_cast<size_t>(j)] = j;
        if (k > 1)
            starts.emplace_back(std::vector<DirectionalLight>(regions.begin(), regions.begin() + k),
                                strongest);
        const LightSetFit* prev = k > 1 ? &out.back() : nullptr;
        if (prev && options.split_starts)
            for (int j = 0; j < k - 1; ++j)
                for (int axis = 0; axis < 2; ++axis) {
                    std::vector<DirectionalLight> set = prev->lights;
                    const auto [a, c] = split_light(prev->lights[static_cast<size_t>(j)], axis);
                    set[static_cast<size_t>(j)] = a;
                    set.push_back(c);
                    std::vector<int> idx = prev->regions;
                    idx.push_back(idx[static_cast<size_t>(j)]);
                    starts.emplace_back(std::move(set), std::move(idx));
                }
        for (int j = 0; j < nr; ++j) {
            std::vector<DirectionalLight> set = prev ? prev->lights : std::vector<DirectionalLight>{};
            std::vector<int> idx = prev ? prev->regions : std::vector<int>{};
            if (std::find(idx.begin(), idx.end(), j) != idx.end()) continue;
            set.push_back(regions[static_cast<size_t>(j)]);
            idx.push_back(j);
            starts.emplace_back(std::move(set), std::move(idx));
        }
        std::vector<LightFitResult> fits(starts.size());
        std::vector<double> score(starts.size());
        parallel::for_chunks(static_cast<int64_t>(starts.size()), 1, [&](int64_t b, int64_t e) {
            for (int64_t s = b; s < e; ++s) {
                const auto is = static_cast<size_t>(s);
                fits[is] = fit_lights(starts[is].first, sh_bands, map_coeffs, normals, e_ref, options);
                score[is] = refine ? refine(fits[is].lights, fits[is].coeffs) : fits[is].rms_fitted;
            }
        });
        size_t best = 0;
        for (size_t s = 1; s < fits.size(); ++s)
            if (score[s] < score[best]) best = s;
        LightSetFit r;
        r.lights = std::move(fits[best].lights);
        r.coeffs = std::move(fits[best].coeffs);
        r.rms_fitted = fits[best].rms_fitted;
        r.score = score[best];
        r.regions = starts[best].second;
        r.starts = static_cast<int>(starts.size());
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace inlight::envmap
