// The error of a bake (bake.h: make_reference, validate, truncation_by_bands, choose_bands):
// an independent reference by adaptive cubature (cubature.h) at grid nodes and off-grid normals.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "brdf/bake.h"
#include "brdf/cubature.h"
#include "core/check.h"
#include "core/parallel.h"
#include "sh/quadrature.h"
#include "sh/sh.h"

namespace inlight::brdf {

std::vector<TestLighting> test_lightings() {
    const Eigen::Vector3d key = view_from_deg(35, 90), window = view_from_deg(50, -20);
    return {
        {"uniform", [](const Eigen::Vector3d&) { return 1.0; }},
        {"front_gradient", [](const Eigen::Vector3d& w) { return 1.0 + w.z(); }},
        {"key_vmf10",
         [key](const Eigen::Vector3d& w) { return std::exp(10.0 * (key.dot(w) - 1.0)); }, key},
        {"window_vmf50",
         [window](const Eigen::Vector3d& w) { return std::exp(50.0 * (window.dot(w) - 1.0)); },
         window},
    };
}

std::vector<Eigen::VectorXd> test_lighting_coeffs(int sh_bands) {
    const auto lights = test_lightings();
    std::vector<Eigen::VectorXd> out(lights.size(), Eigen::VectorXd::Zero(sh::count(sh_bands)));
    std::vector<double> x, w, y(sh::count(sh_bands));
    const int n = 128, n_phi = 256;
    sh::gauss_legendre(n, x, w);
    for (int i = 0; i < n; ++i) {
        const double s = std::sqrt(std::max(0.0, 1.0 - x[i] * x[i]));
        for (int j = 0; j < n_phi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / n_phi;
            const Eigen::Vector3d d(s * std::cos(phi), s * std::sin(phi), x[i]);
            sh::eval(sh_bands, d, y.data());
            const double weight = w[i] * 2.0 * kPi / n_phi;
            for (size_t l = 0; l < lights.size(); ++l) {
                const double lw = weight * lights[l].radiance(d);
                for (int k = 0; k < sh::count(sh_bands); ++k) out[l][k] += lw * y[k];
            }
        }
    }
    return out;
}

namespace {

double dot_prefix(const Eigen::VectorXd& l, const double* b, int count) {
    double s = 0;
    for (int k = 0; k < count; ++k) s += l[k] * b[k];
    return s;
}

// Radiance scale per lighting: the largest exact radiance over everything checked.
std::vector<double> radiance_scales(const ReferenceSet& ref, int n_lights) {
    std::vector<double> scale(n_lights, 0.0);
    for (int l = 0; l < n_lights; ++l) {
        for (int node : ref.nodes) {
            scale[l] = std::max(scale[l], ref.at_node.at(node).exact.col(l).cwiseAbs().maxCoeff());
        }
        for (const auto& r : ref.at_normal) {
            scale[l] = std::max(scale[l], r.exact.col(l).cwiseAbs().maxCoeff());
        }
    }
    return scale;
}

}  // namespace

double reference_rel_tol_for(const BakeOptions& o) {
    const double gl = ValidateOptions{}.reference_rel_tol;
    if (o.integrator == Integrator::kGaussLegendre) return gl;
    return std::max(gl, 0.01 / std::sqrt(static_cast<double>(std::max(1, o.samples))));
}

ReferenceNormal reference_normal(const Material& m, const Eigen::Vector3d& n,
                                 const Eigen::Vector3d& view, const ValidateOptions& vopt) {
    const auto lights = test_lightings();
    const int nk = sh::count(kMaxBakeBands), nl = static_cast<int>(lights.size());
    const int channels = baked_lobe_is_achromatic(m) ? 1 : 3;
    ReferenceNormal r;
    r.coeffs = Eigen::MatrixXd::Zero(3, nk);
    r.exact = Eigen::MatrixXd::Zero(3, nl);
    const FacetView fv = facet_view(m, n, view);
    if (!fv.visible()) return r;
    const Eigen::Matrix3d frame = world_from_local(n);
    // Components: [channel][coefficient], then [channel][lighting].
    std::vector<double> y(nk);
    const HemisphereIntegrand f = [&](const Eigen::Vector3d& wi, double* out) {
        const Eigen::Vector3d v = fv.lobe_cos(m, wi);
        const Eigen::Vector3d w = (frame * wi).normalized();
        sh::eval(kMaxBakeBands, w, y.data());
        for (int ch = 0; ch < channels; ++ch) {
            for (int k = 0; k < nk; ++k) out[ch * nk + k] = v[ch] * y[k];
            for (int l = 0; l < nl; ++l)
                out[channels * nk + ch * nl + l] = v[ch] * lights[l].radiance(w);
        }
    };
    std::vector<Eigen::Vector3d> features = {Eigen::Vector3d(-fv.wo.x(), -fv.wo.y(), fv.wo.z())};
    for (const TestLighting& l : lights) {
        if (l.peak.squaredNorm() > 0) features.push_back(frame.transpose() * l.peak);
    }
    CubatureOptions copt;
    copt.rel_tol = vopt.reference_rel_tol;
    copt.max_evals = vopt.reference_max_evals;
    copt.scale_count = channels * nk;
    // An edge-on facet's lobe peaks (GGX) or is singular like 1 / |wi + wo| (the report's
    // limit, F D (n.h) / (2 wo.h)) at the horizon point -wo: polar coordinates about it.
    const int dim = channels * (nk + nl);
    const CubatureResult c = fv.edge_on
                                 ? hemisphere_cubature_about_horizon(f, dim, features[0], copt)
                                 : hemisphere_cubature(f, dim, features, copt);
    for (int ch = 0; ch < 3; ++ch) {
        const int from = channels == 3 ? ch : 0;
        r.coeffs.row(ch) = c.integral.segment(from * nk, nk).transpose();
        r.exact.row(ch) = c.integral.segment(channels * nk + from * nl, nl).transpose();
    }
    r.error = c.error;
    r.evals = c.evals;
    r.converged = c.converged;
    return r;
}

nlohmann::json Validation::to_json() const {
    return {{"integration_coeff_max_abs", integration_coeff_max_abs},
            {"integration_coeff_rms", integration_coeff_rms},
            {"integration_coeff_max_rel", integration_coeff_max_rel},
            {"integration_radiance_max_rel", integration_radiance_max_rel},
            {"interpolation_coeff_max_abs", interpolation_coeff_max_abs},
            {"interpolation_radiance_max_rel", interpolation_radiance_max_rel},
            {"truncation_radiance_max_rel", truncation_radiance_max_rel},
            {"truncation_radiance_max_rel_by_bands", truncation_radiance_max_rel_by_bands},
            {"total_radiance_max_rel", total_radiance_max_rel},
            {"reference_error_max_rel", reference_error_max_rel},
            {"reference_evals", reference_evals},
            {"nodes_checked", nodes_checked},
            {"test_normals", test_normals},
            {"per_lighting", per_lighting},
            {"validate_time_s", time_s}};
}

ReferenceSet make_reference(const Material& m, const Grid& grid, const Eigen::Vector3d& view,
                            const ValidateOptions& vopt) {
    const auto start = std::chrono::steady_clock::now();
    ReferenceSet ref;
    ref.grid = grid;
    // Grid nodes checked (evenly strided) and off-grid test normals inside the grid's domain.
    const int count = grid.node_count();
    const int want = (vopt.max_nodes <= 0 || vopt.max_nodes >= count) ? count : vopt.max_nodes;
    for (int i = 0; i < want; ++i) ref.nodes.push_back(static_cast<int>(int64_t(i) * count / want));
    const double cos_max = grid.kind == GridKind::kThetaPhi ? std::cos(grid.theta_max) : 0.0;
    for (int i = 0; i < vopt.test_normals; ++i) {
        const double z = 1.0 - (i + 0.5) / vopt.test_normals * (1.0 - cos_max);
        const double phi = i * kPi * (3.0 - std::sqrt(5.0));
        const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
        ref.normals.emplace_back(s * std::cos(phi), s * std::sin(phi), z);
    }
    // Reference at every node needed: the checked ones and the corners of each test normal.
    std::vector<int> need;
    auto add = [&](int node) {
        if (!ref.at_node.count(node)) {
            ref.at_node[node] = ReferenceNormal{};
            need.push_back(node);
        }
    };
    for (int node : ref.nodes) add(node);
    for (const auto& n : ref.normals) {
        const GridCoord g = grid_coord(grid, n.cast<float>());
        for (int r : {g.r0, g.r1}) {
            for (int c : {g.c0, g.c1}) add(r * grid.cols + c);
        }
    }
    const std::set<int> checked(ref.nodes.begin(), ref.nodes.end());
    ValidateOptions off_grid = vopt;
    off_grid.reference_rel_tol = std::max(vopt.reference_rel_tol, vopt.off_grid_rel_tol);
    std::vector<ReferenceNormal> at_need(need.size());
    ref.at_normal.resize(ref.normals.size());
    const int64_t total = static_cast<int64_t>(need.size() + ref.normals.size());
    parallel::for_chunks(total, 1, [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
            if (i < static_cast<int64_t>(need.size())) {
                const int node = need[i];
                at_need[i] =
                    reference_normal(m, grid_node_normal(grid, node / grid.cols, node % grid.cols),
                                     view, checked.count(node) ? vopt : off_grid);
            } else {
                const size_t j = i - need.size();
                ref.at_normal[j] = reference_normal(m, ref.normals[j], view, off_grid);
            }
        }
    });
    for (size_t i = 0; i < need.size(); ++i) ref.at_node[need[i]] = std::move(at_need[i]);

    // The reference's own error: its cubature estimate against the largest coefficient.
    double max_ref = 0, max_err = 0;
    for (const auto& [node, r] : ref.at_node) {
        if (checked.count(node)) {
            max_ref = std::max(max_ref, r.coeffs.cwiseAbs().maxCoeff());
            max_err = std::max(max_err, r.error);
        }
        ref.evals += r.evals;
    }
    for (const auto& r : ref.at_normal) ref.evals += r.evals;
    ref.error_max_rel = max_ref > 0 ? max_err / max_ref : 0.0;
    ref.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return ref;
}

std::vector<double> truncation_by_bands(const ReferenceSet& ref) {
    const auto lcoef = test_lighting_coeffs(kMaxBakeBands);
    const int n_lights = static_cast<int>(lcoef.size());
    const std::vector<double> scale = radiance_scales(ref, n_lights);
    std::vector<double> out(kMaxBakeBands, 0.0);
    for (int node : ref.nodes) {
        const ReferenceNormal& r = ref.at_node.at(node);
        for (int ch = 0; ch < 3; ++ch) {
            const Eigen::VectorXd rc = r.coeffs.row(ch).transpose();
            for (int l = 0; l < n_lights; ++l) {
                if (!(scale[l] > 0)) continue;
                for (int b = 1; b <= kMaxBakeBands; ++b) {
                    const double e =
                        std::abs(dot_prefix(lcoef[l], rc.data(), b * b) - r.exact(ch, l));
                    out[b - 1] = std::max(out[b - 1], e / scale[l]);
                }
            }
        }
    }
    return out;
}

Validation validate(const ReferenceSet& ref, const Table& baked) {
    const auto start = std::chrono::steady_clock::now();
    const Grid& grid = baked.grid;
    INLIGHT_CHECK(to_string(grid) == to_string(ref.grid)) << "reference for another grid";
    const auto lights = test_lightings();
    const int n_lights = static_cast<int>(lights.size());
    const auto lcoef = test_lighting_coeffs(kMaxBakeBands);
    const int kb = baked.coeff_count();

    Validation v;
    v.nodes_checked = static_cast<int>(ref.nodes.size());
    v.test_normals = static_cast<int>(ref.normals.size());
    v.reference_error_max_rel = ref.error_max_rel;
    v.reference_evals = ref.evals;
    v.truncation_radiance_max_rel_by_bands = truncation_by_bands(ref);
    auto ch_of = [&](int ch) { return baked.channels == 3 ? ch : 0; };
    const std::vector<double> scale = radiance_scales(ref, n_lights);
    auto rel = [&](int l, double err) { return scale[l] > 0 ? err / scale[l] : 0.0; };
    std::vector<double> integ(n_lights, 0), interp(n_lights, 0), trunc(n_lights, 0),
        total(n_lights, 0);

    // Integration and truncation at grid nodes.
    double max_ref = 0, sum_sq = 0;
    int64_t n_sq = 0;
    for (int node : ref.nodes) {
        const ReferenceNormal& r = ref.at_node.at(node);
        const int i1 = node / grid.cols, i2 = node % grid.cols;
        for (int ch = 0; ch < 3; ++ch) {
            Eigen::VectorXd b(kb);
            for (int k = 0; k < kb; ++k) {
                b[k] = baked.at(ch_of(ch), i1, i2, k);
                const double e = std::abs(b[k] - r.coeffs(ch, k));
                v.integration_coeff_max_abs = std::max(v.integration_coeff_max_abs, e);
                max_ref = std::max(max_ref, std::abs(r.coeffs(ch, k)));
                sum_sq += e * e;
                ++n_sq;
            }
            const Eigen::VectorXd rc = r.coeffs.row(ch).transpose();
            for (int l = 0; l < n_lights; ++l) {
                const double sh_ref = dot_prefix(lcoef[l], rc.data(), kb);
                integ[l] = std::max(integ[l],
                                    rel(l, std::abs(dot_prefix(lcoef[l], b.data(), kb) - sh_ref)));
                trunc[l] = std::max(trunc[l], rel(l, std::abs(sh_ref - r.exact(ch, l))));
            }
        }
    }
    v.integration_coeff_rms = n_sq ? std::sqrt(sum_sq / n_sq) : 0;
    v.integration_coeff_max_rel = max_ref > 0 ? v.integration_coeff_max_abs / max_ref : 0;

    // Interpolation (a table of reference coefficients) and total (the baked table) at the
    // off-grid normals.
    Table ref_table = baked;
    ref_table.channels = 3;
    ref_table.resize();
    for (const auto& [node, r] : ref.at_node) {
        for (int ch = 0; ch < 3; ++ch) {
            for (int k = 0; k < kb; ++k) {
                ref_table.coeffs[ref_table.index(ch, node / grid.cols, node % grid.cols, k)] =
                    static_cast<float>(r.coeffs(ch, k));
            }
        }
    }
    std::vector<float> interp_k(kb), baked_k(kb);
    for (size_t j = 0; j < ref.normals.size(); ++j) {
        const Eigen::Vector3f nf = ref.normals[j].cast<float>();
        const ReferenceNormal& r = ref.at_normal[j];
        for (int ch = 0; ch < 3; ++ch) {
            lookup(ref_table, nf, ch, interp_k.data());
            lookup(baked, nf, ch_of(ch), baked_k.data());
            Eigen::VectorXd bi(kb), bb(kb);
            for (int k = 0; k < kb; ++k) {
                bi[k] = interp_k[k];
                bb[k] = baked_k[k];
                v.interpolation_coeff_max_abs =
                    std::max(v.interpolation_coeff_max_abs, std::abs(bi[k] - r.coeffs(ch, k)));
            }
            const Eigen::VectorXd rc = r.coeffs.row(ch).transpose();
            for (int l = 0; l < n_lights; ++l) {
                interp[l] =
                    std::max(interp[l], rel(l, std::abs(dot_prefix(lcoef[l], bi.data(), kb) -
                                                        dot_prefix(lcoef[l], rc.data(), kb))));
                total[l] = std::max(total[l], rel(l, std::abs(dot_prefix(lcoef[l], bb.data(), kb) -
                                                              r.exact(ch, l))));
            }
        }
    }
    for (int l = 0; l < n_lights; ++l) {
        v.integration_radiance_max_rel = std::max(v.integration_radiance_max_rel, integ[l]);
        v.interpolation_radiance_max_rel = std::max(v.interpolation_radiance_max_rel, interp[l]);
        v.truncation_radiance_max_rel = std::max(v.truncation_radiance_max_rel, trunc[l]);
        v.total_radiance_max_rel = std::max(v.total_radiance_max_rel, total[l]);
        v.per_lighting[lights[l].name] = {{"integration_radiance_max_rel", integ[l]},
                                          {"interpolation_radiance_max_rel", interp[l]},
                                          {"truncation_radiance_max_rel", trunc[l]},
                                          {"total_radiance_max_rel", total[l]},
                                          {"max_exact_radiance", scale[l]}};
    }
    v.time_s = ref.time_s +
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return v;
}

Validation validate(const Material& m, const Table& baked, const BakeOptions& o,
                    const ValidateOptions& vopt) {
    return validate(make_reference(m, baked.grid, o.view, vopt), baked);
}

int choose_bands(const std::vector<double>& by_bands, double max_error) {
    for (size_t b = 0; b < by_bands.size(); ++b) {
        if (by_bands[b] <= max_error) return static_cast<int>(b) + 1;
    }
    return 0;
}

int choose_bands(const Validation& v, double max_error) {
    return choose_bands(v.truncation_radiance_max_rel_by_bands, max_error);
}

}  // namespace inlight::brdf
