#include "render/btf_capture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "brdf/brdf.h"
#include "btf/synthetic.h"
#include "core/check.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"
#include "image/image.h"
#include "render/path_tracer.h"
#include "render/sampling.h"
#include "render/weave_geometry.h"

namespace inlight::render {
namespace {

constexpr double kLum[3] = {0.2126, 0.7152, 0.0722};  // Rec.709 luminance
/// The margin serves directions up to this polar angle; beyond it rays that run almost
/// parallel to the fabric may leave the repeated region (tan 85 = 11.4 slab thicknesses).
constexpr double kMaxMarginThetaDeg = 85;

/// A light reaches the sample's plane only from above it; theta = 90 deg (cos = 6e-17 in
/// double) and below count as behind the sample: a black image, not noise.
bool lights_sample(const Eigen::Vector3d& l) { return l.z() > 1e-9; }

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The capture scene's shapes: the yarns, then the backing plate (render/scene.h, weave objects).
constexpr int kBackingShape = 1;

/// One vertex of a camera path: where light can arrive.
struct Vertex {
    Eigen::Vector3d p, ng;
    Eigen::Matrix3d local_from_world;
    Eigen::Vector3d wo_l;
    brdf::Material brdf;
    Eigen::Vector3d beta;  ///< path throughput up to this vertex
};

/// Traces one camera path by BRDF sampling (the light-independent part); fills `path`.
void trace_camera_path(const Scene& scene, const Ray& camera_ray, Rng& rng,
                       const CaptureOptions& opt, std::vector<Vertex>& path, int64_t* rays,
                       int64_t* misses, int64_t* backing) {
    path.clear();
    const Accel& accel = scene.accel();
    Eigen::Vector3d beta = Eigen::Vector3d::Ones();
    Ray ray = camera_ray;
    for (int depth = 0; depth < opt.max_depth; ++depth) {
        SurfaceHit hit;
        ++*rays;
        if (!accel.intersect(ray, &hit)) {
            if (depth == 0) ++*misses;
            break;
        }
        if (depth == 0 && hit.shape == kBackingShape) ++*backing;
        const Eigen::Vector3d wo = -ray.dir;
        const ShadingPoint sp = shade(scene.material(hit.shape), hit, wo);
        Vertex v;
        v.p = hit.p;
        v.ng = sp.ng;
        v.local_from_world = sp.world_from_local.transpose();
        v.wo_l = v.local_from_world * wo;
        v.brdf = sp.brdf;
        v.beta = beta;
        path.push_back(v);
        if (depth + 1 >= opt.max_depth) break;
        const Eigen::Vector2d u = rng.uniform2();
        const double u_lobe = rng.uniform();
        const brdf::Sample bs = brdf::sample(sp.brdf, v.wo_l, u, u_lobe);
        if (!bs.valid || !(bs.pdf > 0)) break;
        const Eigen::Vector3d wi = sp.world_from_local * bs.wi;
        if (wi.dot(sp.ng) <= 0) break;
        beta = beta.cwiseProduct(bs.value) * (bs.wi.z() / bs.pdf);
        if (depth + 1 >= opt.rr_depth && !russian_roulette(beta, rng)) break;
        ray = spawn_ray(hit.p, sp.ng, wi, accel.scene_scale());
    }
}

/// Per light, per pixel sums of one tile.
struct PixelSums {
    double rgb[3] = {0, 0, 0};
    double y = 0, y2 = 0;
};

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const auto i = static_cast<size_t>(std::min<double>(v.size() - 1, std::floor(q * v.size())));
    return v[i];
}

}  // namespace

CaptureScene::CaptureScene(std::shared_ptr<const weave::Weave> weave, const CaptureOptions& opt,
                           double max_theta_deg, const EnvironmentSpec* environment)
    : m_weave(std::move(weave)), m_options(opt) {
    INLIGHT_CHECK(m_weave != nullptr);
    INLIGHT_CHECK(opt.width_px >= 1 && opt.width_px <= 4096 && opt.height_px >= 1 &&
                  opt.height_px <= 4096)
        << opt.width_px << "x" << opt.height_px;
    INLIGHT_CHECK(opt.spp >= 1 && opt.max_depth >= 1 && opt.rr_depth >= 1 && opt.tile_px >= 1);
    INLIGHT_CHECK(std::isfinite(opt.irradiance_w_m2) && opt.irradiance_w_m2 > 0);
    INLIGHT_CHECK(opt.origin_mm.allFinite());
    const weave::Weave& w = *m_weave;
    // The slab's horizontal reach at the largest angle, plus one period each way so that a
    // window edge always has whole neighbouring threads.
    m_margin_mm = slab_margin_mm(w, std::clamp(max_theta_deg, 0.0, kMaxMarginThetaDeg)) +
                  std::max(w.period_x_mm, w.period_y_mm);
    SceneDesc desc;
    desc.source = w.spec.name.empty() ? "capture" : w.spec.name;
    desc.environment.radiance = Eigen::Vector3d::Zero();
    if (environment) desc.environment = *environment;
    ObjectSpec o;
    o.name = "fabric";
    o.shape.kind = ShapeKind::kWeave;
    o.weave = m_weave;
    const Eigen::Vector2d period(w.period_x_mm, w.period_y_mm);
    o.shape.size = period + Eigen::Vector2d::Constant(2 * m_margin_mm);
    o.shape.center = Eigen::Vector3d(opt.origin_mm.x() + 0.5 * period.x(),
                                     opt.origin_mm.y() + 0.5 * period.y(), 0.0);
    desc.objects.push_back(o);
    m_scene = std::make_unique<Scene>(std::move(desc));
    const Shape& yarns = m_scene->accel().shapes()[0];
    m_segments = static_cast<int>(yarns.curves->first.size());
}

Ray CaptureScene::view_ray(const Eigen::Vector3d& v, double x, double y) const {
    const weave::Weave& w = *m_weave;
    const Eigen::Vector3d p(m_options.origin_mm.x() + x / m_options.width_px * w.period_x_mm,
                            m_options.origin_mm.y() + w.period_y_mm -
                                y / m_options.height_px * w.period_y_mm,
                            0.0);
    // Start above the highest yarn (1 mm of clearance) on the line through p along v.
    const double lift = (std::max(w.z_max_mm, 0.0) + 1.0) / v.z();
    Ray r;
    r.origin = p + lift * v;
    r.dir = -v;
    return r;
}

ViewCapture capture_view(const CaptureScene& cs, const btf::Direction& view, int view_index,
                         const std::vector<btf::Direction>& lights) {
    const Eigen::Vector3d v = view.vector();
    if (!(v.z() > 1e-9)) {
        throw Error(str("view (", view.theta_deg, ", ", view.phi_deg,
                        ") deg is at or below the horizon: it cannot see the sample"));
    }
    const CaptureOptions& opt = cs.options();
    const Scene& scene = cs.scene();
    const double scale = scene.accel().scene_scale();
    const int w = opt.width_px, h = opt.height_px, t = opt.tile_px;
    const int nl = static_cast<int>(lights.size());
    std::vector<Eigen::Vector3d> lv;
    for (const auto& l : lights) lv.push_back(l.vector());

    ViewCapture out;
    for (int k = 0; k < nl; ++k) out.radiance.emplace_back(w, h, 3, image::ColorSpace::kLinearSrgb);
    const int tiles_x = (w + t - 1) / t, tiles_y = (h + t - 1) / t;
    const int64_t tiles = int64_t(tiles_x) * tiles_y;
    // Per tile: rays and times; per tile and light: sum of se_Y^2 and of Y over its pixels.
    std::vector<int64_t> cam_rays(tiles, 0), shadow_rays(tiles, 0), miss(tiles, 0), back(tiles, 0);
    std::vector<double> path_s(tiles, 0), light_s(tiles, 0);
    std::vector<double> se2(tiles * nl, 0), ysum(tiles * nl, 0);
    const double e = opt.irradiance_w_m2;

    parallel::for_chunks(tiles, 1, [&](int64_t b, int64_t end) {
        std::vector<Vertex> path;
        std::vector<PixelSums> sums(static_cast<size_t>(nl));
        for (int64_t tile = b; tile < end; ++tile) {
            const int x0 = static_cast<int>(tile % tiles_x) * t;
            const int y0 = static_cast<int>(tile / tiles_x) * t;
            const int x1 = std::min(w, x0 + t), y1 = std::min(h, y0 + t);
            double tp = 0, tl = 0;
            int64_t rays = 0, shadows = 0, misses = 0, backing = 0;
            for (int y = y0; y < y1; ++y) {
                for (int x = x0; x < x1; ++x) {
                    std::fill(sums.begin(), sums.end(), PixelSums{});
                    const uint64_t key = uint64_t(view_index) * uint64_t(w) * uint64_t(h) +
                                         uint64_t(y) * uint64_t(w) + uint64_t(x);
                    for (int s = 0; s < opt.spp; ++s) {
                        auto c0 = Clock::now();
                        Rng rng(opt.seed, key, static_cast<uint64_t>(s));
                        const Eigen::Vector2d j =
                            opt.jitter ? rng.uniform2() : Eigen::Vector2d(0.5, 0.5);
                        trace_camera_path(scene, cs.view_ray(v, x + j[0], y + j[1]), rng, opt,
                                          path, &rays, &misses, &backing);
                        auto c1 = Clock::now();
                        tp += std::chrono::duration<double>(c1 - c0).count();
                        for (int k = 0; k < nl; ++k) {
                            const Eigen::Vector3d& l = lv[static_cast<size_t>(k)];
                            Eigen::Vector3d c = Eigen::Vector3d::Zero();
                            if (lights_sample(l)) {
                                for (const Vertex& vx : path) {
                                    if (l.dot(vx.ng) <= 0) continue;
                                    const Eigen::Vector3d wi_l = vx.local_from_world * l;
                                    if (wi_l.z() <= 0) continue;
                                    const Eigen::Vector3d f = brdf::eval(vx.brdf, vx.wo_l, wi_l);
                                    if (!(f.maxCoeff() > 0)) continue;
                                    ++shadows;
                                    if (scene.accel().occluded(spawn_ray(vx.p, vx.ng, l, scale)))
                                        continue;
                                    c += vx.beta.cwiseProduct(f) * (wi_l.z() * e);
                                }
                            }
                            if (!c.allFinite()) c.setZero();
                            PixelSums& ps = sums[static_cast<size_t>(k)];
                            for (int ch = 0; ch < 3; ++ch) ps.rgb[ch] += c[ch];
                            const double yv = kLum[0] * c[0] + kLum[1] * c[1] + kLum[2] * c[2];
                            ps.y += yv;
                            ps.y2 += yv * yv;
                        }
                        tl += seconds_since(c1);
                    }
                    const double n = opt.spp;
                    for (int k = 0; k < nl; ++k) {
                        const PixelSums& ps = sums[static_cast<size_t>(k)];
                        image::Image& img = out.radiance[static_cast<size_t>(k)];
                        for (int ch = 0; ch < 3; ++ch)
                            img.at(x, y, ch) = static_cast<float>(ps.rgb[ch] / n);
                        const double mean = ps.y / n;
                        const double var =
                            n > 1 ? std::max(0.0, (ps.y2 - n * mean * mean) / (n - 1)) : 0.0;
                        se2[static_cast<size_t>(tile * nl + k)] += var / n;
                        ysum[static_cast<size_t>(tile * nl + k)] += mean;
                    }
                }
            }
            cam_rays[static_cast<size_t>(tile)] = rays;
            shadow_rays[static_cast<size_t>(tile)] = shadows;
            miss[static_cast<size_t>(tile)] = misses;
            back[static_cast<size_t>(tile)] = backing;
            path_s[static_cast<size_t>(tile)] = tp;
            light_s[static_cast<size_t>(tile)] = tl;
        }
    });
    const double npix = double(w) * h;
    for (int k = 0; k < nl; ++k) {
        double s2 = 0, ys = 0;
        for (int64_t tile = 0; tile < tiles; ++tile) {
            s2 += se2[static_cast<size_t>(tile * nl + k)];
            ys += ysum[static_cast<size_t>(tile * nl + k)];
        }
        out.rel_error.push_back(opt.spp > 1 && ys > 0
                                    ? std::sqrt(s2 / npix) / (ys / npix)
                                    : std::numeric_limits<double>::quiet_NaN());
    }
    for (int64_t tile = 0; tile < tiles; ++tile) {
        out.camera_rays += cam_rays[static_cast<size_t>(tile)];
        out.shadow_rays += shadow_rays[static_cast<size_t>(tile)];
        out.primary_misses += miss[static_cast<size_t>(tile)];
        out.primary_backing += back[static_cast<size_t>(tile)];
        out.path_time_s += path_s[static_cast<size_t>(tile)];
        out.light_time_s += light_s[static_cast<size_t>(tile)];
    }
    return out;
}

std::vector<CaptureJob> full_jobs(const std::vector<btf::Direction>& views,
                                  const std::vector<btf::Direction>& lights) {
    std::vector<CaptureJob> jobs;
    for (const auto& v : views) jobs.push_back({v, lights});
    return jobs;
}

std::vector<CaptureJob> pair_jobs(const std::vector<btf::DirectionPair>& pairs) {
    std::vector<CaptureJob> jobs;
    std::vector<btf::Direction> views;
    for (const auto& p : pairs) {
        const auto k = btf::find_direction(views, p.view);
        if (k) {
            jobs[static_cast<size_t>(*k)].lights.push_back(p.light);
        } else {
            views.push_back(p.view);
            jobs.push_back({p.view, {p.light}});
        }
    }
    return jobs;
}

CaptureResult capture_btf(const CaptureScene& scene, const std::vector<CaptureJob>& jobs,
                          const std::string& dir, const CaptureWriteOptions& write,
                          const std::function<void(int, int)>& progress) {
    INLIGHT_CHECK(write.extension == "png" || write.extension == "exr") << write.extension;
    CaptureResult r;
    const auto t0 = Clock::now();
    std::vector<double> errors;
    btf::UboWriteOptions names;
    names.extension = write.extension;
    names.per_view_folders = write.per_view_folders;
    image::WriteOptions wo;
    wo.bits = write.extension == "exr" ? 32 : 8;
    for (size_t iv = 0; iv < jobs.size(); ++iv) {
        const CaptureJob& job = jobs[iv];
        const auto tr = Clock::now();
        const ViewCapture vc = capture_view(scene, job.view, static_cast<int>(iv), job.lights);
        r.render_time_s += seconds_since(tr);
        const auto tw = Clock::now();
        const auto nl = static_cast<int64_t>(job.lights.size());
        parallel::for_chunks(nl, 1, [&](int64_t b, int64_t e) {
            for (int64_t k = b; k < e; ++k) {
                image::write_image(
                    btf::ubo2003_path(dir, job.lights[static_cast<size_t>(k)], job.view, names),
                    vc.radiance[static_cast<size_t>(k)], wo);
            }
        });
        r.write_time_s += seconds_since(tw);
        for (int64_t k = 0; k < nl; ++k) {
            const double e = vc.rel_error[static_cast<size_t>(k)];
            if (std::isfinite(e)) errors.push_back(e);
            if (!lights_sample(job.lights[static_cast<size_t>(k)].vector())) ++r.black_images;
        }
        r.images += nl;
        r.camera_rays += vc.camera_rays;
        r.shadow_rays += vc.shadow_rays;
        r.path_time_s += vc.path_time_s;
        r.light_time_s += vc.light_time_s;
        if (progress) progress(static_cast<int>(iv + 1), static_cast<int>(jobs.size()));
    }
    r.wall_time_s = seconds_since(t0);
    r.images_per_s = r.images / std::max(r.wall_time_s, 1e-9);
    r.rel_error_median = percentile(errors, 0.5);
    r.rel_error_p90 = percentile(errors, 0.9);
    r.rel_error_max = errors.empty() ? std::numeric_limits<double>::quiet_NaN()
                                     : *std::max_element(errors.begin(), errors.end());
    return r;
}

nlohmann::json to_json(const CaptureResult& r) {
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    return {{"images", r.images},
            {"black_images", r.black_images},
            {"wall_time_s", r.wall_time_s},
            {"render_time_s", r.render_time_s},
            {"write_time_s", r.write_time_s},
            {"images_per_s", r.images_per_s},
            {"camera_rays", r.camera_rays},
            {"shadow_rays", r.shadow_rays},
            {"path_thread_time_s", r.path_time_s},
            {"light_thread_time_s", r.light_time_s},
            {"rel_error_median", num(r.rel_error_median)},
            {"rel_error_p90", num(r.rel_error_p90)},
            {"rel_error_max", num(r.rel_error_max)}};
}

}  // namespace inlight::render
