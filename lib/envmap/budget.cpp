#include "envmap/budget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/log.h"
#include "core/parallel.h"
#include "sh/sh.h"

namespace inlight::envmap {

namespace {
constexpr EnumName<ErrorMetric> kErrorMetricNames[] = {{ErrorMetric::kAbsOverMean, "abs-over-mean"},
                                                       {ErrorMetric::kMeanRel, "mean-rel"}};
constexpr EnumName<ShFit> kShFitNames[] = {{ShFit::kProjection, "projection"},
                                           {ShFit::kMetric, "metric"}};
}  // namespace

ErrorMetric error_metric_from_string(const std::string& name) {
    return enum_from_string(kErrorMetricNames, name, "error metric");
}

std::string to_string(ErrorMetric metric) { return enum_to_string(kErrorMetricNames, metric); }

ShFit sh_fit_from_string(const std::string& name) {
    return enum_from_string(kShFitNames, name, "SH fit");
}

std::string to_string(ShFit fit) { return enum_to_string(kShFitNames, fit); }

double fit_sh_to_metric(Eigen::MatrixXd& coeffs, int sh_bands, std::vector<DirectionalLight>& lights,
                        const std::vector<Eigen::Vector3d>& normals, const Eigen::MatrixXd& e_ref,
                        ErrorMetric metric) {
    const auto nn = static_cast<Eigen::Index>(normals.size());
    // Columns: A_l Y_lm(n) for every coefficient with A_l != 0, then each light's irradiance per
    // unit flux (its shape; the flux scales every channel alike).
    std::vector<int> rows;
    for (int l = 0; l < sh_bands; ++l)
        if (sh::cosine_zonal(l) != 0)
            for (int m = -l; m <= l; ++m) rows.push_back(sh::index(l, m));
    const auto nc = static_cast<Eigen::Index>(rows.size());
    const auto nl = static_cast<Eigen::Index>(lights.size());
    Eigen::MatrixXd a(nn, nc + nl);
    std::vector<double> y(static_cast<size_t>(sh::count(sh_bands)));
    for (Eigen::Index i = 0; i < nn; ++i) {
        const Eigen::Vector3d& n = normals[static_cast<size_t>(i)];
        sh::eval(sh_bands, n, y.data());
        for (Eigen::Index k = 0; k < nc; ++k) {
            const int r = rows[static_cast<size_t>(k)];
            const int l = static_cast<int>(std::sqrt(static_cast<double>(r)));
            a(i, k) = sh::cosine_zonal(l) * y[static_cast<size_t>(r)];
        }
        for (Eigen::Index j = 0; j < nl; ++j) {
            DirectionalLight unit = lights[static_cast<size_t>(j)];
            unit.flux = Eigen::Vector3d::Ones();
            a(i, nc + j) = light_irradiance(unit, n)[0];
        }
    }
    // The start's unknowns, and the metric of any unknowns on these normals.
    Eigen::MatrixXd x(nc + nl, 3);
    for (Eigen::Index k = 0; k < nc; ++k) x.row(k) = coeffs.row(rows[static_cast<size_t>(k)]);
    for (Eigen::Index j = 0; j < nl; ++j) x.row(nc + j) = lights[static_cast<size_t>(j)].flux.transpose();
    const auto value = [&](const Eigen::MatrixXd& u) {
        return metric_value(irradiance_error(a * u, e_ref), metric);
    };
    // Per normal: the luminance reference and the metric's divisor (as irradiance_error).
    Eigen::VectorXd ref(nn), scale(nn);
    for (Eigen::Index i = 0; i < nn; ++i) ref(i) = luminance(e_ref(i, 0), e_ref(i, 1), e_ref(i, 2));
    const double floor = std::max(kRelFloor * ref.cwiseAbs().maxCoeff(), 1e-30);
    for (Eigen::Index i = 0; i < nn; ++i)
        scale(i) = metric == ErrorMetric::kMeanRel ? 1.0 / std::max(std::abs(ref(i)), floor) : 1.0;
    const Eigen::RowVector3d lum(0.2126, 0.7152, 0.0722);
    Eigen::MatrixXd best = x;
    double best_value = value(x);
    // IRLS for min sum_i scale_i |r_i|: weighted least squares with w_i = scale_i / |r_i|, from
    // w_i = scale_i^2 (least squares of the scaled residual). Every channel has the same
    // weights, so the luminance of the solution is the weighted fit of the luminance.
    Eigen::VectorXd w = scale.cwiseProduct(scale);
    // |r| below this fraction of the mean reference is treated as this (the IRLS's smoothing).
    const double delta = 1e-6 * std::max(ref.cwiseAbs().mean(), 1e-30);
    constexpr int kIterations = 12;
    for (int it = 0; it < kIterations; ++it) {
        const Eigen::VectorXd sw = w.cwiseSqrt();
        const Eigen::MatrixXd u =
            (sw.asDiagonal() * a).colPivHouseholderQr().solve(sw.asDiagonal() * e_ref);
        if (!u.allFinite()) break;
        const double v = value(u);
        const bool fluxes_ok = nl == 0 || (u.bottomRows(nl).array() >= 0).all();
        if (fluxes_ok && v < best_value) {
            best_value = v;
            best = u;
        }
        const Eigen::VectorXd r = (a * u - e_ref) * lum.transpose();
        for (Eigen::Index i = 0; i < nn; ++i)
            w(i) = scale(i) / std::max(std::abs(r(i)), delta);
    }
    for (Eigen::Index k = 0; k < nc; ++k) coeffs.row(rows[static_cast<size_t>(k)]) = best.row(k);
    for (Eigen::Index j = 0; j < nl; ++j)
        lights[static_cast<size_t>(j)].flux = best.row(nc + j).transpose();
    return best_value;
}

double metric_value(const IrradianceError& error, ErrorMetric metric) {
    return metric == ErrorMetric::kAbsOverMean ? error.abs_over_mean : error.mean_rel;
}

ShaderCost shader_cost(int sh_bands, int lights, const CostModel& model) {
    ShaderCost c;
    c.sh_bands = sh_bands;
    c.lights = lights;
    c.lighting_floats = 3 * sh::count(sh_bands) + 7 * lights;
    // Diffuse: the basis for every coefficient, the sum over the bands with A_l != 0 (l = 1 and
    // even l; the shader skips the others).
    int nonzero = 0;
    for (int l = 0; l < sh_bands; ++l)
        if (sh::cosine_zonal(l) != 0) nonzero += 2 * l + 1;
    int ops = (sh_bands > 1 ? kBasisOpsPerCoeff * sh::count(sh_bands) : 0) +
              kIrradianceOpsPerCoeff * nonzero;
    ops += lights * ((model.light_shading == LightShading::kCap ? kLightIrradianceOps
                                                                 : kSmoothLightIrradianceOps) +
                     kLightDiffuseOps);
    if (model.table_bands > 0) {
        c.specular_bands = std::min(sh_bands, model.table_bands);
        const int k = sh::count(c.specular_bands);
        c.texture_fetches = 4 * ((k + 3) / 4) * model.table_channels;
        ops += kTableCoordOps + kTableOpsPerCoeff * k * model.table_channels +
               kSpecularOpsPerCoeff * k + lights * kLightSpecularOps;
    }
    c.operations = ops;
    return c;
}

Eigen::MatrixXd brute_force_radiance(const Environment& env, const RadianceCheck& check,
                                     const std::vector<Eigen::Vector3d>& normals) {
    const auto samples = make_sample_set(env);
    // The samples with light, once (a lat-long map has ~5e5; most normals see half of them).
    std::vector<Eigen::Vector3d> dirs, rad;
    Eigen::Vector3d d;
    double w, v[3];
    for (int64_t i = 0; i < samples->size(); ++i) {
        if (!samples->sample(i, d, w, v) || !(w > 0)) continue;
        if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;
        dirs.push_back(d);
        rad.emplace_back(v[0] * w, v[1] * w, v[2] * w);
    }
    const brdf::Material& m = check.material;
    const Eigen::Vector3d& view = check.table.view;
    const bool specular = m.specular != brdf::Model::kLambert;
    Eigen::MatrixXd out(static_cast<Eigen::Index>(normals.size()), 3);
    parallel::for_chunks(static_cast<int64_t>(normals.size()), 1, [&](int64_t b, int64_t e) {
        for (int64_t k = b; k < e; ++k) {
            const Eigen::Vector3d& n = normals[static_cast<size_t>(k)];
            const Eigen::Matrix3d local_from_world = brdf::world_from_local(n).transpose();
            const Eigen::Vector3d wo = local_from_world * view;
            Eigen::Vector3d diffuse = Eigen::Vector3d::Zero(), spec = Eigen::Vector3d::Zero();
            for (size_t i = 0; i < dirs.size(); ++i) {
                const double c = n.dot(dirs[i]);
                if (c <= 0) continue;
                diffuse += c * rad[i];
                if (specular)
                    spec +=
                        c *
                        brdf::eval_specular(m, wo, local_from_world * dirs[i]).cwiseProduct(rad[i]);
            }
            out.row(k) = (m.albedo.cwiseProduct(diffuse) * kInvPi + spec).transpose();
        }
    });
    return out;
}

Eigen::MatrixXd model_radiance(const Eigen::MatrixXd& coeffs, int sh_bands,
                               const std::vector<DirectionalLight>& lights,
                               const RadianceCheck& check,
                               const std::vector<Eigen::Vector3d>& normals) {
    const brdf::Material& m = check.material;
    const brdf::Table& t = check.table;
    const Eigen::MatrixXd e = sh_irradiance(coeffs, sh_bands, normals);
    const int k_spec = sh::count(std::min(sh_bands, t.sh_bands));
    const bool specular = m.specular != brdf::Model::kLambert;
    Eigen::MatrixXd out(static_cast<Eigen::Index>(normals.size()), 3);
    std::vector<float> b(static_cast<size_t>(t.coeff_count()));
    for (size_t i = 0; i < normals.size(); ++i) {
        const Eigen::Vector3d& n = normals[i];
        Eigen::Vector3d irr = e.row(static_cast<Eigen::Index>(i)).transpose(),
                        spec = Eigen::Vector3d::Zero();
        for (const auto& l : lights) {
            irr += light_irradiance(l, n);
            spec += light_specular(l, n, t.view, m);
        }
        if (specular) {
            for (int c = 0; c < 3; ++c) {
                lookup(t, n.cast<float>(), t.channels == 3 ? c : 0, b.data());
                for (int k = 0; k < k_spec; ++k)
                    spec[c] += coeffs(k, c) * b[static_cast<size_t>(k)];
            }
        }
        out.row(static_cast<Eigen::Index>(i)) =
            (m.albedo.cwiseProduct(irr) * kInvPi + spec).transpose();
    }
    return out;
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Irradiance of the first `count` lights at each normal (normals x 3).
Eigen::MatrixXd lights_irradiance(const std::vector<DirectionalLight>& lights, int count,
                                  const std::vector<Eigen::Vector3d>& normals) {
    Eigen::MatrixXd e = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(normals.size()), 3);
    for (int j = 0; j < count; ++j)
        for (size_t i = 0; i < normals.size(); ++i)
            e.row(static_cast<Eigen::Index>(i)) +=
                light_irradiance(lights[static_cast<size_t>(j)], normals[i]).transpose();
    return e;
}

/// Partial-sphere frames: the irradiance the SH radiance gives from the OBSERVED directions
/// only, by the same per-pixel sum as the reference (the unseen part, which the fit
/// extrapolates, has no data to be checked against). normals x 3.
class ObservedIrradiance {
  public:
    explicit ObservedIrradiance(const Environment& env) {
        const auto samples = make_sample_set(env);
        Eigen::Vector3d d;
        double w, v[3];
        for (int64_t i = 0; i < samples->size(); ++i) {
            if (!samples->sample(i, d, w, v) || !(w > 0)) continue;
            m_dirs.push_back(d);
            m_weights.push_back(w);
        }
    }
    Eigen::MatrixXd operator()(const Eigen::MatrixXd& coeffs, int sh_bands,
                               const std::vector<Eigen::Vector3d>& normals) const {
        const int nn = static_cast<int>(normals.size()), kc = sh::count(sh_bands);
        Eigen::Matrix3Xd nm(3, nn);
        for (int i = 0; i < nn; ++i) nm.col(i) = normals[static_cast<size_t>(i)];
        using Acc = Eigen::MatrixXd;
        return parallel::reduce(
            static_cast<int64_t>(m_dirs.size()), 4096, Acc(Acc::Zero(nn, 3)),
            [&](int64_t b, int64_t e) {
                Acc acc = Acc::Zero(nn, 3);
                std::vector<double> y(static_cast<size_t>(kc));
                Eigen::VectorXd cosines(nn);
                for (int64_t i = b; i < e; ++i) {
                    const auto is = static_cast<size_t>(i);
                    sh::eval(sh_bands, m_dirs[is], y.data());
                    Eigen::Vector3d l = Eigen::Vector3d::Zero();
                    for (int k = 0; k < kc; ++k)
                        l += y[static_cast<size_t>(k)] * coeffs.row(k).transpose();
                    cosines.noalias() = nm.transpose() * m_dirs[is];
                    for (int k = 0; k < nn; ++k)
                        if (cosines(k) > 0)
                            acc.row(k) += (m_weights[is] * cosines(k)) * l.transpose();
                }
                return acc;
            },
            [](Acc a, const Acc& o) { return Acc(a + o); });
    }

  private:
    std::vector<Eigen::Vector3d> m_dirs;
    std::vector<double> m_weights;
};

}  // namespace

BudgetPlan plan_budget(const Environment& env, const BudgetOptions& options,
                       const image::Image* saturated) {
    if (!(options.max_error > 0) || !std::isfinite(options.max_error))
        throw UsageError(
            str("budget: max_error must be a positive number, got ", options.max_error));
    if (options.max_bands < 1 || options.max_bands > sh::kMaxBands)
        throw UsageError(
            str("budget: max_bands must be in [1, ", sh::kMaxBands, "], got ", options.max_bands));
    if (options.validate_normals < 1) throw UsageError("budget: validate_normals must be >= 1");
    if (options.holdout_normals < 0) throw UsageError("budget: holdout_normals must be >= 0");
    if (!(options.scoring_margin >= 0 && options.scoring_margin < 0.5))
        throw UsageError(str("budget: scoring_margin must be in [0, 0.5), got ",
                             options.scoring_margin));
    if (options.radiance && !env.full_sphere())
        throw UsageError(
            str(env.source, ": the radiance check (--brdf-table) needs a full-sphere map"));
    const auto t_start = std::chrono::steady_clock::now();
    if (!(options.metric_start_min_flux_fraction >= 0 && options.metric_start_min_flux_fraction <= 1))
        throw UsageError("budget: metric_start_min_flux_fraction must be in [0, 1]");
    if (options.extra_start_regions < 0)
        throw UsageError("budget: extra_start_regions must be >= 0");
    BudgetPlan plan;
    // Fit the lights of every candidate (light_fit.h) where the brute force sees the whole
    // sphere unclipped and the SH are the plain truncation the fit models.
    const bool fit = options.fit_normals > 0 && options.extract.max_lights > 0 &&
                     env.full_sphere() && !saturated &&
                     options.project.window == sh::Window::kNone;
    ExtractOptions pool = options.extract;
    if (fit) pool.max_lights += options.extra_start_regions;
    if (fit && options.sh_fit == ShFit::kMetric)
        pool.min_flux_fraction =
            std::min(pool.min_flux_fraction, options.metric_start_min_flux_fraction);
    plan.extraction = extract_lights(env, pool, saturated);
    for (auto& l : plan.extraction.lights) l.shading = options.light_shading;
    const auto& lights = plan.extraction.lights;
    const int max_k = std::min(options.extract.max_lights, static_cast<int>(lights.size()));

    // References: brute force over the original map's pixels.
    const auto normals =
        validation_normals(options.validate_normals, env.full_sphere() ? 4.0 : kPi / 3);
    plan.normals = static_cast<int>(normals.size());
    auto t0 = std::chrono::steady_clock::now();
    // A set of normals to score a model on: the brute-force irradiance there and, with a
    // RadianceCheck, the normals facing its view with their brute-force outgoing radiance.
    struct ScoringSet {
        std::vector<Eigen::Vector3d> normals, facing;
        Eigen::MatrixXd e_ref, l_ref;
    };
    const auto scoring_set = [&](std::vector<Eigen::Vector3d> at) {
        ScoringSet set;
        set.e_ref = brute_force_irradiance(env, at);
        if (options.radiance) {
            for (const auto& n : at)
                if (n.dot(options.radiance->table.view) > 0) set.facing.push_back(n);
            set.l_ref = brute_force_radiance(env, *options.radiance, set.facing);
        }
        set.normals = std::move(at);
        return set;
    };
    const ScoringSet scored = scoring_set(normals);
    CostModel cost_model;
    cost_model.light_shading = options.light_shading;
    if (options.radiance) {
        plan.radiance_normals = static_cast<int>(scored.facing.size());
        if (options.radiance->material.specular != brdf::Model::kLambert) {
            cost_model.table_bands = options.radiance->table.sh_bands;
            cost_model.table_channels = options.radiance->table.channels;
        }
    }
    plan.reference_time_s = seconds_since(t0);

    // Every residual's SH: full-sphere projections are orthogonal, so b bands are the first b^2
    // coefficients of one projection; partial-sphere fits are redone for every band count.
    std::vector<std::vector<ProjectResult>> proj(static_cast<size_t>(max_k + 1));
    for (int k = 0; k <= max_k; ++k) {
        const Environment residual = residual_environment(env, plan.extraction, k);
        ProjectOptions po = options.project;
        if (env.full_sphere()) {
            po.sh_bands = options.max_bands;
            const ProjectResult full = project(residual, po);
            for (int b = 1; b <= options.max_bands; ++b) {
                ProjectResult r = full;
                r.coeffs = full.coeffs.topRows(sh::count(b));
                r.coeffs_unwindowed = full.coeffs_unwindowed.topRows(sh::count(b));
                // Windows depend on the band count: reapply to the truncated projection.
                r.coeffs = r.coeffs_unwindowed;
                sh::apply_window(po.window, b, r.coeffs);
                proj[static_cast<size_t>(k)].push_back(std::move(r));
            }
        } else {
            for (int b = 1; b <= options.max_bands; ++b) {
                po.sh_bands = b;
                proj[static_cast<size_t>(k)].push_back(project(residual, po));
            }
        }
    }

    std::vector<Eigen::Vector3d> fit_set;
    Eigen::MatrixXd e_fit;
    // The metric fit of the coefficients needs the brute force at the fit normals: full-sphere
    // maps without clipped pixels (a camera frame's unseen part has no reference).
    const bool sh_fit = options.sh_fit == ShFit::kMetric && env.full_sphere() && !saturated;
    if (sh_fit && options.fit_normals < 1)
        throw UsageError("budget: the metric SH fit needs fit normals (fit_normals >= 1)");
    if ((fit && max_k > 0) || sh_fit) {
        fit_set = fit_normals(options.fit_normals);
        t0 = std::chrono::steady_clock::now();
        e_fit = brute_force_irradiance(env, fit_set);
        plan.reference_time_s += seconds_since(t0);
    }
    // The metric fit's weights for the light geometry (least squares of the metric's per-normal
    // error): 1 for abs-over-mean, 1 / max(E_ref, floor)^2 for mean-rel (as irradiance_error).
    Eigen::VectorXd fit_weights;
    if (sh_fit) {
        const auto nf = e_fit.rows();
        Eigen::VectorXd y(nf);
        for (Eigen::Index i = 0; i < nf; ++i) y[i] = luminance(e_fit(i, 0), e_fit(i, 1), e_fit(i, 2));
        const double floor = std::max(kRelFloor * y.cwiseAbs().maxCoeff(), 1e-30);
        fit_weights = Eigen::VectorXd::Ones(nf);
        if (options.metric == ErrorMetric::kMeanRel)
            for (Eigen::Index i = 0; i < nf; ++i)
                fit_weights[i] = 1 / std::pow(std::max(std::abs(y[i]), floor), 2);
    }
    // The metric fit (ShFit::kMetric) of a candidate of b bands: its coefficients and fluxes
    // fitted to the metric at the fit normals, then its lights' geometry refitted with the
    // coefficients free (kept if the metric there is lower: `refit` says so). Returns the
    // metric there.
    const auto fit_to_metric = [&](std::vector<DirectionalLight>& set, Eigen::MatrixXd& coeffs,
                                   int b, bool& refit_kept) {
        refit_kept = false;
        double v = fit_sh_to_metric(coeffs, b, set, fit_set, e_fit, options.metric);
        if (set.empty()) return v;
        LightFitResult g = fit_lights_free_sh(set, b, fit_set, e_fit, fit_weights);
        Eigen::MatrixXd refit = coeffs;
        const double vg = fit_sh_to_metric(refit, b, g.lights, fit_set, e_fit, options.metric);
        if (vg < v) {
            v = vg;
            set = std::move(g.lights);
            coeffs = std::move(refit);
            refit_kept = true;
        }
        return v;
    };
    // Per band count b - 1: the fitted light sets for 1 .. max_k lights. With the metric fit,
    // every start of the light fit is refined to the metric and the starts are compared by the
    // metric on the fit normals: the metric fit lands in different minima from different
    // starts, and the least projection RMS is not the least metric (docs/budget.md).
    std::vector<std::vector<LightSetFit>> fitted(static_cast<size_t>(options.max_bands));
    if (fit && max_k > 0) {
        for (int b = 1; b <= options.max_bands; ++b) {
            auto& f = fitted[static_cast<size_t>(b - 1)];
            const Eigen::MatrixXd& map = proj[0][static_cast<size_t>(b - 1)].coeffs_unwindowed;
            if (b > 1 && sh::cosine_zonal(b - 1) == 0) {
                // A_{b-1} = 0: band b - 1 adds nothing to irradiance, so the fit (which sees
                // only irradiance) is that of b - 1 bands; only the coefficients grow.
                f = fitted[static_cast<size_t>(b - 2)];
                for (auto& s : f) {
                    s.coeffs = map.topRows(sh::count(b));
                    for (const auto& l : s.lights) s.coeffs -= cap_coefficients(l, b);
                }
                continue;
            }
            LightSetRefine refine;
            LightFitOptions fit_options;
            // The split starts were measured with the metric fit (docs/budget.md); the
            // projection's candidates keep the starts their trade-off was measured with.
            fit_options.split_starts = sh_fit;
            if (sh_fit)
                refine = [&fit_to_metric, b](std::vector<DirectionalLight>& set,
                                             Eigen::MatrixXd& coeffs) {
                    bool refit_kept;
                    return fit_to_metric(set, coeffs, b, refit_kept);
                };
            f = fit_light_sets(lights, max_k, b, map, fit_set, e_fit, fit_options, refine);
        }
    }

    std::unique_ptr<ObservedIrradiance> observed;
    if (!env.full_sphere()) observed = std::make_unique<ObservedIrradiance>(env);
    // A model's error on a ScoringSet: its irradiance error and, with a RadianceCheck, its
    // outgoing radiance error, `error` the worse by the metric. The candidates and the holdout
    // are scored by this one rule, so the holdout checks exactly what was scored.
    struct Score {
        IrradianceError irradiance, radiance;
        bool has_radiance = false;
        double error = 0;
    };
    const auto score = [&](const ScoringSet& set, const Eigen::MatrixXd& coeffs, int b,
                           const std::vector<DirectionalLight>& used) {
        Score sc;
        const Eigen::MatrixXd e_lights =
            lights_irradiance(used, static_cast<int>(used.size()), set.normals);
        const Eigen::MatrixXd e_sh = observed ? (*observed)(coeffs, b, set.normals)
                                              : sh_irradiance(coeffs, b, set.normals);
        sc.irradiance = irradiance_error(e_sh + e_lights, set.e_ref);
        sc.error = metric_value(sc.irradiance, options.metric);
        if (options.radiance && !set.facing.empty()) {
            sc.has_radiance = true;
            sc.radiance = irradiance_error(
                model_radiance(coeffs, b, used, *options.radiance, set.facing), set.l_ref);
            sc.error = std::max(sc.error, metric_value(sc.radiance, options.metric));
        }
        return sc;
    };
    for (int k = 0; k <= max_k; ++k) {
        const std::vector<DirectionalLight> found(lights.begin(), lights.begin() + k);
        for (int b = 1; b <= options.max_bands; ++b) {
            ProjectResult& r = proj[static_cast<size_t>(k)][static_cast<size_t>(b - 1)];
            BudgetCandidate c;
            c.lights = k;
            c.sh_bands = b;
            c.light_set = found;
            for (int j = 0; j < k; ++j) c.start_regions.push_back(j);
            if (fit && k > 0) {
                // The map minus the fitted lights replaces the residual of the regions.
                const LightSetFit& f =
                    fitted[static_cast<size_t>(b - 1)][static_cast<size_t>(k - 1)];
                c.light_set = f.lights;
                c.lights_fitted = true;
                c.start_regions = f.regions;
                r.coeffs = r.coeffs_unwindowed = f.coeffs;
            }
            if (sh_fit) {
                // proj[0] also starts the light fits above: those are done by now. The fitted
                // sets were refined the same way (this starts from their result, so it ends no
                // higher on the fit normals); the regions as found and the reused fits of
                // A_l = 0 bands are refined here first.
                bool refit_kept;
                fit_to_metric(c.light_set, r.coeffs, b, refit_kept);
                c.lights_fitted = c.lights_fitted || refit_kept;
                r.coeffs_unwindowed = r.coeffs;
                c.sh_fitted = true;
            }
            const Score sc = score(scored, r.coeffs, b, c.light_set);
            c.irradiance = sc.irradiance;
            c.radiance = sc.radiance;
            c.has_radiance = sc.has_radiance;
            c.error = sc.error;
            c.cost = shader_cost(b, k, cost_model);
            c.meets = c.error <= options.max_error * (1 - options.scoring_margin);
            plan.candidates.push_back(c);
        }
    }
    // The cheapest that meets the budget (ties: fewer lights, then fewer bands: the order of the
    // candidates); if none does, the one with the least error.
    for (size_t i = 0; i < plan.candidates.size(); ++i) {
        const auto& c = plan.candidates[i];
        if (!c.meets) continue;
        if (plan.chosen < 0 ||
            c.cost.operations < plan.candidates[static_cast<size_t>(plan.chosen)].cost.operations)
            plan.chosen = static_cast<int>(i);
    }
    plan.met = plan.chosen >= 0;
    if (!plan.met) {
        for (size_t i = 0; i < plan.candidates.size(); ++i)
            if (plan.chosen < 0 ||
                plan.candidates[i].error < plan.candidates[static_cast<size_t>(plan.chosen)].error)
                plan.chosen = static_cast<int>(i);
    }
    const BudgetCandidate& best = plan.candidates[static_cast<size_t>(plan.chosen)];
    plan.lights = best.lights;
    plan.sh_bands = best.sh_bands;
    plan.chosen_lights = best.light_set;
    plan.projection =
        proj[static_cast<size_t>(best.lights)][static_cast<size_t>(best.sh_bands - 1)];
    if (options.holdout_normals > 0) {
        // The choice scored again, off every normal it was scored or fitted on.
        const ScoringSet held = scoring_set(
            holdout_normals(options.holdout_normals, env.full_sphere() ? 4.0 : kPi / 3));
        plan.holdout_count = static_cast<int>(held.normals.size());
        const Score sc = score(held, plan.projection.coeffs, plan.sh_bands, best.light_set);
        plan.holdout_irradiance = sc.irradiance;
        plan.holdout_error = sc.error;
    }
    for (int j = 0; j < plan.lights; ++j) {
        const DirectionalLight& l = plan.chosen_lights[static_cast<size_t>(j)];
        if (!l.flux_is_lower_bound) continue;
        double theta, phi;
        spherical_from_direction(l.direction, theta, phi);
        log::warn(str(env.source, ": light ", j + 1, " (theta ", theta * 180 / kPi, " deg, phi ",
                      phi * 180 / kPi, " deg) has luminance flux ", luminance_flux(l),
                      " as a lower bound: ",
                      l.saturated_samples > 0 ? str(l.saturated_samples, " clipped pixels carry ",
                                                    100 * l.saturated_flux_fraction, "% of it")
                                              : std::string("it touches the edge of the field")));
    }
    plan.plan_time_s = seconds_since(t_start);
    return plan;
}

namespace {

nlohmann::json error_json(const IrradianceError& e) {
    return {{"abs_over_mean", e.abs_over_mean},
            {"mean_rel", e.mean_rel},
            {"max_rel", e.max_rel},
            {"rms_over_mean", e.rms_over_mean}};
}

nlohmann::json cost_json(const ShaderCost& c) {
    return {{"operations", c.operations},
            {"lighting_floats", c.lighting_floats},
            {"texture_fetches", c.texture_fetches},
            {"specular_bands", c.specular_bands},
            {"coefficients", sh::count(c.sh_bands)}};
}

}  // namespace

nlohmann::json to_json(const BudgetPlan& plan, const BudgetOptions& options) {
    nlohmann::json cands = nlohmann::json::array();
    for (const auto& c : plan.candidates) {
        nlohmann::json j = {{"lights", c.lights},
                            {"sh_bands", c.sh_bands},
                            {"irradiance", error_json(c.irradiance)},
                            {"error", c.error},
                            {"meets", c.meets},
                            {"cost", cost_json(c.cost)}};
        if (c.has_radiance) j["radiance"] = error_json(c.radiance);
        if (c.lights > 0) {
            j["lights_fitted"] = c.lights_fitted;
            j["start_regions"] = c.start_regions;
            j["light_set"] = nlohmann::json::array();
            for (const auto& l : c.light_set) {
                const nlohmann::json lj = to_json(l);
                j["light_set"].push_back({{"theta_deg", lj["theta_deg"]},
                                          {"phi_deg", lj["phi_deg"]},
                                          {"luminance_flux", lj["luminance_flux"]},
                                          {"angular_radius_deg", lj["angular_radius_deg"]}});
            }
        }
        cands.push_back(j);
    }
    nlohmann::json lights = nlohmann::json::array();
    for (const auto& l : plan.extraction.lights) lights.push_back(to_json(l));
    const BudgetCandidate& best = plan.candidates[static_cast<size_t>(plan.chosen)];
    return {{"metric", to_string(options.metric)},
            {"max_error", options.max_error},
            {"scoring_margin", options.scoring_margin},
            {"scored_limit", options.max_error * (1 - options.scoring_margin)},
            {"met", plan.met},
            {"chosen",
             {{"sh_bands", plan.sh_bands},
              {"lights", plan.lights},
              {"error", best.error},
              {"lights_fitted", best.lights_fitted},
              {"sh_fitted", best.sh_fitted},
              {"cost", cost_json(best.cost)}}},
            {"holdout",
             plan.holdout_count > 0
                 ? nlohmann::json{{"normals", plan.holdout_count},
                                  {"error", plan.holdout_error},
                                  {"irradiance", error_json(plan.holdout_irradiance)}}
                 : nlohmann::json(nullptr)},
            {"lights_found", lights},
            {"light_shading", to_string(options.light_shading)},
            {"sh_fit", to_string(options.sh_fit)},
            {"fit_normals", options.fit_normals},
            {"extra_start_regions", options.extra_start_regions},
            {"median_luminance", plan.extraction.median_luminance},
            {"regions_examined", plan.extraction.regions_examined},
            {"normals", plan.normals},
            {"radiance_normals", plan.radiance_normals},
            {"reference_time_s", plan.reference_time_s},
            {"plan_time_s", plan.plan_time_s},
            {"candidates", cands}};
}

}  // namespace inlight::envmap
