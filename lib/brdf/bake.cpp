#include "brdf/bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "core/check.h"
#include "core/error.h"
#include "core/number.h"
#include "core/parallel.h"
#include "sh/quadrature.h"
#include "sh/sh.h"

namespace inlight::brdf {
namespace {

uint64_t splitmix(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// Stream id of a normal: equal normals (to 1e-9) share random numbers, whatever their node.
uint64_t normal_stream(uint64_t seed, const Eigen::Vector3d& n) {
    uint64_t h = splitmix(seed);
    for (int i = 0; i < 3; ++i) {
        h = splitmix(h ^ static_cast<uint64_t>(std::llround(n[i] * 1e9)));
    }
    return h;
}

class Rng {
  public:
    explicit Rng(uint64_t stream) : m_state(stream) {}
    double next() {
        m_state += 0x9E3779B97F4A7C15ull;
        return static_cast<double>(splitmix(m_state) >> 11) * 0x1.0p-53;
    }
    uint32_t next_u32() {
        m_state += 0x9E3779B97F4A7C15ull;
        return static_cast<uint32_t>(splitmix(m_state) >> 32);
    }

  private:
    uint64_t m_state;
};

// Second Sobol dimension (primitive polynomial x + 1): V_1 = 2^31, V_k = V_{k-1} ^ (V_{k-1} >> 1).
uint32_t sobol_dim1(uint32_t i) {
    uint32_t r = 0;
    for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1) {
        if (i & 1u) r ^= v;
    }
    return r;
}
uint32_t reverse_bits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}
double u32_to_unit(uint32_t x) { return (static_cast<double>(x) + 0.5) * 0x1.0p-32; }

// Accumulates sum_i weight_i * value_i * Y(world_from_local * wi_i) into B (3 x count).
class Accumulator {
  public:
    Accumulator(int sh_bands, const Eigen::Matrix3d& world_from_local)
        : m_bands(sh_bands),
          m_frame(world_from_local),
          m_y(sh::count(sh_bands)),
          m_b(Eigen::MatrixXd::Zero(3, sh::count(sh_bands))) {}
    void add(const Eigen::Vector3d& wi_local, const Eigen::Vector3d& weighted_value) {
        const Eigen::Vector3d w = (m_frame * wi_local).normalized();
        sh::eval(m_bands, w, m_y.data());
        for (int k = 0; k < static_cast<int>(m_y.size()); ++k)
            m_b.col(k) += weighted_value * m_y[k];
    }
    Eigen::MatrixXd& result() { return m_b; }

  private:
    int m_bands;
    Eigen::Matrix3d m_frame;
    std::vector<double> m_y;
    Eigen::MatrixXd m_b;
};

// The lobe's half-vector warp: u in [0, 1] -> cos(theta_h), its inverse, and the density of h
// (solid angle) when u is uniform, D(h) (n.h) / normalisation.
struct Warp {
    const Material& m;
    double cos_of(double u) const {
        switch (m.specular) {
            case Model::kGgx: {
                const double a = std::max(m.alpha, kMinAlpha);
                return std::sqrt(std::max(0.0, (1.0 - u) / (1.0 + (a * a - 1.0) * u)));
            }
            case Model::kCookTorranceReport: {
                const double r = std::max(m.report_r, kMinAlpha);
                return std::sqrt(std::max(0.0, u / (1.0 + r * r * (1.0 - u))));
            }
            case Model::kCharlie: {
                const double a = std::clamp(m.alpha, kMinAlpha, 1.0);
                const double s = std::pow(u, a / (1.0 + 2.0 * a));
                return std::sqrt(std::max(0.0, 1.0 - s * s));
            }
            case Model::kLambert:
                break;
        }
        return u;
    }
    double u_of(double c) const {
        const double c2 = c * c;
        switch (m.specular) {
            case Model::kGgx: {
                const double a = std::max(m.alpha, kMinAlpha);
                return (1.0 - c2) / (1.0 + c2 * (a * a - 1.0));
            }
            case Model::kCookTorranceReport: {
                const double r = std::max(m.report_r, kMinAlpha);
                return c2 * (1.0 + r * r) / (1.0 + c2 * r * r);
            }
            case Model::kCharlie: {
                const double a = std::clamp(m.alpha, kMinAlpha, 1.0);
                return std::pow(std::max(0.0, 1.0 - c2), (1.0 + 2.0 * a) / (2.0 * a));
            }
            case Model::kLambert:
                break;
        }
        return c;
    }
    double density(double c) const {
        switch (m.specular) {
            case Model::kGgx:
                return ggx_d(std::max(m.alpha, kMinAlpha), c) * c;
            case Model::kCookTorranceReport: {
                const double r = std::max(m.report_r, kMinAlpha);
                return report_d(r, c) * c * (1.0 + r * r) / (r * r);
            }
            case Model::kCharlie:
                return charlie_d(std::clamp(m.alpha, kMinAlpha, 1.0), c) * c;
            case Model::kLambert:
                break;
        }
        return 0;
    }
};

// The deterministic rule: calls fn(wi_local, weight) so that sum weight g(wi) approximates
// the integral of g over the upper hemisphere for integrands that contain the lobe.
// Lambert: GL in cos(theta_i) on [0, 1] x 2n uniform phi (exact for polynomials).
// Specular lobes: for each of 2n phi_h nodes, the half vectors whose reflection of wo lies
// above the horizon form the interval theta_h in [max(0, b/2 - pi/4), b/2 + pi/4], b =
// atan2(wo.(cos phi, sin phi, 0), wo.z) (from a sin 2t + wo.z cos 2t > 0); n GL nodes span that
// interval in the warped variable u, so the integrand has no jump inside the rule.
template <typename Fn>
void for_each_gl_node(const Material& m, const Eigen::Vector3d& wo, int n, Fn&& fn) {
    std::vector<double> x, w;
    sh::gauss_legendre(n, x, w);
    const int n_phi = 2 * n;
    if (m.specular == Model::kLambert) {
        for (int i = 0; i < n; ++i) {
            const double c = 0.5 * (x[i] + 1.0), s = std::sqrt(std::max(0.0, 1.0 - c * c));
            for (int j = 0; j < n_phi; ++j) {
                const double phi = 2.0 * kPi * (j + 0.5) / n_phi;
                fn(Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), c),
                   0.5 * w[i] * 2.0 * kPi / n_phi);
            }
        }
        return;
    }
    // phi is measured from wo's azimuth and split where wo.(cos phi, sin phi, 0) changes sign:
    // for grazing views the interval of theta_h switches there within ~wo.z, so each half gets
    // its own Gauss-Legendre rule (n nodes) instead of one periodic trapezoid rule.
    const Warp warp{m};
    const double phi_o = std::atan2(wo.y(), wo.x());
    for (int j = 0; j < n_phi; ++j) {
        const int half_index = j / n;  // 0: facing wo's azimuth, 1: away from it
        const double phi = phi_o + 0.5 * kPi * x[j % n] + kPi * half_index;
        const double w_phi = 0.5 * kPi * w[j % n];  // GL weight on an interval of length pi
        const double cp = std::cos(phi), sp = std::sin(phi);
        const double b = std::atan2(wo.x() * cp + wo.y() * sp, wo.z());
        const double theta_lo = std::max(0.0, 0.5 * b - 0.25 * kPi);
        const double theta_hi = 0.5 * b + 0.25 * kPi;
        double ua = warp.u_of(std::cos(theta_lo)), ub = warp.u_of(std::cos(theta_hi));
        if (ua > ub) std::swap(ua, ub);
        const double half = 0.5 * (ub - ua);
        if (!(half > 0)) continue;
        for (int i = 0; i < n; ++i) {
            const double u = ua + half * (x[i] + 1.0);
            const double c = warp.cos_of(u);
            const double ph = warp.density(c);
            if (!(ph > 0) || !std::isfinite(ph)) continue;
            const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
            const Eigen::Vector3d h(s * cp, s * sp, c);
            const double wo_h = wo.dot(h);
            if (wo_h <= 0) continue;
            const Eigen::Vector3d wi = 2.0 * wo_h * h - wo;
            if (wi.z() <= 0) continue;
            fn(wi.normalized(), half * w[i] * w_phi / (2.0 * kPi) / ph * 4.0 * wo_h);
        }
    }
}

// The view in the facet's local frame. A normal exactly perpendicular to the view (|n.v| <
// 1e-7, e.g. the horizon row of thetaphi or report5x5 for the default view) takes the limit
// from the visible side (n.v = 1e-6), which is finite and non-zero for every model, instead of
// the 0 of a back-facing facet: interpolation toward the horizon then stays continuous.
Eigen::Vector3d facet_view(const Eigen::Matrix3d& frame, const Eigen::Vector3d& view) {
    Eigen::Vector3d wo = frame.transpose() * view;
    if (std::abs(wo.z()) < 1e-7) wo = Eigen::Vector3d(wo.x(), wo.y(), 1e-6).normalized();
    return wo;
}

int gl_n_for_samples(int samples) {
    return std::max(1, static_cast<int>(std::lround(std::sqrt(samples / 2.0))));
}

void check_options(const BakeOptions& o) {
    if (o.sh_bands < 1 || o.sh_bands > kMaxBakeBands) {
        throw UsageError(str("--sh-bands must be in [1, ", kMaxBakeBands, "], got ", o.sh_bands));
    }
    if (o.samples < 1) throw UsageError(str("--samples must be >= 1, got ", o.samples));
    if (std::abs(o.view.norm() - 1.0) > 1e-9) {
        throw UsageError("view direction must be a unit vector");
    }
}

}  // namespace

std::string to_string(Integrator integrator) {
    switch (integrator) {
        case Integrator::kStratifiedMc:
            return "stratified-mc";
        case Integrator::kGaussLegendre:
            return "gauss-legendre";
        case Integrator::kSobolIs:
            return "sobol-is";
    }
    return "?";
}

Integrator integrator_from_string(const std::string& name) {
    for (Integrator i :
         {Integrator::kStratifiedMc, Integrator::kGaussLegendre, Integrator::kSobolIs}) {
        if (name == to_string(i)) return i;
    }
    throw UsageError(str("unknown integrator '", name,
                         "' (expected stratified-mc, gauss-legendre or sobol-is)"));
}

Eigen::Vector3d parse_view(const std::string& xyz) {
    const std::string context = str("view '", xyz, "'");
    const std::vector<std::string> items = split(xyz, ',');
    if (items.size() != 3) throw UsageError(str(context, ": expected x,y,z"));
    Eigen::Vector3d d;
    for (int i = 0; i < 3; ++i) d[i] = parse_finite(items[static_cast<size_t>(i)], context);
    if (!(d.norm() > 0) || !std::isfinite(d.norm())) {
        throw UsageError(str(context, ": expected a non-zero direction"));
    }
    if (d.z() < 0) {
        throw UsageError(str(context, ": behind the screen (z < 0; +z points toward the viewer)"));
    }
    return d.normalized();
}

Eigen::Vector3d parse_view_deg(const std::string& text) {
    const std::string context = str("view '", text, "' (THETA[,PHI] in degrees)");
    const std::vector<std::string> items = split(text, ',');
    if (items.size() > 2) throw UsageError(str(context, ": expected at most two numbers"));
    const double theta = parse_finite(items[0], context);
    const double phi = items.size() == 2 ? parse_finite(items[1], context) : 0.0;
    if (theta < 0 || theta > 90) {
        throw UsageError(str(context, ": theta ", theta,
                             " is outside [0, 90]: the view would be behind the screen"));
    }
    if (std::abs(phi) > 360) throw UsageError(str(context, ": phi ", phi, " is outside [-360, 360]"));
    return view_from_deg(theta, phi);
}

Eigen::Vector3d view_from_deg(double theta_deg, double phi_deg) {
    return direction_from_spherical(theta_deg * kPi / 180.0, phi_deg * kPi / 180.0);
}

Eigen::MatrixXd project_normal(const Material& m, const Eigen::Vector3d& n, const BakeOptions& o) {
    const Eigen::Matrix3d frame = world_from_local(n);
    const Eigen::Vector3d wo = facet_view(frame, o.view);
    Accumulator acc(o.sh_bands, frame);
    if (wo.z() <= 0) return acc.result();  // the view sees the back of this facet
    switch (o.integrator) {
        case Integrator::kStratifiedMc: {
            Rng rng(normal_stream(o.seed, n));
            const int sq = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(o.samples))));
            const double weight = 4.0 * kPi / (static_cast<double>(sq) * sq);
            for (int a = 0; a < sq; ++a) {
                for (int b = 0; b < sq; ++b) {
                    const double p = (a + rng.next()) / sq;
                    const double q = (b + rng.next()) / sq;
                    const Eigen::Vector3d w = direction_from_spherical(
                        2.0 * std::acos(std::sqrt(1.0 - p)), 2.0 * kPi * q);
                    const Eigen::Vector3d wi = frame.transpose() * w;
                    if (wi.z() <= 0) continue;
                    acc.add(wi, weight * wi.z() * eval_baked_lobe(m, wo, wi));
                }
            }
            break;
        }
        case Integrator::kGaussLegendre:
            for_each_gl_node(m, wo, gl_n_for_samples(o.samples),
                             [&](const Eigen::Vector3d& wi, double weight) {
                                 acc.add(wi, weight * wi.z() * eval_baked_lobe(m, wo, wi));
                             });
            break;
        case Integrator::kSobolIs: {
            Rng rng(normal_stream(o.seed, n));
            const uint32_t shift0 = rng.next_u32(), shift1 = rng.next_u32();
            const double inv_n = 1.0 / o.samples;
            for (int i = 0; i < o.samples; ++i) {
                const uint32_t idx = static_cast<uint32_t>(i);
                const Eigen::Vector2d u(u32_to_unit(reverse_bits(idx) ^ shift0),
                                        u32_to_unit(sobol_dim1(idx) ^ shift1));
                const Sample s = sample_baked_lobe(m, wo, u);
                if (!s.valid) continue;
                acc.add(s.wi, inv_n * s.wi.z() / s.pdf * s.value);
            }
            break;
        }
    }
    return acc.result();
}

Table bake(const Material& m, const Grid& grid, const BakeOptions& o) {
    check_options(o);
    Table t;
    t.grid = grid;
    t.sh_bands = o.sh_bands;
    t.channels = baked_lobe_is_achromatic(m) ? 1 : 3;
    t.view = o.view;
    t.resize();
    const int k_count = t.coeff_count();
    parallel::for_chunks(grid.node_count(), 1, [&](int64_t begin, int64_t end) {
        for (int64_t node = begin; node < end; ++node) {
            const int i1 = static_cast<int>(node / grid.cols),
                      i2 = static_cast<int>(node % grid.cols);
            const Eigen::MatrixXd b = project_normal(m, grid_node_normal(grid, i1, i2), o);
            for (int ch = 0; ch < t.channels; ++ch) {
                for (int k = 0; k < k_count; ++k) {
                    t.coeffs[t.index(ch, i1, i2, k)] = static_cast<float>(b(ch, k));
                }
            }
        }
    });
    return t;
}

std::vector<TestLighting> test_lightings() {
    const Eigen::Vector3d key = view_from_deg(35, 90), window = view_from_deg(50, -20);
    return {
        {"uniform", [](const Eigen::Vector3d&) { return 1.0; }},
        {"front_gradient", [](const Eigen::Vector3d& w) { return 1.0 + w.z(); }},
        {"key_vmf10",
         [key](const Eigen::Vector3d& w) { return std::exp(10.0 * (key.dot(w) - 1.0)); }},
        {"window_vmf50",
         [window](const Eigen::Vector3d& w) { return std::exp(50.0 * (window.dot(w) - 1.0)); }},
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

ReferenceNormal reference_at(const Material& m, const Eigen::Vector3d& n,
                             const Eigen::Vector3d& view, int gl_n,
                             const std::vector<TestLighting>& lights) {
    const Eigen::Matrix3d frame = world_from_local(n);
    const Eigen::Vector3d wo = facet_view(frame, view);
    Accumulator acc(kMaxBakeBands, frame);
    ReferenceNormal r;
    r.exact = Eigen::MatrixXd::Zero(3, static_cast<int>(lights.size()));
    if (wo.z() > 0) {
        for_each_gl_node(m, wo, gl_n, [&](const Eigen::Vector3d& wi, double weight) {
            const Eigen::Vector3d v = weight * wi.z() * eval_baked_lobe(m, wo, wi);
            acc.add(wi, v);
            const Eigen::Vector3d w = (frame * wi).normalized();
            for (size_t l = 0; l < lights.size(); ++l) {
                r.exact.col(static_cast<int>(l)) += v * lights[l].radiance(w);
            }
        });
    }
    r.coeffs = acc.result();
    return r;
}

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
            {"reference_self_coeff_max_rel", reference_self_coeff_max_rel},
            {"nodes_checked", nodes_checked},
            {"test_normals", test_normals},
            {"per_lighting", per_lighting},
            {"validate_time_s", time_s}};
}

ReferenceSet make_reference(const Material& m, const Grid& grid, const Eigen::Vector3d& view,
                            const ValidateOptions& vopt) {
    const auto start = std::chrono::steady_clock::now();
    const auto lights = test_lightings();
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
    std::vector<ReferenceNormal> at_need(need.size());
    ref.at_normal.resize(ref.normals.size());
    const int64_t total = static_cast<int64_t>(need.size() + ref.normals.size());
    parallel::for_chunks(total, 1, [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
            if (i < static_cast<int64_t>(need.size())) {
                const int node = need[i];
                at_need[i] =
                    reference_at(m, grid_node_normal(grid, node / grid.cols, node % grid.cols),
                                 view, vopt.reference_gl_n, lights);
            } else {
                const size_t j = i - need.size();
                ref.at_normal[j] =
                    reference_at(m, ref.normals[j], view, vopt.reference_gl_n, lights);
            }
        }
    });
    for (size_t i = 0; i < need.size(); ++i) ref.at_node[need[i]] = std::move(at_need[i]);

    // The reference against itself at twice the nodes, at up to 4 checked nodes.
    const int self_count = std::min<int>(4, static_cast<int>(ref.nodes.size()));
    std::vector<double> self_err(self_count, 0.0);
    double max_ref = 0;
    for (int node : ref.nodes)
        max_ref = std::max(max_ref, ref.at_node[node].coeffs.cwiseAbs().maxCoeff());
    parallel::for_chunks(self_count, 1, [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
            // First and last checked nodes (the pole and horizon rows of thetaphi) and between.
            const size_t pick = self_count > 1 ? i * (ref.nodes.size() - 1) / (self_count - 1) : 0;
            const int node = ref.nodes[pick];
            const ReferenceNormal fine =
                reference_at(m, grid_node_normal(grid, node / grid.cols, node % grid.cols), view,
                             2 * vopt.reference_gl_n, lights);
            self_err[i] = (fine.coeffs - ref.at_node.at(node).coeffs).cwiseAbs().maxCoeff();
        }
    });
    for (double e : self_err) {
        ref.self_coeff_max_rel = std::max(ref.self_coeff_max_rel, max_ref > 0 ? e / max_ref : 0.0);
    }
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
    v.reference_self_coeff_max_rel = ref.self_coeff_max_rel;
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

std::vector<double> lobe_energy_captured(const Material& m, const Eigen::Vector3d& n,
                                         const Eigen::Vector3d& view, int max_bands, int gl_n) {
    const Eigen::Matrix3d frame = world_from_local(n);
    const Eigen::Vector3d wo = facet_view(frame, view);
    Accumulator acc(max_bands, frame);
    double energy = 0;
    if (wo.z() > 0) {
        for_each_gl_node(m, wo, gl_n, [&](const Eigen::Vector3d& wi, double weight) {
            const Eigen::Vector3d fc = wi.z() * eval_baked_lobe(m, wo, wi);
            acc.add(wi, weight * fc);
            energy += weight * fc.squaredNorm();
        });
    }
    std::vector<double> captured(max_bands, 0.0);
    double sum = 0;
    for (int b = 1; b <= max_bands; ++b) {
        for (int k = (b - 1) * (b - 1); k < b * b; ++k) sum += acc.result().col(k).squaredNorm();
        captured[b - 1] = energy > 0 ? std::min(1.0, sum / energy) : 1.0;
    }
    return captured;
}

int bands_for_lobe_error(const std::vector<double>& captured, double rel_l2_error) {
    for (size_t b = 0; b < captured.size(); ++b) {
        if (std::sqrt(std::max(0.0, 1.0 - captured[b])) <= rel_l2_error)
            return static_cast<int>(b) + 1;
    }
    return 0;
}

}  // namespace inlight::brdf
