#include "envmap/lights.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/log.h"
#include "envmap/validate.h"

namespace inlight::envmap {

double luminance_flux(const DirectionalLight& light) {
    return luminance(light.flux[0], light.flux[1], light.flux[2]);
}

double cap_cosine_integral(double cos_beta, double alpha) {
    cos_beta = std::clamp(cos_beta, -1.0, 1.0);
    const double sin_a = std::sin(alpha), cos_a = std::cos(alpha);
    const double sin_b = std::sqrt(std::max(0.0, 1.0 - cos_beta * cos_beta));
    // Wholly above the horizon (beta <= pi/2 - alpha): cos(beta) >= sin(alpha).
    if (cos_beta >= sin_a) return kPi * sin_a * sin_a * cos_beta;
    // Wholly below (beta >= pi/2 + alpha).
    if (cos_beta <= -sin_a) return 0.0;
    // Straddling the horizon (Snyder 1996): with x = cot(alpha) and y = -x cot(beta),
    // sin^2(alpha) (cos(beta) acos(y) - x sin(beta) sqrt(1 - y^2)) + atan(sin(beta) sqrt(1 - y^2) /
    // x). Here sin(beta) >= cos(alpha) > 0, so the divisions are safe for alpha < pi/2.
    const double x = cos_a / sin_a;
    const double y = std::clamp(-x * cos_beta / sin_b, -1.0, 1.0);
    const double s = sin_b * std::sqrt(std::max(0.0, 1.0 - y * y));
    const double e = sin_a * sin_a * (cos_beta * std::acos(y) - x * s) + std::atan2(s, x);
    return std::max(0.0, e);
}

namespace {
constexpr EnumName<LightShading> kLightShadingNames[] = {{LightShading::kCap, "cap"},
                                                         {LightShading::kSmoothCap, "smooth-cap"}};
}  // namespace

LightShading light_shading_from_string(const std::string& name) {
    return enum_from_string(kLightShadingNames, name, "light shading");
}

std::string to_string(LightShading shading) { return enum_to_string(kLightShadingNames, shading); }

double smooth_cap_cosine(double cos_beta, double alpha) {
    const double t = std::clamp(cos_beta, -1.0, 1.0), s = std::sin(alpha);
    if (t >= s) return t;
    if (t <= -s) return 0.0;
    return (t + s) * (t + s) / (4 * s);
}

Eigen::Vector3d light_irradiance(const DirectionalLight& light, const Eigen::Vector3d& n) {
    const double c = n.dot(light.direction);
    const double a = light.angular_radius;
    if (light.shading == LightShading::kSmoothCap)
        return light.flux * (0.5 * (1.0 + std::cos(a)) * smooth_cap_cosine(c, a));
    // Below 1e-4 rad the cap's horizon band is narrower than float resolution of c: a point.
    if (a < 1e-4) return light.flux * std::max(0.0, c) * 0.5 * (1.0 + std::cos(a));
    const double cap_sr = 2.0 * kPi * (1.0 - std::cos(a));
    return light.flux * (cap_cosine_integral(c, a) / cap_sr);
}

Eigen::Vector3d light_specular(const DirectionalLight& light, const Eigen::Vector3d& n,
                               const Eigen::Vector3d& view, const brdf::Material& material) {
    if (material.specular == brdf::Model::kLambert) return Eigen::Vector3d::Zero();
    const Eigen::Matrix3d local_from_world = brdf::world_from_local(n).transpose();
    const Eigen::Vector3d wo = local_from_world * view, wi = local_from_world * light.direction;
    if (wo.z() <= 0) return Eigen::Vector3d::Zero();
    return brdf::eval_specular(material, wo, wi).cwiseProduct(light_irradiance(light, n));
}

namespace {

/// The observed samples of an environment, flat.
struct Samples {
    std::vector<int64_t> index;  ///< pixel index in env.radiance
    std::vector<Eigen::Vector3d> dir;
    std::vector<double> omega, y;
    std::vector<Eigen::Vector3d> rgb;
};

Samples gather(const Environment& env) {
    const auto set = make_sample_set(env);
    Samples s;
    Eigen::Vector3d d;
    double w, v[3];
    for (int64_t i = 0; i < set->size(); ++i) {
        if (!set->sample(i, d, w, v) || !(w > 0)) continue;
        s.index.push_back(i);
        s.dir.push_back(d);
        s.omega.push_back(w);
        s.rgb.emplace_back(v[0], v[1], v[2]);
        s.y.push_back(luminance(v[0], v[1], v[2]));
    }
    return s;
}

/// Weighted median of values (weights > 0); 0 for an empty set.
double weighted_median(std::vector<std::pair<double, double>> vw) {
    if (vw.empty()) return 0.0;
    std::sort(vw.begin(), vw.end());
    double total = 0;
    for (const auto& p : vw) total += p.second;
    double acc = 0;
    for (const auto& p : vw) {
        acc += p.second;
        if (acc >= 0.5 * total) return p.first;
    }
    return vw.back().first;
}

/// Directions hashed into cubic cells of side `cell` for neighbour queries.
class DirectionHash {
  public:
    DirectionHash(const std::vector<Eigen::Vector3d>& dirs, const std::vector<int>& members,
                  double cell)
        : m_dirs(dirs), m_cell(cell) {
        for (int k : members) m_cells[key(cell_of(dirs[static_cast<size_t>(k)]))].push_back(k);
    }
    /// Calls fn(k) for every member within chord distance `radius` of `d`.
    template <typename Fn>
    void near(const Eigen::Vector3d& d, double radius, Fn fn) const {
        const Eigen::Vector3i lo = cell_of(d.array() - radius), hi = cell_of(d.array() + radius);
        for (int x = lo.x(); x <= hi.x(); ++x)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int z = lo.z(); z <= hi.z(); ++z) {
                    const auto it = m_cells.find(key(Eigen::Vector3i(x, y, z)));
                    if (it == m_cells.end()) continue;
                    for (int k : it->second)
                        if ((m_dirs[static_cast<size_t>(k)] - d).norm() <= radius) fn(k);
                }
    }

  private:
    Eigen::Vector3i cell_of(const Eigen::Vector3d& d) const {
        return ((d.array() + 1.0) / m_cell).floor().cast<int>();
    }
    static uint64_t key(const Eigen::Vector3i& c) {
        auto u = [](int v) { return static_cast<uint64_t>(static_cast<uint32_t>(v + (1 << 20))); };
        return (u(c.x()) << 42) ^ (u(c.y()) << 21) ^ u(c.z());
    }
    const std::vector<Eigen::Vector3d>& m_dirs;
    double m_cell;
    std::unordered_map<uint64_t, std::vector<int>> m_cells;
};

/// True when pixel `index` of a fisheye frame has a 4-neighbour outside the image or unobserved.
bool touches_unobserved(const Environment& env, int64_t index) {
    const int w = env.radiance.width, h = env.radiance.height;
    const int x = static_cast<int>(index % w), y = static_cast<int>(index / w);
    const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
    for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) return true;
        if (!(env.solid_angle.at(nx[k], ny[k], 0) > 0)) return true;
    }
    return false;
}

// Region growing links samples closer than this many pixel pitches (diagonal neighbours are
// sqrt(2) apart; a one-pixel gap, 2 apart, is not bridged).
constexpr double kLinkPitches = 1.8;
// Seeds tried at most (bright clouds, sky patches) before giving up on more lights.
constexpr int kMaxRegions = 64;
// Region thresholds step down from the seed's luminance by this factor per level.
constexpr double kLevelStep = 1.4142135623730951;
// ... down to this fraction of it at most (23 stops: beyond any camera's range), for maps
// whose background is black.
constexpr double kMinLevel = 1e-7;

/// A region grown from one seed and what surrounds it.
struct Region {
    std::vector<int> members;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double extent = 0;  ///< largest angle of a member from centre
    Eigen::Vector3d background = Eigen::Vector3d::Zero();  ///< weighted median of the ring
};

}  // namespace

Extraction extract_lights(const Environment& env, const ExtractOptions& options,
                          const image::Image* saturated) {
    if (options.max_lights < 0) throw UsageError("max_lights must be >= 0");
    if (!(options.min_peak_contrast > 1) || !(options.grow_contrast > 1) ||
        !(options.grow_contrast <= options.min_peak_contrast) ||
        !(options.max_radius_deg > 0 && options.max_radius_deg <= 90) ||
        !(options.min_flux_fraction >= 0 && options.min_flux_fraction < 1))
        throw UsageError(
            "light extraction: 1 < grow contrast <= peak contrast, radius in (0, 90] "
            "degrees and flux fraction in [0, 1) expected");
    if (saturated &&
        (saturated->width != env.radiance.width || saturated->height != env.radiance.height))
        throw Error(str(env.source, ": saturation mask size differs from the frame"));
    Extraction ex;
    if (options.max_lights == 0) return ex;
    const Samples s = gather(env);
    const int n = static_cast<int>(s.y.size());
    if (n == 0) return ex;
    {
        std::vector<std::pair<double, double>> vw(static_cast<size_t>(n));
        for (int i = 0; i < n; ++i) {
            vw[static_cast<size_t>(i)] = {s.y[static_cast<size_t>(i)],
                                          s.omega[static_cast<size_t>(i)]};
            ex.total_luminance_flux +=
                s.y[static_cast<size_t>(i)] * s.omega[static_cast<size_t>(i)];
        }
        ex.median_luminance = weighted_median(std::move(vw));
    }
    double pitch = 0;
    for (double w : s.omega) pitch = std::max(pitch, std::sqrt(w));
    const double link = kLinkPitches * pitch;
    const double max_radius = options.max_radius_deg * kPi / 180;

    // Only samples brighter than the median can be part of a light (a light is grow_contrast
    // times brighter than its surroundings, and those are rarely all darker than the median).
    std::vector<int> cand, all(static_cast<size_t>(n));
    std::iota(all.begin(), all.end(), 0);
    for (int i = 0; i < n; ++i)
        if (s.y[static_cast<size_t>(i)] > ex.median_luminance) cand.push_back(i);
    std::stable_sort(cand.begin(), cand.end(), [&](int a, int b) {
        return s.y[static_cast<size_t>(a)] > s.y[static_cast<size_t>(b)];
    });
    const DirectionHash bright(s.dir, cand, link);
    const DirectionHash every(s.dir, all, std::max(link, 0.05));
    std::vector<char> taken(static_cast<size_t>(n), 0);  // in a region already examined
    std::vector<int> mark(static_cast<size_t>(n), -1);   // BFS visit stamps

    int stamp = 0;
    // The connected region of untaken samples >= t around seed, its centre, extent and ring.
    auto grow = [&](int seed, double t) {
        Region r;
        ++stamp;
        r.members = {seed};
        mark[static_cast<size_t>(seed)] = stamp;
        for (size_t q = 0; q < r.members.size(); ++q) {
            bright.near(s.dir[static_cast<size_t>(r.members[q])], link, [&](int k) {
                const auto ks = static_cast<size_t>(k);
                if (mark[ks] == stamp || taken[ks] || s.y[ks] < t) return;
                mark[ks] = stamp;
                r.members.push_back(k);
            });
        }
        for (int k : r.members)
            r.centre += s.y[static_cast<size_t>(k)] * s.omega[static_cast<size_t>(k)] *
                        s.dir[static_cast<size_t>(k)];
        if (!(r.centre.norm() > 0)) return r;
        r.centre.normalize();
        for (int k : r.members)
            r.extent = std::max(
                r.extent,
                std::acos(std::clamp(r.centre.dot(s.dir[static_cast<size_t>(k)]), -1.0, 1.0)));
        if (r.extent > 2 * max_radius) return r;  // too wide: no need for its surroundings
        const double ring_in = r.extent + 2 * pitch;
        const double ring_out = ring_in + std::max(3 * pitch, r.extent);
        const double cos_in = std::cos(ring_in), cos_out = std::cos(ring_out);
        std::vector<std::pair<double, double>> ring[3];
        every.near(r.centre, 2 * std::sin(0.5 * std::min(ring_out, kPi)), [&](int k) {
            const auto ks = static_cast<size_t>(k);
            const double c = r.centre.dot(s.dir[ks]);
            if (c > cos_in || c < cos_out) return;
            for (int ch = 0; ch < 3; ++ch) ring[ch].push_back({s.rgb[ks][ch], s.omega[ks]});
        });
        for (int ch = 0; ch < 3; ++ch)
            r.background[ch] = std::max(0.0, weighted_median(std::move(ring[ch])));
        return r;
    };

    struct Found {
        DirectionalLight light;
        std::vector<int64_t> pixels;
    };
    std::vector<Found> found;
    for (int seed : cand) {
        if (taken[static_cast<size_t>(seed)]) continue;
        if (ex.regions_examined >= kMaxRegions) break;
        ++ex.regions_examined;
        // Lower the threshold from the seed's luminance while the region stays compact and the
        // threshold stays grow_contrast times above the background around the region: the last
        // such region is the light (its halo down to grow_contrast x background included).
        const double peak = s.y[static_cast<size_t>(seed)];
        Region best, first;
        bool have = false;
        const double t_min = std::max(ex.median_luminance, kMinLevel * peak);
        for (double t = peak / kLevelStep; t > t_min; t /= kLevelStep) {
            Region r = grow(seed, t);
            if (first.members.empty()) first = r;
            const double b_y = luminance(r.background[0], r.background[1], r.background[2]);
            if (r.extent > max_radius || t < options.grow_contrast * b_y) break;
            best = std::move(r);
            have = true;
        }
        if (!have) {  // not a light: never seed from this neighbourhood again
            for (int k : first.members) taken[static_cast<size_t>(k)] = 1;
            taken[static_cast<size_t>(seed)] = 1;
            continue;
        }
        for (int k : best.members) taken[static_cast<size_t>(k)] = 1;
        const Eigen::Vector3d b = best.background;
        const double b_y = luminance(b[0], b[1], b[2]);
        // Excess over the background: flux, first moment, peak.
        DirectionalLight light;
        Eigen::Vector3d v_y = Eigen::Vector3d::Zero();
        double sat_flux = 0;
        for (int k : best.members) {
            const auto ks = static_cast<size_t>(k);
            const Eigen::Vector3d excess = s.rgb[ks] - b;
            light.flux += excess * s.omega[ks];
            const double ey = luminance(excess[0], excess[1], excess[2]) * s.omega[ks];
            v_y += ey * s.dir[ks];
            light.peak_radiance = std::max(light.peak_radiance, s.y[ks]);
            light.solid_angle_sr += s.omega[ks];
            if (saturated) {
                const int64_t px = s.index[ks];
                if (saturated->pixels[static_cast<size_t>(px) * saturated->channels] > 0) {
                    ++light.saturated_samples;
                    sat_flux += ey;
                }
            }
            if (env.layout == Layout::kFisheye && !light.at_field_edge)
                light.at_field_edge = touches_unobserved(env, s.index[ks]);
        }
        const double phi_y = luminance_flux(light);
        const double contrast = b_y > 0 ? light.peak_radiance / b_y : INFINITY;
        if (!(phi_y > 0) || !(v_y.norm() > 0) || contrast < options.min_peak_contrast) continue;
        if (phi_y < options.min_flux_fraction * ex.total_luminance_flux) continue;
        const double mean_cos = std::min(1.0, v_y.norm() / phi_y);
        light.angular_radius = std::acos(std::clamp(2 * mean_cos - 1, -1.0, 1.0));
        if (light.angular_radius > max_radius) continue;
        light.direction = v_y.normalized();
        light.background = b;
        light.samples = static_cast<int64_t>(best.members.size());
        light.saturated_flux_fraction = sat_flux / phi_y;
        light.flux_is_lower_bound = light.saturated_samples > 0 || light.at_field_edge;
        Found f{light, {}};
        for (int k : best.members) f.pixels.push_back(s.index[static_cast<size_t>(k)]);
        found.push_back(std::move(f));
    }
    std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
        return luminance_flux(a.light) > luminance_flux(b.light);
    });
    for (auto& f : found) {
        if (static_cast<int>(ex.lights.size()) >= options.max_lights) break;
        ex.lights.push_back(f.light);
        ex.region_samples.push_back(std::move(f.pixels));
    }
    return ex;
}

Environment residual_environment(const Environment& env, const Extraction& extraction, int count) {
    if (count < 0 || count > static_cast<int>(extraction.lights.size()))
        throw UsageError(
            str("residual: ", log::count(count, "light"), " asked, ", extraction.lights.size(), " found"));
    Environment out = env;
    const int ch = out.radiance.channels;
    for (int l = 0; l < count; ++l) {
        const Eigen::Vector3d& b = extraction.lights[static_cast<size_t>(l)].background;
        for (int64_t px : extraction.region_samples[static_cast<size_t>(l)])
            for (int c = 0; c < 3; ++c)
                out.radiance.pixels[static_cast<size_t>(px) * ch + c] = static_cast<float>(b[c]);
    }
    return out;
}

nlohmann::json to_json(const DirectionalLight& light) {
    double theta, phi;
    spherical_from_direction(light.direction, theta, phi);
    const double phi_y = luminance_flux(light);
    const Eigen::Vector3d colour =
        phi_y > 0 ? Eigen::Vector3d(light.flux / phi_y) : Eigen::Vector3d::Zero();
    return {{"direction", {light.direction.x(), light.direction.y(), light.direction.z()}},
            {"theta_deg", theta * 180 / kPi},
            {"phi_deg", phi * 180 / kPi},
            {"flux", {light.flux.x(), light.flux.y(), light.flux.z()}},
            {"luminance_flux", phi_y},
            {"colour", {colour.x(), colour.y(), colour.z()}},
            {"angular_radius_deg", light.angular_radius * 180 / kPi},
            {"irradiance", to_string(light.shading)},
            {"background", {light.background.x(), light.background.y(), light.background.z()}},
            {"peak_radiance", light.peak_radiance},
            {"solid_angle_sr", light.solid_angle_sr},
            {"samples", light.samples},
            {"saturated_samples", light.saturated_samples},
            {"saturated_flux_fraction", light.saturated_flux_fraction},
            {"at_field_edge", light.at_field_edge},
            {"flux_is_lower_bound", light.flux_is_lower_bound},
            {"fitted", light.fitted}};
}

DirectionalLight light_from_json(const nlohmann::json& j, const std::string& where) {
    auto vec = [&](const char* key) {
        if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
            throw Error(str(where, ": light needs ", key, " = [x, y, z]"));
        Eigen::Vector3d v;
        for (int k = 0; k < 3; ++k) {
            if (!j[key][static_cast<size_t>(k)].is_number())
                throw Error(str(where, ": light ", key, " must hold numbers"));
            v[k] = j[key][static_cast<size_t>(k)].get<double>();
            if (!std::isfinite(v[k])) throw Error(str(where, ": light ", key, " is not finite"));
        }
        return v;
    };
    DirectionalLight l;
    l.direction = vec("direction");
    if (!(std::abs(l.direction.norm() - 1) < 1e-3))
        throw Error(str(where, ": light direction must be a unit vector"));
    l.direction.normalize();
    l.flux = vec("flux");
    if ((l.flux.array() < 0).any()) throw Error(str(where, ": light flux must be >= 0"));
    if (!j.contains("angular_radius_deg") || !j["angular_radius_deg"].is_number())
        throw Error(str(where, ": light needs angular_radius_deg"));
    const double r = j["angular_radius_deg"].get<double>();
    if (!(r >= 0 && r <= 90))
        throw Error(str(where, ": light angular_radius_deg must be in [0, 90]"));
    l.angular_radius = r * kPi / 180;
    // Optional (files written before it shade the exact cap).
    if (j.contains("irradiance")) {
        if (!j["irradiance"].is_string())
            throw Error(str(where, ": light irradiance must be \"cap\" or \"smooth-cap\""));
        try {
            l.shading = enum_from_string<Error>(kLightShadingNames,
                                                j["irradiance"].get<std::string>(), "light irradiance");
        } catch (const Error& e) {
            throw Error(str(where, ": ", e.what()));
        }
    }
    return l;
}

}  // namespace inlight::envmap
