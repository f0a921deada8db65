#include "btf/interp.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"

namespace inlight::btf {
namespace {

/// Ties and zero tests on determinants of unit vectors: a few ulps of their O(1) products.
constexpr double kDetEps = 1e-12;
/// Directions closer than this are the same direction (dome.h's duplicate tolerance).
constexpr double kSameDeg = 1e-6;

void check_unit(const Eigen::Vector3d& d) {
    if (!d.allFinite() || std::abs(d.norm() - 1) > 1e-6)
        throw Error(str("angular interpolation: the query (", d.x(), ", ", d.y(), ", ", d.z(),
                        ") is not a unit vector"));
}

double det3(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return a.dot(b.cross(c));
}

double wrap360(double deg) {
    double r = std::fmod(deg, 360.0);
    if (r < 0) r += 360.0;
    return r;
}

/// Weights of `p` between a and b along their great-circle arc, p on the arc: p = alpha a +
/// beta b; alpha ~ |p x b|, beta ~ |a x p| (the triangle weights restricted to the edge).
std::array<double, 2> arc_weights(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& p) {
    const double wa = p.cross(b).norm(), wb = a.cross(p).norm();
    const double s = wa + wb;
    if (!(s > 0)) return {1.0, 0.0};
    return {wa / s, wb / s};
}

/// Drops weights below kDetEps (rounding of an exact zero, e.g. on a measured direction or an
/// edge) and renormalises, so that a measured direction takes one sample, an edge two.
DirectionWeights compact(DirectionWeights w) {
    DirectionWeights out;
    out.outside_deg = w.outside_deg;
    double s = 0;
    for (int i = 0; i < w.count; ++i)
        if (w.weight[size_t(i)] > kDetEps) {
            out.index[size_t(out.count)] = w.index[size_t(i)];
            out.weight[size_t(out.count)] = w.weight[size_t(i)];
            s += w.weight[size_t(i)];
            ++out.count;
        }
    if (out.count == 0) return w;
    for (int i = 0; i < out.count; ++i) out.weight[size_t(i)] /= s;
    return out;
}

}  // namespace

constexpr EnumName<InterpScheme> kInterpSchemeNames[] = {
    {InterpScheme::kThesis, "thesis"},
    {InterpScheme::kDelaunay, "delaunay"},
    {InterpScheme::kNearest, "nearest"},
};

std::string to_string(InterpScheme s) { return enum_to_string(kInterpSchemeNames, s); }

InterpScheme interp_scheme_from_string(const std::string& name) {
    return enum_from_string(kInterpSchemeNames, name, "interpolation scheme");
}

Eigen::VectorXd dense_weights(const DirectionWeights& w, int n) {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < w.count; ++i) out[w.index[size_t(i)]] += w.weight[size_t(i)];
    return out;
}

// ---- the thesis' scheme ----

ThesisInterpolator::ThesisInterpolator(const std::vector<Direction>& set) {
    if (set.empty()) throw Error("thesis interpolation: empty direction set");
    std::vector<int> order(set.size());
    for (size_t i = 0; i < set.size(); ++i) order[i] = int(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return set[size_t(a)].theta_deg < set[size_t(b)].theta_deg;
    });
    for (int i : order) {
        if (m_rings.empty() || set[size_t(i)].theta_deg - m_rings.back().theta_deg > kSameDeg) {
            m_rings.emplace_back();
            m_rings.back().theta_deg = set[size_t(i)].theta_deg;
        }
        m_rings.back().index.push_back(i);
    }
    for (Ring& r : m_rings) {
        const size_t n = r.index.size();
        if (r.theta_deg < kSameDeg && n != 1)
            throw Error(str("thesis interpolation: ", n, " directions at theta 0"));
        std::sort(r.index.begin(), r.index.end(), [&](int a, int b) {
            return wrap360(set[size_t(a)].phi_deg) < wrap360(set[size_t(b)].phi_deg);
        });
        r.step_deg = 360.0 / double(n);
        r.phi0_deg = wrap360(set[size_t(r.index[0])].phi_deg);
        for (size_t j = 0; j < n; ++j) {
            const double phi = wrap360(set[size_t(r.index[j])].phi_deg);
            if (r.theta_deg >= kSameDeg && std::abs(phi - r.phi0_deg - double(j) * r.step_deg) > kSameDeg)
                throw Error(str("thesis interpolation needs rings of evenly spaced azimuths: the ring at theta ",
                                r.theta_deg, " deg has ", n, " directions, but direction ", r.index[j],
                                " is at phi ", phi, ", not ", r.phi0_deg + double(j) * r.step_deg));
        }
    }
    for (const Direction& d : set) m_vec.push_back(d.vector());
}

std::pair<int, int> ThesisInterpolator::bracket(const Ring& r, double phi_deg, double* t) const {
    const int n = static_cast<int>(r.index.size());
    const double u = wrap360(phi_deg - r.phi0_deg) / r.step_deg;
    int j = static_cast<int>(std::floor(u));
    double f = u - j;
    if (j >= n) {  // u rounded up to n
        j = 0;
        f = 0;
    }
    if (t) *t = f;
    return {j, (j + 1) % n};
}

DirectionWeights ThesisInterpolator::weights(const Eigen::Vector3d& d) const {
    check_unit(d);
    const double theta = std::acos(std::clamp(d.z(), -1.0, 1.0)) * 180.0 / kPi;
    const double phi = std::abs(d.x()) + std::abs(d.y()) > 0 ? wrap360(std::atan2(d.y(), d.x()) * 180.0 / kPi) : 0.0;
    // f^l and f^u over the set's rings: the last ring at or above theta, the first below it.
    int lo = -1;
    for (size_t i = 0; i < m_rings.size(); ++i)
        if (m_rings[i].theta_deg <= theta + kSameDeg) lo = int(i);
    const int hi = lo + 1 < int(m_rings.size()) ? lo + 1 : -1;
    DirectionWeights w;
    auto linear_on = [&](const Ring& r) {  // "beyond the measuring directions": linear in phi
        double t = 0;
        const auto [a, b] = bracket(r, phi, &t);
        w.count = a == b ? 1 : 2;
        w.index = {r.index[size_t(a)], r.index[size_t(b)], 0};
        w.weight = {a == b ? 1.0 : 1 - t, a == b ? 0.0 : t, 0};
        w.outside_deg = std::abs(theta - r.theta_deg) > kSameDeg ? std::abs(theta - r.theta_deg) : 0.0;
        return compact(w);
    };
    if (lo < 0) return linear_on(m_rings.front());
    if (hi < 0) return linear_on(m_rings[size_t(lo)]);
    const Ring &rl = m_rings[size_t(lo)], &ru = m_rings[size_t(hi)];
    const auto [a, b] = bracket(rl, phi, nullptr);
    const auto [c, dd] = bracket(ru, phi, nullptr);
    const int A = rl.index[size_t(a)], B = rl.index[size_t(b)], C = ru.index[size_t(c)], D = ru.index[size_t(dd)];
    std::array<int, 3> tri;
    if (A == B) tri = {A, C, D};
    else if (C == D) tri = {A, B, C};
    // d' = cos of the angle: the larger, the nearer (4.4.1).
    else if (d.dot(m_vec[size_t(A)]) >= d.dot(m_vec[size_t(D)])) tri = {A, B, C};
    else tri = {B, C, D};
    const Eigen::Vector3d &p1 = m_vec[size_t(tri[0])], &p2 = m_vec[size_t(tri[1])], &p3 = m_vec[size_t(tri[2])];
    std::array<double, 3> v = {std::abs(det3(d, p2, p3)), std::abs(det3(d, p3, p1)), std::abs(det3(d, p1, p2))};
    const double s = v[0] + v[1] + v[2];
    w.count = 3;
    w.index = tri;
    for (int i = 0; i < 3; ++i) w.weight[size_t(i)] = s > 0 ? v[size_t(i)] / s : (i == 0 ? 1.0 : 0.0);
    return compact(w);
}

// ---- the spherical Delaunay reference ----

DelaunayInterpolator::DelaunayInterpolator(const std::vector<Direction>& set) {
    const int n = static_cast<int>(set.size());
    if (n < 3) throw Error(str("Delaunay interpolation: needs at least 3 directions, got ", n));
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < i; ++j)
            if (angle_between_deg(set[size_t(i)], set[size_t(j)]) < kSameDeg)
                throw Error(str("Delaunay interpolation: directions ", j, " and ", i, " (theta ",
                                set[size_t(i)].theta_deg, ", phi ", set[size_t(i)].phi_deg,
                                " deg) are the same direction"));
    for (const Direction& d : set) m_vec.push_back(d.vector());
    // The hull of the directions and the origin: the faces away from the origin are the
    // spherical Delaunay triangles; faces through the origin close a set within a hemisphere.
    std::vector<coordT> pts;
    for (const auto& v : m_vec) pts.insert(pts.end(), {v.x(), v.y(), v.z()});
    pts.insert(pts.end(), {0.0, 0.0, 0.0});
    char* buf = nullptr;
    size_t len = 0;
    FILE* err = open_memstream(&buf, &len);
    qhT qh_qh;
    qhT* qh = &qh_qh;
    qh_zero(qh, err);
    char cmd[] = "qhull Qt";
    const int code = qh_new_qhull(qh, 3, n + 1, pts.data(), False, cmd, nullptr, err);
    if (code == 0) {
        facetT* facet;
        FORALLfacets {
            std::array<int, 3> t{{-1, -1, -1}};
            int k = 0;
            bool origin = false;
            vertexT *vertex, **vertexp;
            FOREACHvertex_(facet->vertices) {
                const int id = qh_pointid(qh, vertex->point);
                if (id == n) origin = true;
                if (k < 3) t[size_t(k)] = id;
                ++k;
            }
            if (origin || k != 3 || !(facet->offset < -kDetEps)) continue;
            double det = det3(m_vec[size_t(t[0])], m_vec[size_t(t[1])], m_vec[size_t(t[2])]);
            if (det < 0) {
                std::swap(t[1], t[2]);
                det = -det;
            }
            if (det > kDetEps) m_tri.push_back(t);
        }
    }
    qh_freeqhull(qh, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(qh, &curlong, &totlong);
    std::fclose(err);
    std::string message(buf ? buf : "", len);
    std::free(buf);
    if (code != 0 || m_tri.empty()) {
        throw Error(str("Delaunay interpolation: the ", n,
                        " directions lie on one great circle (no spherical triangle): ",
                        message.substr(0, message.find('\n'))));
    }
    std::sort(m_tri.begin(), m_tri.end());  // Qhull's facet order is not part of the result
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : m_tri)
        for (int e = 0; e < 3; ++e) ++edges[{t[size_t(e)], t[size_t((e + 1) % 3)]}];
    for (const auto& [e, count] : edges)
        if (edges.find({e.second, e.first}) == edges.end()) m_boundary.push_back({e.first, e.second});
}

DirectionWeights DelaunayInterpolator::weights(const Eigen::Vector3d& d) const {
    check_unit(d);
    DirectionWeights w;
    for (const auto& t : m_tri) {
        const Eigen::Vector3d &a = m_vec[size_t(t[0])], &b = m_vec[size_t(t[1])], &c = m_vec[size_t(t[2])];
        const std::array<double, 3> v = {det3(d, b, c), det3(a, d, c), det3(a, b, d)};
        if (v[0] < -kDetEps || v[1] < -kDetEps || v[2] < -kDetEps) continue;
        const double s = std::max(0.0, v[0]) + std::max(0.0, v[1]) + std::max(0.0, v[2]);
        if (!(s > 0)) continue;  // the antipode of the triangle's plane: not in its cone
        w.count = 3;
        w.index = t;
        for (int i = 0; i < 3; ++i) w.weight[size_t(i)] = std::max(0.0, v[size_t(i)]) / s;
        return compact(w);
    }
    // Outside the region: the nearest point of its boundary arcs.
    double best = 4;
    for (const auto& e : m_boundary) {
        const Eigen::Vector3d &a = m_vec[size_t(e[0])], &b = m_vec[size_t(e[1])];
        const Eigen::Vector3d nrm = a.cross(b).normalized();
        Eigen::Vector3d p = d - d.dot(nrm) * nrm;
        const bool on_arc = p.norm() > 1e-15 && a.cross(p).dot(nrm) >= 0 && p.cross(b).dot(nrm) >= 0;
        p = on_arc ? Eigen::Vector3d(p.normalized()) : (d.dot(a) >= d.dot(b) ? a : b);
        const double angle = std::atan2(d.cross(p).norm(), d.dot(p));
        if (angle < best - 1e-15) {
            best = angle;
            const auto ab = arc_weights(a, b, p);
            w.count = 2;
            w.index = {e[0], e[1], 0};
            w.weight = {ab[0], ab[1], 0};
            w.outside_deg = angle * 180.0 / kPi;
        }
    }
    return compact(w);
}

std::vector<ImageTerm> interpolation_terms(const DirectionInterpolator& lights,
                                           const DirectionInterpolator& views,
                                           const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
    const DirectionWeights wl = lights.weights(light), wv = views.weights(view);
    std::vector<ImageTerm> terms;
    for (int u = 0; u < wl.count; ++u)
        for (int v = 0; v < wv.count; ++v) {
            const double w = wl.weight[size_t(u)] * wv.weight[size_t(v)];
            if (w > 0) terms.push_back({wl.index[size_t(u)], wv.index[size_t(v)], Eigen::Vector3d::Constant(w)});
        }
    return terms;
}

NearestInterpolator::NearestInterpolator(const std::vector<Direction>& set) {
    if (set.empty()) throw Error("nearest direction: empty direction set");
    for (const Direction& d : set) m_vec.push_back(d.vector());
}

DirectionWeights NearestInterpolator::weights(const Eigen::Vector3d& d) const {
    check_unit(d);
    DirectionWeights w;
    w.count = 1;
    w.weight[0] = 1;
    for (size_t i = 1; i < m_vec.size(); ++i)
        if (m_vec[i].dot(d) > m_vec[size_t(w.index[0])].dot(d)) w.index[0] = int(i);
    return w;
}

std::unique_ptr<DirectionInterpolator> make_interpolator(InterpScheme scheme,
                                                         const std::vector<Direction>& set) {
    if (scheme == InterpScheme::kThesis) return std::make_unique<ThesisInterpolator>(set);
    if (scheme == InterpScheme::kNearest) return std::make_unique<NearestInterpolator>(set);
    return std::make_unique<DelaunayInterpolator>(set);
}

}  // namespace inlight::btf
