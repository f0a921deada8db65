#include "brdf/bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/number.h"
#include "core/parallel.h"
#include "core/sobol.h"
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
// Edge-on (wo.z = 0, the exact limit): see for_each_edge_on_node.
template <typename Fn>
void for_each_gl_node(const Material& m, const FacetView& fv, int n, Fn&& fn);

// wo.z = 0: every h with wo.h > 0 reflects above the horizon (wi.z = 2 (wo.h) h.z), so the
// domain is the half of the h hemisphere facing wo, where the limit integrand is smooth (brdf.h:
// GGX 2 F D (wo.h) / alpha, the report 2 F D (n.h), per unit solid angle of h). 2n GL nodes in
// phi_h over [phi_o - pi/2, phi_o + pi/2] x n GL nodes in tau, u = u(c = 0) + (u(1) - u(0))
// smoothstep(tau): the warp cancels D, and smoothstep's flat ends remove the square roots that
// sin(theta_h) and cos(theta_h) have in u at h = n and h.z -> 0 (u is quadratic in theta there).
constexpr double kMinWoH = 1e-8;

template <typename Fn>
void for_each_edge_on_node(const Warp& warp, const Eigen::Vector3d& wo, int n, Fn&& fn) {
    std::vector<double> x, w, xp, wp;
    sh::gauss_legendre(n, x, w);
    sh::gauss_legendre(2 * n, xp, wp);
    const double phi_o = std::atan2(wo.y(), wo.x());
    const double u0 = warp.u_of(0.0), du = warp.u_of(1.0) - u0;
    for (int j = 0; j < 2 * n; ++j) {
        const double phi = phi_o + 0.5 * kPi * xp[j], w_phi = 0.5 * kPi * wp[j];
        const double cp = std::cos(phi), sp = std::sin(phi);
        for (int i = 0; i < n; ++i) {
            const double tau = 0.5 * (x[i] + 1.0);
            const double c = warp.cos_of(u0 + du * tau * tau * (3.0 - 2.0 * tau));
            const double ph = warp.density(c);
            if (!(ph > 0) || !std::isfinite(ph)) continue;
            const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
            const Eigen::Vector3d h(s * cp, s * sp, c);
            const double wo_h = wo.dot(h);
            // Below kMinWoH, wi = reflect(wo, h) is -wo to rounding and the h that the lobe
            // recomputes from wo + wi is lost to cancellation; the h-measure skipped is < 2e-8
            // sr and the integrand per unit h-measure is bounded (F D (n.h) or F D (wo.h)).
            if (wo_h <= kMinWoH) continue;
            const Eigen::Vector3d wi = 2.0 * wo_h * h - wo;
            if (wi.z() <= 0) continue;
            const double w_u = 0.5 * w[i] * 6.0 * std::abs(du) * tau * (1.0 - tau);
            fn(wi.normalized(), w_u * w_phi / (2.0 * kPi) / ph * 4.0 * wo_h);
        }
    }
}

// The report's V-cavity G = min(1, 2 (n.h)(n.v)/(v.h), 2 (n.h)(n.l)/(v.h)) is continuous but
// has a kink wherever its active term changes, and a product rule across a kink converges only
// algebraically (the interior rows stopped at 7e-6 at 10^4 samples). Along one phi_h node's line
// these are isolated points in tau: appends to `kinks` (ascending, inside (0, 1)) the tau where
// the active term changes, found on a scan of kKinkScan steps and refined by bisection on the
// difference of the two terms to double precision. `h_of(tau)` is the line's half vector.
constexpr int kKinkScan = 48;

// Returns the number of changes the scan sees; kLocate = false only counts them.
template <bool kLocate, typename HOf>
int report_g_kinks(const Eigen::Vector3d& wo, HOf&& h_of, std::vector<double>* kinks) {
    // terms(tau): {1, 2 (n.h)(n.v)/(v.h), 2 (n.h)(n.l)/(v.h)}, n.l = 2 (v.h)(n.h) - n.v.
    const auto terms = [&](double tau, double e[3]) {
        const Eigen::Vector3d h = h_of(tau);
        const double vh = std::max(wo.dot(h), 1e-300), nh = h.z();
        e[0] = 1.0;
        e[1] = 2.0 * nh * wo.z() / vh;
        e[2] = 2.0 * nh * (2.0 * vh * nh - wo.z()) / vh;
    };
    const auto active = [](const double e[3]) {
        return e[1] < e[0] ? (e[2] < e[1] ? 2 : 1) : (e[2] < e[0] ? 2 : 0);
    };
    double e[3];
    terms(0.0, e);
    int prev = active(e), count = 0;
    double t_prev = 0.0;
    for (int k = 1; k <= kKinkScan; ++k) {
        const double t = static_cast<double>(k) / kKinkScan;
        terms(t, e);
        const int cur = active(e);
        if (cur == prev) {
            t_prev = t;
            continue;
        }
        ++count;
        if constexpr (kLocate) {
            // e[prev] - e[cur] changes sign on [t_prev, t]: <= 0 at t_prev, > 0 at t.
            double lo = t_prev, hi = t;
            for (int it = 0; it < 60 && hi - lo > 1e-16; ++it) {
                const double mid = 0.5 * (lo + hi);
                terms(mid, e);
                (e[prev] - e[cur] <= 0 ? lo : hi) = mid;
            }
            const double kink = 0.5 * (lo + hi);
            if (kink > 1e-12 && kink < 1.0 - 1e-12) kinks->push_back(kink);
        }
        prev = cur;
        t_prev = t;
    }
    return count;
}

// Gauss-Legendre nodes and weights on [-1, 1] per node count, computed once per count (a map:
// references stay valid while other counts are added).
class GaussLegendreCache {
  public:
    const std::pair<std::vector<double>, std::vector<double>>& get(int n) {
        auto& r = m_rules[n];
        if (r.first.empty()) sh::gauss_legendre(n, r.first, r.second);
        return r;
    }

  private:
    std::map<int, std::pair<std::vector<double>, std::vector<double>>> m_rules;
};

// GL nodes on a piece of relative length `len` out of (break_count - 1) pieces of a rule of n
// nodes: n for a single piece, else in proportion to the length, at least min(n, 3).
int nodes_on_piece(int n, size_t break_count, double len) {
    if (break_count == 2) return n;
    return std::max(std::min(n, 3), static_cast<int>(std::lround(n * len)));
}

// Gauss-Legendre quadrature over [0, 1] split at `breaks` (0, ..., 1): for each node of each
// piece [t0, t0 + len], fn(t0, len, x, w) with x and w the node and weight of the piece's rule
// on [-1, 1] (nodes_on_piece of n); the caller maps x into the piece.
template <typename Fn>
void for_each_piece_node(GaussLegendreCache& rules, int n, const std::vector<double>& breaks,
                         Fn&& fn) {
    for (size_t piece = 0; piece + 1 < breaks.size(); ++piece) {
        const double t0 = breaks[piece], len = breaks[piece + 1] - t0;
        const auto& [x, w] = rules.get(nodes_on_piece(n, breaks.size(), len));
        for (size_t i = 0; i < x.size(); ++i) fn(t0, len, x[i], w[i]);
    }
}

template <typename Fn>
void for_each_gl_node(const Material& m, const FacetView& fv, int n, Fn&& fn) {
    const Eigen::Vector3d& wo = fv.wo;
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
    const Warp warp{m};
    if (fv.edge_on) {
        for_each_edge_on_node(warp, wo, n, fn);
        return;
    }
    // phi is measured from wo's azimuth and split where wo.(cos phi, sin phi, 0) changes sign:
    // for grazing views the interval of theta_h switches there within ~wo.z, so each half gets
    // its own Gauss-Legendre rule (n nodes) instead of one periodic trapezoid rule.
    const double phi_o = std::atan2(wo.y(), wo.x());
    // One line of constant phi_h: its admissible theta_h interval as [ua, ua + 2 half] in u.
    struct Line {
        double cp = 1, sp = 0, ua = 0, half = 0;
    };
    const auto line_of = [&](double phi) {
        Line line;
        line.cp = std::cos(phi);
        line.sp = std::sin(phi);
        const double b = std::atan2(wo.x() * line.cp + wo.y() * line.sp, wo.z());
        const double theta_lo = std::max(0.0, 0.5 * b - 0.25 * kPi);
        const double theta_hi = 0.5 * b + 0.25 * kPi;
        double ua = warp.u_of(std::cos(theta_lo)), ub = warp.u_of(std::cos(theta_hi));
        if (ua > ub) std::swap(ua, ub);
        line.ua = ua;
        line.half = 0.5 * (ub - ua);
        return line;
    };
    // u = ua + (ub - ua) smoothstep(tau): flat ends take the square root out of sin(theta_h) at
    // h = n (u is quadratic in theta_h there) and soften the horizon end.
    const auto h_on = [&](const Line& line, double tau) {
        const double c = warp.cos_of(line.ua + 2.0 * line.half * tau * tau * (3.0 - 2.0 * tau));
        const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
        return Eigen::Vector3d(s * line.cp, s * line.sp, c);
    };
    const bool kinked = m.specular == Model::kCookTorranceReport;
    // The report's G: where a kink curve turns back (or leaves through the interval's ends) the
    // number of kinks on a line changes, and the integral over the line is not smooth in phi
    // there (grazing views: 7e-6 at 10^4 samples). Such phi split each half into pieces, found
    // on a scan of kKinkScan lines per half and refined by bisection on the count.
    const auto kink_count = [&](double phi) {
        const Line line = line_of(phi);
        if (!(line.half > 0)) return -1;
        return report_g_kinks<false>(wo, [&](double tau) { return h_on(line, tau); }, nullptr);
    };
    GaussLegendreCache rules;
    std::vector<double> breaks, phi_breaks;
    for (int half_index = 0; half_index < 2; ++half_index) {  // 0: facing wo's azimuth
        const double phi0 = phi_o - 0.5 * kPi + kPi * half_index;  // the half is [phi0, phi0 + pi]
        phi_breaks.assign(1, 0.0);
        if (kinked) {
            int prev = kink_count(phi0);
            for (int k = 1; k <= kKinkScan; ++k) {
                const double s_k = static_cast<double>(k) / kKinkScan;
                const int cur = kink_count(phi0 + kPi * s_k);
                if (cur == prev) continue;
                double lo = static_cast<double>(k - 1) / kKinkScan, hi = s_k;
                for (int it = 0; it < 40; ++it) {
                    const double mid = 0.5 * (lo + hi);
                    (kink_count(phi0 + kPi * mid) == prev ? lo : hi) = mid;
                }
                phi_breaks.push_back(0.5 * (lo + hi));
                prev = cur;
            }
        }
        phi_breaks.push_back(1.0);
        for_each_piece_node(
            rules, n, phi_breaks, [&](double s0, double s_len, double xs, double ws) {
                const double phi = phi_breaks.size() == 2
                                       ? phi_o + 0.5 * kPi * xs + kPi * half_index
                                       : phi0 + kPi * (s0 + 0.5 * s_len * (xs + 1.0));
                // GL weight on an interval of length pi s_len
                const double w_phi = 0.5 * kPi * s_len * ws;
                const Line line = line_of(phi);
                if (!(line.half > 0)) return;
                const auto h_of = [&](double tau) { return h_on(line, tau); };
                // tau in [0, 1], split at the kinks of the report's G.
                breaks.assign(1, 0.0);
                if (kinked) report_g_kinks<true>(wo, h_of, &breaks);
                breaks.push_back(1.0);
                for_each_piece_node(
                    rules, n, breaks, [&](double t0, double len, double xt, double wt) {
                        const double tau = t0 + 0.5 * len * (xt + 1.0);
                        const Eigen::Vector3d h = h_of(tau);
                        const double ph = warp.density(h.z());
                        if (!(ph > 0) || !std::isfinite(ph)) return;
                        const double wo_h = wo.dot(h);
                        if (wo_h <= 0) return;
                        const Eigen::Vector3d wi = 2.0 * wo_h * h - wo;
                        if (wi.z() <= 0) return;
                        const double w_u = 0.5 * len * wt * 12.0 * line.half * tau * (1.0 - tau);
                        fn(wi.normalized(), w_u * w_phi / (2.0 * kPi) / ph * 4.0 * wo_h);
                    });
            });
    }
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

Eigen::Vector3d FacetView::lobe_cos(const Material& m, const Eigen::Vector3d& wi) const {
    return wi.z() * (edge_on ? eval_baked_lobe_edge_on(m, wo, wi) : eval_baked_lobe(m, wo, wi));
}

FacetView facet_view(const Material& m, const Eigen::Vector3d& n, const Eigen::Vector3d& view) {
    FacetView fv;
    fv.wo = world_from_local(n).transpose() * view;
    if (std::abs(fv.wo.z()) < kEdgeOnCos) {
        if (baked_lobe_has_edge_on_limit(m)) {
            fv.wo = Eigen::Vector3d(fv.wo.x(), fv.wo.y(), 0.0).normalized();
            fv.edge_on = true;
        } else {
            fv.wo = Eigen::Vector3d(fv.wo.x(), fv.wo.y(), kCharlieEdgeOnCos).normalized();
        }
    }
    return fv;
}

constexpr EnumName<Integrator> kIntegratorNames[] = {
    {Integrator::kStratifiedMc, "stratified-mc"},
    {Integrator::kGaussLegendre, "gauss-legendre"},
    {Integrator::kSobolIs, "sobol-is"},
};

std::string to_string(Integrator integrator) { return enum_to_string(kIntegratorNames, integrator); }

Integrator integrator_from_string(const std::string& name) {
    return enum_from_string(kIntegratorNames, name, "integrator");
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
    if (std::abs(phi) > 360)
        throw UsageError(str(context, ": phi ", phi, " is outside [-360, 360]"));
    return view_from_deg(theta, phi);
}

Eigen::Vector3d view_from_deg(double theta_deg, double phi_deg) {
    return direction_from_spherical(theta_deg * kPi / 180.0, phi_deg * kPi / 180.0);
}

Eigen::MatrixXd project_normal(const Material& m, const Eigen::Vector3d& n, const BakeOptions& o) {
    const Eigen::Matrix3d frame = world_from_local(n);
    const FacetView fv = facet_view(m, n, o.view);
    Accumulator acc(o.sh_bands, frame);
    if (!fv.visible()) return acc.result();  // the view sees the back of this facet
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
                    acc.add(wi, weight * fv.lobe_cos(m, wi));
                }
            }
            break;
        }
        case Integrator::kGaussLegendre:
            for_each_gl_node(m, fv, gl_n_for_samples(o.samples),
                             [&](const Eigen::Vector3d& wi, double weight) {
                                 acc.add(wi, weight * fv.lobe_cos(m, wi));
                             });
            break;
        case Integrator::kSobolIs: {
            Rng rng(normal_stream(o.seed, n));
            const uint32_t shift0 = rng.next_u32(), shift1 = rng.next_u32();
            const double inv_n = 1.0 / o.samples;
            for (int i = 0; i < o.samples; ++i) {
                const uint32_t idx = static_cast<uint32_t>(i);
                const Eigen::Vector2d u(u32_to_unit(sobol::sample_u32(idx, 0) ^ shift0),
                                        u32_to_unit(sobol::sample_u32(idx, 1) ^ shift1));
                const Sample s = fv.edge_on ? sample_baked_lobe_edge_on(m, fv.wo, u)
                                            : sample_baked_lobe(m, fv.wo, u);
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

std::vector<double> lobe_energy_captured(const Material& m, const Eigen::Vector3d& n,
                                         const Eigen::Vector3d& view, int max_bands, int gl_n) {
    const Eigen::Matrix3d frame = world_from_local(n);
    const FacetView fv = facet_view(m, n, view);
    Accumulator acc(max_bands, frame);
    double energy = 0;
    if (fv.visible()) {
        for_each_gl_node(m, fv, gl_n, [&](const Eigen::Vector3d& wi, double weight) {
            const Eigen::Vector3d fc = fv.lobe_cos(m, wi);
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
