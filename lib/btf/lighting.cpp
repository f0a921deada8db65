#include "btf/lighting.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>

#include "btf/interp.h"
#include "btf/sh_lighting.h"
#include "core/check.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"

namespace inlight::btf {

namespace {
/// Light directions nearer the horizon own no cell under CellRule::kCosine: cos(89.5 deg).
constexpr double kMinCellCos = 0.0087265;
}  // namespace

std::string to_string(CellRule rule) {
    switch (rule) {
        case CellRule::kConstant: return "constant";
        case CellRule::kCosine: return "cosine";
        case CellRule::kBarycentric: return "barycentric";
        case CellRule::kExtrapolated: return "extrapolated";
        case CellRule::kCosineBarycentric: return "cosine-barycentric";
    }
    return "?";
}

CellRule cell_rule_from_string(const std::string& name) {
    for (CellRule r : {CellRule::kConstant, CellRule::kCosine, CellRule::kBarycentric, CellRule::kExtrapolated,
                       CellRule::kCosineBarycentric})
        if (name == to_string(r)) return r;
    throw Error(str("light cell rule '", name,
                    "': expected constant, cosine, barycentric, extrapolated or cosine-barycentric"));
}

namespace {

/// Eligibility under the cosine-type rules: more than 0.5 deg above the horizon.
std::vector<char> cosine_eligible(const std::vector<Eigen::Vector3d>& lv, const char* who) {
    std::vector<char> eligible(lv.size(), 1);
    for (size_t k = 0; k < lv.size(); ++k) eligible[k] = lv[k].z() >= kMinCellCos;
    if (std::none_of(eligible.begin(), eligible.end(), [](char e) { return e != 0; }))
        throw Error(str(who, ": every light direction lies within 0.5 deg of the horizon"));
    return eligible;
}

LightTriangulation build_triangulation(const std::vector<Direction>& lights, const std::vector<char>* eligible) {
    std::vector<Direction> set = lights;
    for (int j = 0; j < 72; ++j) {
        const Direction h{90.0, 5.0 * j};
        if (!find_direction(lights, h, 1e-3)) set.push_back(h);
    }
    LightTriangulation t;
    t.triangles = DelaunayInterpolator(set).triangles();
    std::vector<Eigen::Vector3d> lv;
    for (const Direction& d : lights) lv.push_back(d.vector());
    for (const Direction& d : set) t.vertices.push_back(d.vector());
    for (size_t i = 0; i < set.size(); ++i) {
        if (i < lights.size() && (!eligible || (*eligible)[i]))
            t.owner.push_back(static_cast<int>(i));
        else
            t.owner.push_back(eligible ? nearest_light(lv, t.vertices[i], eligible) : -1);
    }
    return t;
}

/// A LightTriangulation with a hint for coherent queries: a query walks from the hint's triangle
/// across the edge facing the point (a few steps for a neighbouring point), and scans every
/// triangle only if the walk leaves the triangulation or goes round in circles.
class HorizonTriangulation {
  public:
    explicit HorizonTriangulation(LightTriangulation triangulation) : m_t(std::move(triangulation)) {
        // m_across[t][i]: the triangle sharing the edge opposite vertex i of t, or -1.
        std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (lo, hi) -> (triangle, i)
        m_across.assign(m_t.triangles.size(), {-1, -1, -1});
        for (size_t t = 0; t < m_t.triangles.size(); ++t) {
            for (int i = 0; i < 3; ++i) {
                const int a = m_t.triangles[t][size_t((i + 1) % 3)], b = m_t.triangles[t][size_t((i + 2) % 3)];
                const auto key = std::minmax(a, b);
                const auto it = edges.find(key);
                if (it == edges.end()) {
                    edges.emplace(key, std::make_pair(static_cast<int>(t), i));
                } else {
                    m_across[t][size_t(i)] = it->second.first;
                    m_across[size_t(it->second.first)][size_t(it->second.second)] = static_cast<int>(t);
                }
            }
        }
    }
    /// Adds the barycentric weight of each vertex of the triangle holding d to its owner;
    /// `hint` is the triangle the previous query found (updated).
    template <typename Add>
    void spread(const Eigen::Vector3d& d, size_t& hint, const Add& add) const {
        const size_t n_tri = m_t.triangles.size();
        if (n_tri == 0) return;
        double w[3];
        size_t t = hint % n_tri;
        bool found = false;
        for (size_t step = 0; step < 64 && !found; ++step) {  // the walk
            coordinates(t, d, w);
            int worst = 0;
            for (int i = 1; i < 3; ++i)
                if (w[i] < w[worst]) worst = i;
            if (w[worst] >= -1e-12) {
                found = inside(w);
                break;
            }
            const int next = m_across[t][size_t(worst)];
            if (next < 0) break;
            t = static_cast<size_t>(next);
        }
        for (size_t n = 0; n < n_tri && !found; ++n) {  // the scan
            t = (hint + n) % n_tri;
            coordinates(t, d, w);
            found = w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] >= -1e-12 && inside(w);
        }
        if (!found) return;
        hint = t;
        const double s = std::max(0.0, w[0]) + std::max(0.0, w[1]) + std::max(0.0, w[2]);
        for (int i = 0; i < 3; ++i) {
            const int owner = m_t.owner[size_t(m_t.triangles[t][size_t(i)])];
            if (owner >= 0) add(size_t(owner), std::max(0.0, w[i]) / s);
        }
    }

  private:
    void coordinates(size_t t, const Eigen::Vector3d& d, double* w) const {
        const auto& v = m_t.triangles[t];
        const Eigen::Vector3d &a = m_t.vertices[size_t(v[0])], &b = m_t.vertices[size_t(v[1])],
                              &c = m_t.vertices[size_t(v[2])];
        w[0] = d.dot(b.cross(c));
        w[1] = a.dot(d.cross(c));
        w[2] = a.dot(b.cross(d));
    }
    static bool inside(const double* w) {
        return std::max(0.0, w[0]) + std::max(0.0, w[1]) + std::max(0.0, w[2]) > 0;
    }

    LightTriangulation m_t;
    std::vector<std::array<int, 3>> m_across;
};

/// Per light: its inner partner for CellRule::kExtrapolated (the nearest light of the next ring
/// in, by angle) when the light lies on the outermost ring (within 1 deg of the largest theta),
/// else -1.
std::vector<int> outer_ring_partners(const std::vector<Eigen::Vector3d>& lv, const std::vector<char>& eligible) {
    double min_z = 2;
    for (size_t k = 0; k < lv.size(); ++k)
        if (eligible[k]) min_z = std::min(min_z, lv[k].z());
    const double theta_max = std::acos(std::clamp(min_z, -1.0, 1.0));
    constexpr double kRingTol = kPi / 180;
    // The next ring in: the largest theta below theta_max - 1 deg.
    double inner_theta = -1;
    for (size_t k = 0; k < lv.size(); ++k) {
        const double th = std::acos(std::clamp(lv[k].z(), -1.0, 1.0));
        if (eligible[k] && th < theta_max - kRingTol) inner_theta = std::max(inner_theta, th);
    }
    std::vector<int> partner(lv.size(), -1);
    if (inner_theta < 0) return partner;
    for (size_t k = 0; k < lv.size(); ++k) {
        const double th = std::acos(std::clamp(lv[k].z(), -1.0, 1.0));
        if (!eligible[k] || th < theta_max - kRingTol) continue;
        double best = -2;
        for (size_t j = 0; j < lv.size(); ++j) {
            const double tj = std::acos(std::clamp(lv[j].z(), -1.0, 1.0));
            if (!eligible[j] || std::abs(tj - inner_theta) > kRingTol) continue;
            if (lv[j].dot(lv[k]) > best) {
                best = lv[j].dot(lv[k]);
                partner[k] = static_cast<int>(j);
            }
        }
    }
    return partner;
}

/// Adds light arriving from unit d (sample frame) with radiance x solid angle `l_omega` to the
/// weights under the cosine-type rules: the cell's light k, and beyond an outer light its
/// extrapolation partner.
template <typename Add>
void add_cosine_weight(const std::vector<Eigen::Vector3d>& lv, const std::vector<int>* partner, size_t k,
                       const Eigen::Vector3d& d, const Add& add) {
    const double cos_ratio = d.z() / lv[k].z();
    const int j = partner ? (*partner)[k] : -1;
    if (j < 0 || d.z() >= lv[k].z()) {
        add(k, cos_ratio);
        return;
    }
    const double th = std::acos(std::clamp(d.z(), -1.0, 1.0));
    const double tk = std::acos(std::clamp(lv[k].z(), -1.0, 1.0));
    const double tj = std::acos(std::clamp(lv[size_t(j)].z(), -1.0, 1.0));
    const double t = (th - tk) / (tk - tj);
    add(k, cos_ratio * (1 + t));
    add(size_t(j), -d.z() / lv[size_t(j)].z() * t);
}

}  // namespace

LightTriangulation light_triangulation(const std::vector<Direction>& lights, CellRule rule) {
    if (rule != CellRule::kBarycentric && rule != CellRule::kCosineBarycentric)
        throw Error(str("light triangulation: the ", to_string(rule), " rule has none"));
    if (lights.empty()) throw Error("light triangulation: no light directions");
    if (rule == CellRule::kBarycentric) return build_triangulation(lights, nullptr);
    std::vector<Eigen::Vector3d> lv;
    for (const Direction& d : lights) lv.push_back(d.vector());
    const std::vector<char> eligible = cosine_eligible(lv, "light triangulation");
    return build_triangulation(lights, &eligible);
}

int nearest_light(const std::vector<Eigen::Vector3d>& light_vectors, const Eigen::Vector3d& d,
                  const std::vector<char>* eligible) {
    int best = 0;
    double best_cos = -2;
    for (size_t k = 0; k < light_vectors.size(); ++k) {
        if (eligible && !(*eligible)[k]) continue;
        const double c = light_vectors[k].dot(d);
        if (c > best_cos) {
            best_cos = c;
            best = static_cast<int>(k);
        }
    }
    return best;
}

std::vector<ImageTerm> shading_terms(const DomeLighting& lighting, const std::vector<int>& views,
                                     const std::vector<double>& view_weights, double irradiance_w_m2) {
    INLIGHT_CHECK_EQ(views.size(), view_weights.size());
    INLIGHT_CHECK(irradiance_w_m2 > 0) << irradiance_w_m2;
    std::vector<ImageTerm> terms;
    for (size_t b = 0; b < views.size(); ++b)
        for (size_t l = 0; l < lighting.weight.size(); ++l)
            terms.push_back({static_cast<int>(l), views[b], lighting.weight[l] * (view_weights[b] / irradiance_w_m2)});
    return terms;
}

namespace {

/// The checks of integrate_dome_cells on a map of at least min_channels channels.
void check_dome_inputs(const image::Image& latlong, int min_channels, const std::vector<Direction>& lights,
                       const DomeLightingOptions& options) {
    if (latlong.height < 1 || latlong.width != 2 * latlong.height) {
        throw Error(str("dome lighting: expected a 2:1 lat-long map, got ", latlong.width, "x",
                        latlong.height));
    }
    if (latlong.channels < min_channels) {
        throw Error(str("dome lighting: expected >= ", min_channels, " channels, got ", latlong.channels));
    }
    if (latlong.color_space != image::ColorSpace::kLinearSrgb) {
        throw Error(str("dome lighting: expected linear_srgb radiance, got ",
                        image::to_string(latlong.color_space)));
    }
    if (lights.empty()) throw Error("dome lighting: no light directions");
    if (options.subsamples < 1 || options.subsamples > 64) {
        throw Error(str("dome lighting: subsamples must be in [1, 64], got ", options.subsamples));
    }
    if (std::abs(options.sample_from_env.determinant() - 1.0) > 1e-9 ||
        !(options.sample_from_env * options.sample_from_env.transpose())
             .isApprox(Eigen::Matrix3d::Identity(), 1e-9)) {
        throw Error("dome lighting: sample_from_env is not a rotation");
    }
    for (float v : latlong.pixels) {
        if (!std::isfinite(v)) throw Error("dome lighting: the map holds NaN or Inf");
    }
}

/// The first `channels` channels of the map integrated over every light's cell: weight (light
/// major, n x channels), the cells' solid angles and the lower hemisphere's integral. Each map
/// direction's cell (or triangle) is found once, whatever the channel count.
struct CellSums {
    std::vector<double> weight;
    std::vector<double> omega;
    std::vector<double> below;
};

CellSums integrate_cells(const image::Image& latlong, int channels, const std::vector<Direction>& lights,
                         const DomeLightingOptions& options) {
    std::vector<Eigen::Vector3d> lv;
    for (const Direction& d : lights) lv.push_back(d.vector());
    const bool extrapolated = options.rule == CellRule::kExtrapolated;
    const bool cos_bary = options.rule == CellRule::kCosineBarycentric;
    const bool cosine = options.rule == CellRule::kCosine || extrapolated || cos_bary;
    const bool barycentric = options.rule == CellRule::kBarycentric || cos_bary;
    const std::vector<char> eligible = cosine ? cosine_eligible(lv, "dome lighting") : std::vector<char>(lv.size(), 1);
    std::unique_ptr<HorizonTriangulation> tri;
    if (barycentric)
        tri = std::make_unique<HorizonTriangulation>(build_triangulation(lights, cos_bary ? &eligible : nullptr));
    const std::vector<int> partner = extrapolated ? outer_ring_partners(lv, eligible) : std::vector<int>();

    const int w = latlong.width, h = latlong.height, s = options.subsamples, nc = latlong.channels;
    const size_t n = lights.size(), c_count = static_cast<size_t>(channels);
    // Per row: the weights, solid angles and below-horizon sum; combined in row order.
    const CellSums identity{std::vector<double>(n * c_count, 0.0), std::vector<double>(n, 0.0),
                            std::vector<double>(c_count, 0.0)};
    return parallel::reduce(
        h, 1, identity,
        [&](int64_t r0, int64_t r1) {
            CellSums p = identity;
            size_t hint = 0;
            for (int64_t row = r0; row < r1; ++row) {
                const double z0 = std::cos(kPi * row / h), z1 = std::cos(kPi * (row + 1) / h);
                const double sub_omega = (z0 - z1) / s * (2 * kPi / w) / s;
                for (int col = 0; col < w; ++col) {
                    const float* l = &latlong.pixels[(static_cast<size_t>(row) * w + col) * nc];
                    auto add = [&](size_t k, double f) {
                        double* wk = &p.weight[k * c_count];
                        for (size_t c = 0; c < c_count; ++c) wk[c] += l[c] * f;
                    };
                    for (int a = 0; a < s; ++a) {
                        const double z = z0 + (a + 0.5) / s * (z1 - z0);
                        const double rr = std::sqrt(std::max(0.0, 1 - z * z));
                        for (int b = 0; b < s; ++b) {
                            const double phi = kPi * (1.0 - 2.0 * (col + (b + 0.5) / s) / w);
                            const Eigen::Vector3d d =
                                options.sample_from_env *
                                Eigen::Vector3d(rr * std::cos(phi), rr * std::sin(phi), z);
                            if (d.z() <= 0) {
                                for (size_t c = 0; c < c_count; ++c) p.below[c] += l[c] * sub_omega;
                                continue;
                            }
                            if (barycentric) {
                                tri->spread(d, hint, [&](size_t k, double beta) {
                                    const double f = cos_bary ? beta * d.z() / lv[k].z() : beta;
                                    add(k, sub_omega * f);
                                    p.omega[k] += sub_omega * beta;
                                });
                                continue;
                            }
                            const auto k = static_cast<size_t>(
                                nearest_light(lv, d, cosine ? &eligible : nullptr));
                            p.omega[k] += sub_omega;
                            if (!cosine) {
                                add(k, sub_omega);
                                continue;
                            }
                            add_cosine_weight(lv, extrapolated ? &partner : nullptr, k, d,
                                              [&](size_t i, double f) { add(i, sub_omega * f); });
                        }
                    }
                }
            }
            return p;
        },
        [](CellSums a, const CellSums& b) {
            for (size_t i = 0; i < a.weight.size(); ++i) a.weight[i] += b.weight[i];
            for (size_t k = 0; k < a.omega.size(); ++k) a.omega[k] += b.omega[k];
            for (size_t c = 0; c < a.below.size(); ++c) a.below[c] += b.below[c];
            return a;
        });
}

}  // namespace

DomeLighting integrate_dome_cells(const image::Image& latlong, const std::vector<Direction>& lights,
                                  const DomeLightingOptions& options) {
    check_dome_inputs(latlong, 3, lights, options);
    const CellSums sums = integrate_cells(latlong, 3, lights, options);
    DomeLighting out;
    for (size_t k = 0; k < lights.size(); ++k)
        out.weight.emplace_back(sums.weight[3 * k], sums.weight[3 * k + 1], sums.weight[3 * k + 2]);
    out.solid_angle_sr = sums.omega;
    out.below_horizon = Eigen::Vector3d(sums.below[0], sums.below[1], sums.below[2]);
    return out;
}

Eigen::MatrixXd integrate_dome_cells_channels(const image::Image& map, const std::vector<Direction>& lights,
                                              const DomeLightingOptions& options) {
    check_dome_inputs(map, 1, lights, options);
    const CellSums sums = integrate_cells(map, map.channels, lights, options);
    Eigen::MatrixXd out(static_cast<Eigen::Index>(lights.size()), map.channels);
    for (size_t k = 0; k < lights.size(); ++k)
        for (int c = 0; c < map.channels; ++c)
            out(static_cast<Eigen::Index>(k), c) = sums.weight[k * static_cast<size_t>(map.channels) + static_cast<size_t>(c)];
    return out;
}

}  // namespace inlight::btf

namespace inlight::btf {

struct PointLightWeights::Impl {
    DomeLightingOptions options;
    std::vector<Eigen::Vector3d> lv;
    std::vector<char> eligible;
    std::vector<int> partner;  ///< kExtrapolated: each outer direction's inner partner
    std::unique_ptr<HorizonTriangulation> tri;  ///< kBarycentric
};

PointLightWeights::PointLightWeights(const std::vector<Direction>& lights, const DomeLightingOptions& options)
    : m_impl(std::make_unique<Impl>()) {
    if (lights.empty()) throw Error("directional light weights: no light directions");
    Impl& m = *m_impl;
    m.options = options;
    for (const Direction& l : lights) m.lv.push_back(l.vector());
    if (options.rule == CellRule::kCosine || options.rule == CellRule::kExtrapolated ||
        options.rule == CellRule::kCosineBarycentric) {
        m.eligible = cosine_eligible(m.lv, "directional light weights");
        if (options.rule == CellRule::kExtrapolated) m.partner = outer_ring_partners(m.lv, m.eligible);
        if (options.rule == CellRule::kCosineBarycentric)
            m.tri = std::make_unique<HorizonTriangulation>(build_triangulation(lights, &m.eligible));
    } else if (options.rule == CellRule::kBarycentric) {
        m.tri = std::make_unique<HorizonTriangulation>(build_triangulation(lights, nullptr));
    }
}
PointLightWeights::~PointLightWeights() = default;
PointLightWeights::PointLightWeights(PointLightWeights&&) noexcept = default;
PointLightWeights& PointLightWeights::operator=(PointLightWeights&&) noexcept = default;

bool PointLightWeights::add(const Eigen::Vector3d& direction, const Eigen::Vector3d& irradiance,
                            std::vector<Eigen::Vector3d>& weight, size_t* hint_io) const {
    size_t local_hint = 0;
    size_t& hint = hint_io ? *hint_io : local_hint;
    if (!direction.allFinite() || std::abs(direction.norm() - 1.0) > 1e-6) {
        throw Error("directional light weights: the light's direction is not a finite unit vector");
    }
    if (!irradiance.allFinite()) throw Error("directional light weights: the irradiance holds NaN or Inf");
    const Impl& m = *m_impl;
    if (weight.size() != m.lv.size()) throw Error("directional light weights: one weight per light direction expected");
    const Eigen::Vector3d d = m.options.sample_from_env * direction;
    if (d.z() <= 0) return false;  // at or below the sample's plane: no light direction sees it
    switch (m.options.rule) {
        case CellRule::kConstant:
            weight[static_cast<size_t>(nearest_light(m.lv, d))] += irradiance;
            break;
        case CellRule::kCosine:
        case CellRule::kExtrapolated: {
            const auto k = static_cast<size_t>(nearest_light(m.lv, d, &m.eligible));
            add_cosine_weight(m.lv, m.partner.empty() ? nullptr : &m.partner, k, d,
                              [&](size_t i, double f) { weight[i] += irradiance * f; });
            break;
        }
        case CellRule::kBarycentric:
            m.tri->spread(d, hint, [&](size_t k, double beta) { weight[k] += irradiance * beta; });
            break;
        case CellRule::kCosineBarycentric:
            m.tri->spread(d, hint,
                          [&](size_t k, double beta) { weight[k] += irradiance * (beta * d.z() / m.lv[k].z()); });
            break;
    }
    return true;
}

DomeLighting directional_light_weights(const std::vector<Direction>& lights,
                                       const Eigen::Vector3d& direction,
                                       const Eigen::Vector3d& irradiance,
                                       const DomeLightingOptions& options) {
    const PointLightWeights spread(lights, options);
    DomeLighting out;
    out.weight.assign(lights.size(), Eigen::Vector3d::Zero());
    out.solid_angle_sr.assign(lights.size(), 0.0);
    if (!spread.add(direction, irradiance, out.weight)) out.below_horizon = irradiance;
    return out;
}

}  // namespace inlight::btf
