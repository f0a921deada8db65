#include "render/path_tracer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>

#include "brdf/brdf.h"
#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace inlight::render {
namespace {

constexpr double kLumR = 0.2126, kLumG = 0.7152, kLumB = 0.0722;  // Rec.709 luminance

double luminance(const Eigen::Vector3d& c) { return kLumR * c[0] + kLumG * c[1] + kLumB * c[2]; }

/// Power heuristic (Veach eq. 9.13, beta = 2) for the strategy of pdf a against pdf b.
double power_heuristic(double a, double b) {
    const double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0;
}

struct Welford {
    int64_t n = 0;
    double mean[4] = {0, 0, 0, 0};  // R, G, B, Y
    double m2[4] = {0, 0, 0, 0};
    void add(const Eigen::Vector3d& x) {
        ++n;
        const double v[4] = {x[0], x[1], x[2], luminance(x)};
        for (int c = 0; c < 4; ++c) {
            const double d = v[c] - mean[c];
            mean[c] += d / static_cast<double>(n);
            m2[c] += d * (v[c] - mean[c]);
        }
    }
    /// Standard error of the mean of channel c (0 for n < 2).
    double std_error(int c) const {
        if (n < 2) return 0.0;
        return std::sqrt(m2[c] / static_cast<double>(n - 1) / static_cast<double>(n));
    }
};

/// Per-pixel running statistics: a Welford mean and variance over all samples, and with G >= 2
/// scramble groups the per-group sums whose spread estimates the error of the mean.
class Accumulators {
  public:
    Accumulators(size_t pixels, int groups)
        : m_groups(groups), m_all(pixels), m_group_sum(groups > 1 ? pixels * groups * 4 : 0) {}

    /// Adds sample `s` (of group s % G) of pixel i; samples of a pixel arrive in order.
    void add(size_t i, int64_t s, const Eigen::Vector3d& x) {
        m_all[i].add(x);
        if (m_groups > 1) {
            double* g = &m_group_sum[(i * static_cast<size_t>(m_groups) +
                                      static_cast<size_t>(s % m_groups)) * 4];
            g[0] += x[0];
            g[1] += x[1];
            g[2] += x[2];
            g[3] += luminance(x);
        }
    }
    size_t size() const { return m_all.size(); }
    /// Samples a pixel needs before its standard error is defined.
    int64_t min_count() const { return m_groups > 1 ? m_groups : 2; }
    int64_t count(size_t i) const { return m_all[i].n; }
    double mean(size_t i, int c) const { return m_all[i].mean[c]; }

    /// Squared standard error of pixel i's mean in channel c (R, G, B, Y): the Welford sample
    /// variance / n with one group (independent samples), else the variance of the G group
    /// means / G (independent randomisations). 0 while undefined (n < 2, or n < G).
    double variance_of_mean(size_t i, int c) const {
        const int64_t n = m_all[i].n;
        if (m_groups == 1) {
            const double se = m_all[i].std_error(c);
            return se * se;
        }
        if (n < m_groups) return 0.0;
        const int64_t base = n / m_groups, extra = n % m_groups;
        const double* g = &m_group_sum[i * static_cast<size_t>(m_groups) * 4];
        double means[16], sum = 0;
        for (int k = 0; k < m_groups; ++k) {
            means[k] = g[static_cast<size_t>(k) * 4 + static_cast<size_t>(c)] /
                       static_cast<double>(base + (k < extra ? 1 : 0));
            sum += means[k];
        }
        const double m = sum / m_groups;
        double ss = 0;
        for (int k = 0; k < m_groups; ++k) ss += (means[k] - m) * (means[k] - m);
        return ss / (static_cast<double>(m_groups) * (m_groups - 1));
    }

  private:
    int m_groups;
    std::vector<Welford> m_all;
    std::vector<double> m_group_sum;  ///< pixel-major, then group, then R, G, B, Y
};

double rel_error_of(const Accumulators& acc) {
    if (acc.size() == 0) return std::numeric_limits<double>::quiet_NaN();
    double se2 = 0, y = 0;
    for (size_t i = 0; i < acc.size(); ++i) {
        if (acc.count(i) < acc.min_count()) return std::numeric_limits<double>::quiet_NaN();
        se2 += acc.variance_of_mean(i, 3);
        y += acc.mean(i, 3);
    }
    const double n = static_cast<double>(acc.size());
    if (!(y != 0)) return std::numeric_limits<double>::quiet_NaN();
    return std::sqrt(se2 / n) / std::abs(y / n);
}

image::Image std_error_image(const Accumulators& acc, int w, int h) {
    image::Image img(w, h, 3, image::ColorSpace::kData);
    for (size_t i = 0; i < acc.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            img.pixels[i * 3 + static_cast<size_t>(c)] =
                static_cast<float>(std::sqrt(acc.variance_of_mean(i, c)));
        }
    }
    return img;
}

image::Image mean_image(const Accumulators& acc, int w, int h) {
    image::Image img(w, h, 3, image::ColorSpace::kLinearSrgb);
    for (size_t i = 0; i < acc.size(); ++i) {
        for (int c = 0; c < 3; ++c)
            img.pixels[i * 3 + static_cast<size_t>(c)] = static_cast<float>(acc.mean(i, c));
    }
    return img;
}

}  // namespace

Ray spawn_ray(const Eigen::Vector3d& p, const Eigen::Vector3d& ng, const Eigen::Vector3d& dir,
              double scene_scale) {
    // Relative offset: Embree intersects in float (2^-24 = 6e-8 relative); 1e-5 of the scene
    // size plus the position's magnitude keeps well clear of that and far below a pixel.
    const double eps = 1e-5 * (scene_scale + p.cwiseAbs().maxCoeff());
    Ray r;
    r.origin = p + (ng.dot(dir) >= 0 ? eps : -eps) * ng;
    r.dir = dir;
    return r;
}

namespace {
// Draws its uniform only when q < 1, so an Rng stream is consumed as before.
template <typename Draw>
bool roulette(Eigen::Vector3d& beta, Draw draw) {
    const double q = std::min(1.0, beta.maxCoeff());
    if (!(q > 0)) return false;
    if (q < 1.0) {
        if (draw() >= q) return false;
        beta /= q;
    }
    return true;
}
}  // namespace

bool russian_roulette(Eigen::Vector3d& beta, Rng& rng) {
    return roulette(beta, [&rng] { return rng.uniform(); });
}

bool russian_roulette(Eigen::Vector3d& beta, Sampler::Stream& u, int dim) {
    return roulette(beta, [&u, dim] { return u.get1d(dim); });
}

constexpr EnumName<Strategy> kStrategyNames[] = {
    {Strategy::kMis, "mis"}, {Strategy::kBsdf, "bsdf"}, {Strategy::kLight, "light"}};

Strategy strategy_from_string(const std::string& name) {
    return enum_from_string(kStrategyNames, name, "strategy");
}

Eigen::Vector3d trace_path(const Scene& scene, const Ray& camera_ray, Sampler::Stream& u,
                           const RenderOptions& options, int64_t* rays) {
    const EnvironmentLight& env = scene.environment();
    const Accel& accel = scene.accel();
    const double scale = accel.scene_scale();
    Eigen::Vector3d radiance = Eigen::Vector3d::Zero();
    Eigen::Vector3d beta = Eigen::Vector3d::Ones();
    Ray ray = camera_ray;
    double prev_bsdf_pdf = 0;
    for (int depth = 0;; ++depth) {
        SurfaceHit hit;
        ++*rays;
        if (!accel.intersect(ray, &hit)) {
            const Eigen::Vector3d le = env.eval(ray.dir);
            if (depth == 0 || options.strategy == Strategy::kBsdf) {
                radiance += beta.cwiseProduct(le);
            } else if (options.strategy == Strategy::kMis) {
                radiance +=
                    beta.cwiseProduct(le) * power_heuristic(prev_bsdf_pdf, env.pdf(ray.dir));
            }
            break;
        }
        if (depth >= options.max_depth) break;
        const Eigen::Vector3d wo = -ray.dir;
        const ShadingPoint sp = shade(scene.material(hit.shape), hit, wo);
        const Eigen::Matrix3d local_from_world = sp.world_from_local.transpose();
        const Eigen::Vector3d wo_l = local_from_world * wo;

        // Next-event estimation: one environment sample, weighted against BSDF sampling.
        if (options.strategy != Strategy::kBsdf) {
            const EnvironmentLight::Sample ls =
                env.sample(u.get2d(PathDims::bounce(depth, PathDims::kLightDim)));
            if (ls.pdf > 0 && ls.dir.dot(sp.ng) > 0) {
                const Eigen::Vector3d wi_l = local_from_world * ls.dir;
                const Eigen::Vector3d f = brdf::eval(sp.brdf, wo_l, wi_l);
                if (wi_l.z() > 0 && f.maxCoeff() > 0) {
                    ++*rays;
                    if (!accel.occluded(spawn_ray(hit.p, sp.ng, ls.dir, scale))) {
                        const double w =
                            options.strategy == Strategy::kMis
                                ? power_heuristic(ls.pdf, brdf::pdf(sp.brdf, wo_l, wi_l))
                                : 1.0;
                        radiance += beta.cwiseProduct(f).cwiseProduct(ls.radiance) *
                                    (wi_l.z() * w / ls.pdf);
                    }
                }
            }
        }

        // Continue the path by BSDF sampling.
        const Eigen::Vector2d u_dir = u.get2d(PathDims::bounce(depth, PathDims::kBsdfDim));
        const double u_lobe = u.get1d(PathDims::bounce(depth, PathDims::kLobeDim));
        const brdf::Sample bs = brdf::sample(sp.brdf, wo_l, u_dir, u_lobe);
        if (!bs.valid || !(bs.pdf > 0)) break;
        const Eigen::Vector3d wi = sp.world_from_local * bs.wi;
        if (wi.dot(sp.ng) <= 0) break;  // the shading normal sent it into the surface
        beta = beta.cwiseProduct(bs.value) * (bs.wi.z() / bs.pdf);
        prev_bsdf_pdf = bs.pdf;
        if (depth + 1 >= options.rr_depth &&
            !russian_roulette(beta, u, PathDims::bounce(depth, PathDims::kRouletteDim)))
            break;
        ray = spawn_ray(hit.p, sp.ng, wi, scale);
    }
    return radiance;
}

namespace {

/// Adaptive sampling: which pixels take the next pass. The marginal error reduction of one more
/// sample in pixel i is ~ v_i / n_i (v_i its variance of the mean, n_i its samples; exactly so for
/// independent samples, up to a constant factor for QMC), at a cost of r_i / n_i rays (r_i the
/// rays the pixel has traced: a deterministic proxy for its time), so the MSE of the image falls
/// fastest for the time spent when v_i / r_i is equalised: pixels at or above the image's mean
/// take the pass. v_i is
/// the luminance variance averaged over the 3x3 neighbourhood (a Sobol pixel's own estimate has
/// 3 dof; 27 keep the choice from chasing noise).
std::vector<uint8_t> choose_active(const Accumulators& acc, const std::vector<int64_t>& rays,
                                   int w, int h, int64_t cap) {
    std::vector<double> v(acc.size());
    for (size_t i = 0; i < acc.size(); ++i) v[i] = acc.variance_of_mean(i, 3);
    std::vector<double> ratio(acc.size());
    double mean_ratio = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            double sum = 0;
            int count = 0;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    sum += v[static_cast<size_t>(yy) * w + xx];
                    ++count;
                }
            }
            const size_t i = static_cast<size_t>(y) * w + x;
            ratio[i] = sum / count / static_cast<double>(std::max<int64_t>(1, rays[i]));
            mean_ratio += ratio[i];
        }
    }
    mean_ratio /= static_cast<double>(acc.size());
    std::vector<uint8_t> active(acc.size(), 0);
    for (size_t i = 0; i < acc.size(); ++i)
        active[i] = ratio[i] > 0 && ratio[i] >= mean_ratio && acc.count(i) < cap;
    return active;
}

}  // namespace

RenderResult render(const Scene& scene, const RenderOptions& options,
                    const std::function<void(int)>& progress) {
    INLIGHT_CHECK_GE(options.spp, 1);
    INLIGHT_CHECK_GE(options.tile_px, 1);
    INLIGHT_CHECK_GE(options.adaptive_max_factor, 1);
    const Camera& cam = scene.camera();
    const int w = cam.width_px, h = cam.height_px;
    const int tiles_x = (w + options.tile_px - 1) / options.tile_px;
    const int tiles_y = (h + options.tile_px - 1) / options.tile_px;
    const int64_t tiles = static_cast<int64_t>(tiles_x) * tiles_y;
    const auto pixels = static_cast<int64_t>(w) * h;

    INLIGHT_CHECK(options.sampler == SamplerKind::kIndependent ||
                  (options.scramble_groups >= 2 && options.scramble_groups <= 16));
    {
        // The per-pixel state below, before any of it is allocated: a 16384 x 16384 camera asked
        // ~60 GB, which was zeroed page by page until the kernel killed the process.
        const int groups = options.sampler == SamplerKind::kSobol ? options.scramble_groups : 1;
        const double per_pixel = sizeof(Welford) + (groups > 1 ? groups * 4 * sizeof(double) : 0) +
                                 2 * 3 * sizeof(float) + 1 + (options.adaptive ? 8 : 0);
        const double need = per_pixel * static_cast<double>(pixels);
        const double have = static_cast<double>(physical_memory_bytes());
        if (have > 0 && need > have) {
            throw Error(str("render: a ", w, "x", h, " image needs about ",
                            std::ceil(need / (1 << 30)), " GiB for its per-pixel sums (",
                            per_pixel, " bytes a pixel), more than this machine's ",
                            std::floor(have / (1 << 30)), " GiB: lower the camera's width_px and "
                            "height_px (or --width-px, --height-px)"));
        }
    }
    // Adaptive: spp is the mean budget and one pixel may take up to adaptive_max_factor x spp.
    const int64_t cap =
        options.adaptive ? static_cast<int64_t>(options.spp) * options.adaptive_max_factor
                         : options.spp;
    INLIGHT_CHECK_LE(cap, int64_t{1} << 30);
    const Sampler sampler(options.sampler, options.seed, w, h, static_cast<int>(cap),
                          options.sampler == SamplerKind::kSobol ? options.scramble_groups : 1);
    Accumulators acc(static_cast<size_t>(pixels), sampler.groups());
    // Uniform passes until every pixel has an error estimate worth ranking.
    const int uniform_spp =
        options.adaptive ? std::min<int>(options.spp, std::max<int>(options.adaptive_min_spp,
                                                                     2 * sampler.groups()))
                         : options.spp;
    const int64_t budget = static_cast<int64_t>(options.spp) * pixels;
    std::vector<int64_t> tile_rays(static_cast<size_t>(tiles), 0);
    std::vector<int64_t> tile_bad(static_cast<size_t>(tiles), 0);
    std::vector<int> snapshots = options.snapshot_spp;
    std::sort(snapshots.begin(), snapshots.end());
    size_t next_snapshot = 0;

    RenderResult result;
    Progress bar("render", budget);
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&start] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const std::clock_t cpu_start = std::clock();
    auto cpu_elapsed = [cpu_start] {
        return static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    };
    int done = 0;           // uniform passes: samples every pixel has
    int64_t total = 0;      // samples taken over all pixels
    int pass_spp = 1;
    std::vector<uint8_t> active(static_cast<size_t>(pixels), 1);
    std::vector<int64_t> pixel_rays(options.adaptive ? static_cast<size_t>(pixels) : 0, 0);
    int64_t active_count = pixels;
    result.stop_reason = "spp";
    for (;;) {
        const bool uniform = done < uniform_spp;
        int n = std::min(pass_spp, uniform ? uniform_spp - done : pass_spp);
        if (uniform || !options.adaptive) {
            for (int s : snapshots) {
                if (s > done && s < done + n) n = s - done;  // end the pass at the snapshot
            }
        }
        if (!uniform && options.adaptive) {  // stay within the budget: no pass overshoots it
            n = static_cast<int>(std::min<int64_t>(
                n, std::max<int64_t>(1, (budget - total + active_count - 1) / active_count)));
        }
        if (options.time_budget_s > 0 && total > 0) {
            const double per_sample = elapsed() / static_cast<double>(total);
            const double left = options.time_budget_s - elapsed();
            const double per_pass_spp = per_sample * static_cast<double>(active_count);
            n = std::max(1, std::min(n, static_cast<int>(left / std::max(per_pass_spp, 1e-12))));
        }
        parallel::for_chunks(tiles, 1, [&](int64_t begin, int64_t end) {
            for (int64_t tile = begin; tile < end; ++tile) {
                const int tx = static_cast<int>(tile % tiles_x),
                          ty = static_cast<int>(tile / tiles_x);
                const int x0 = tx * options.tile_px, y0 = ty * options.tile_px;
                const int x1 = std::min(w, x0 + options.tile_px),
                          y1 = std::min(h, y0 + options.tile_px);
                int64_t rays = 0, bad = 0, taken = 0;
                for (int y = y0; y < y1; ++y) {
                    for (int x = x0; x < x1; ++x) {
                        const size_t pixel = static_cast<size_t>(y) * w + x;
                        if (!active[pixel]) continue;
                        const int64_t first = acc.count(pixel);
                        const int64_t last = std::min<int64_t>(first + n, cap);
                        const int64_t rays_before = rays;
                        for (int64_t s = first; s < last; ++s) {
                            Sampler::Stream u = sampler.stream(x, y, s);
                            const Eigen::Vector2d j = options.jitter
                                                          ? u.get2d(PathDims::kPixelDim)
                                                          : Eigen::Vector2d(0.5, 0.5);
                            const Ray ray = cam.generate_ray(x + j[0], y + j[1]);
                            Eigen::Vector3d l = trace_path(scene, ray, u, options, &rays);
                            if (!l.allFinite()) {
                                l.setZero();
                                ++bad;
                            }
                            acc.add(pixel, s, l);
                        }
                        taken += last - first;
                        if (options.adaptive) pixel_rays[pixel] += rays - rays_before;
                    }
                }
                tile_rays[static_cast<size_t>(tile)] += rays;
                tile_bad[static_cast<size_t>(tile)] += bad;
                bar.add(taken);
            }
        });
        total = 0;
        for (size_t i = 0; i < acc.size(); ++i) total += acc.count(i);
        if (uniform || !options.adaptive) done += n;
        ++result.passes;
        pass_spp = std::min(2 * pass_spp, 32);
        const int mean_spp = static_cast<int>(total / pixels);
        if (progress) progress(mean_spp);
        // A snapshot is due when the mean samples per pixel reach it (exactly, for uniform
        // passes, which end at snapshots).
        bool snap = false;
        while (next_snapshot < snapshots.size() &&
               total >= static_cast<int64_t>(snapshots[next_snapshot]) * pixels) {
            ++next_snapshot;
            snap = true;
        }
        if (snap) {
            Snapshot sn;
            sn.spp = snapshots[next_snapshot - 1];
            sn.mean_spp = static_cast<double>(total) / static_cast<double>(pixels);
            sn.time_s = elapsed();
            sn.cpu_time_s = cpu_elapsed();
            sn.radiance = mean_image(acc, w, h);
            sn.std_error = std_error_image(acc, w, h);
            result.snapshots.push_back(std::move(sn));
        }
        if (total >= budget) break;
        if (options.target_rel_error > 0 && done >= acc.min_count() &&
            rel_error_of(acc) <= options.target_rel_error) {
            result.stop_reason = "target_rel_error";
            break;
        }
        if (options.time_budget_s > 0 && elapsed() >= options.time_budget_s) {
            result.stop_reason = "time_budget";
            break;
        }
        if (options.adaptive && done >= uniform_spp) {
            active = choose_active(acc, pixel_rays, w, h, cap);
            active_count = 0;
            for (uint8_t a : active) active_count += a;
            if (active_count == 0) break;  // nothing left to gain (or every pixel at the cap)
        }
    }
    result.render_time_s = elapsed();
    result.cpu_time_s = cpu_elapsed();
    result.samples = total;
    result.spp = static_cast<int>(total / pixels);
    result.mean_spp = static_cast<double>(total) / static_cast<double>(pixels);
    for (size_t i = 0; i < acc.size(); ++i)
        result.max_pixel_spp = std::max<int64_t>(result.max_pixel_spp, acc.count(i));
    for (int64_t r : tile_rays) result.rays += r;
    for (int64_t b : tile_bad) result.nonfinite_samples += b;
    result.radiance = mean_image(acc, w, h);
    result.std_error = std_error_image(acc, w, h);
    result.rel_error = rel_error_of(acc);
    return result;
}

ConvergenceReference render_reference(const Scene& scene, const RenderOptions& options,
                                      int reference_spp) {
    RenderOptions ref_opt = options;
    ref_opt.spp = reference_spp;
    ref_opt.seed = mix64(options.seed ^ 0x7265666572656e63ull);  // "referenc": independent
    ref_opt.time_budget_s = ref_opt.target_rel_error = 0;
    ref_opt.snapshot_spp.clear();
    ref_opt.adaptive = false;  // a uniform reference: its noise is even over the image
    RenderResult r = render(scene, ref_opt);
    ConvergenceReference ref;
    ref.kind = "render";
    ref.spp = reference_spp;
    ref.rel_error = r.rel_error;
    ref.radiance = std::move(r.radiance);
    ref.std_error = std::move(r.std_error);
    ref.object_mask = object_pixels(scene);
    return ref;
}

ConvergenceResult convergence_study(const Scene& scene, const RenderOptions& options,
                                    int reference_spp, const std::vector<int>& spp_list) {
    return convergence_study(scene, options, render_reference(scene, options, reference_spp),
                             spp_list);
}

ConvergenceResult convergence_study(const Scene& scene, const RenderOptions& options,
                                    const ConvergenceReference& ref,
                                    const std::vector<int>& spp_list) {
    INLIGHT_CHECK(!spp_list.empty());
    INLIGHT_CHECK_EQ(ref.radiance.width, scene.camera().width_px);
    INLIGHT_CHECK_EQ(ref.radiance.height, scene.camera().height_px);
    INLIGHT_CHECK_EQ(ref.radiance.channels, 3);
    ConvergenceResult out;
    out.reference_kind = ref.kind;
    out.reference_spp = ref.spp;
    out.reference_rel_error = ref.rel_error;
    double ref_mean = 0, ref_var = 0;
    for (size_t i = 0; i < ref.radiance.pixels.size(); ++i) {
        ref_mean += ref.radiance.pixels[i];
        ref_var += static_cast<double>(ref.std_error.pixels[i]) * ref.std_error.pixels[i];
    }
    const double count = static_cast<double>(ref.radiance.pixels.size());
    ref_mean /= count;
    ref_var /= count;
    auto lum = [](const image::Image& img, size_t i) {
        return luminance(Eigen::Vector3d(img.pixels[i * 3], img.pixels[i * 3 + 1],
                                         img.pixels[i * 3 + 2]));
    };

    RenderOptions run_opt = options;
    run_opt.spp = *std::max_element(spp_list.begin(), spp_list.end());
    run_opt.snapshot_spp = spp_list;
    run_opt.time_budget_s = run_opt.target_rel_error = 0;
    const RenderResult run = render(scene, run_opt);
    std::vector<double> xs, ys;
    for (const Snapshot& s : run.snapshots) {
        double mse = 0, var = 0;
        for (size_t i = 0; i < s.radiance.pixels.size(); ++i) {
            const double d = static_cast<double>(s.radiance.pixels[i]) - ref.radiance.pixels[i];
            mse += d * d;
            var += static_cast<double>(s.std_error.pixels[i]) * s.std_error.pixels[i];
        }
        mse /= count;
        var /= count;
        double rel_sum = 0;
        int64_t objects = 0;
        for (size_t i = 0; i < ref.object_mask.size(); ++i) {
            const double y_ref = lum(ref.radiance, i);
            if (!ref.object_mask[i] || !(y_ref != 0)) continue;
            rel_sum += std::abs(lum(s.radiance, i) - y_ref) / std::abs(y_ref);
            ++objects;
        }
        ConvergencePoint p;
        p.spp = s.spp;
        p.mean_spp = s.mean_spp;
        p.cpu_time_s = s.cpu_time_s;
        p.predicted_rel_rmse = std::sqrt(var + ref_var) / std::abs(ref_mean);
        p.time_s = s.time_s;
        p.rel_rmse = std::sqrt(mse) / std::abs(ref_mean);
        p.rel_rmse_corrected = std::sqrt(std::max(0.0, mse - ref_var)) / std::abs(ref_mean);
        p.mean_rel_error = objects > 0 ? rel_sum / static_cast<double>(objects)
                                       : std::numeric_limits<double>::quiet_NaN();
        out.points.push_back(p);
        if (p.rel_rmse_corrected > 0) {
            xs.push_back(std::log(p.mean_spp));
            ys.push_back(std::log(p.rel_rmse_corrected));
        }
    }
    if (xs.size() >= 2) {
        double mx = 0, my = 0;
        for (size_t i = 0; i < xs.size(); ++i) {
            mx += xs[i];
            my += ys[i];
        }
        mx /= static_cast<double>(xs.size());
        my /= static_cast<double>(xs.size());
        double sxy = 0, sxx = 0;
        for (size_t i = 0; i < xs.size(); ++i) {
            sxy += (xs[i] - mx) * (ys[i] - my);
            sxx += (xs[i] - mx) * (xs[i] - mx);
        }
        out.slope = sxx > 0 ? sxy / sxx : 0;
    } else {
        out.slope = std::numeric_limits<double>::quiet_NaN();
    }
    return out;
}

namespace {
nlohmann::json finite_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}
}  // namespace

nlohmann::json to_json(const RenderResult& r) {
    const double t = std::max(r.render_time_s, 1e-9);
    return {{"spp", r.spp},
            {"mean_spp", r.mean_spp},
            {"max_pixel_spp", r.max_pixel_spp},
            {"passes", r.passes},
            {"samples", r.samples},
            {"rays", r.rays},
            {"render_time_s", r.render_time_s},
            {"cpu_time_s", r.cpu_time_s},
            {"samples_per_s", static_cast<double>(r.samples) / t},
            {"rays_per_s", static_cast<double>(r.rays) / t},
            {"rel_error", finite_or_null(r.rel_error)},
            {"stop_reason", r.stop_reason},
            {"nonfinite_samples", r.nonfinite_samples}};
}

nlohmann::json to_json(const ConvergenceResult& c) {
    nlohmann::json pts = nlohmann::json::array();
    for (const auto& p : c.points) {
        pts.push_back({{"spp", p.spp},
                       {"mean_spp", p.mean_spp},
                       {"time_s", p.time_s},
                       {"cpu_time_s", p.cpu_time_s},
                       {"rel_rmse", p.rel_rmse},
                       {"rel_rmse_corrected", p.rel_rmse_corrected},
                       {"predicted_rel_rmse", p.predicted_rel_rmse},
                       {"mean_rel_error", finite_or_null(p.mean_rel_error)}});
    }
    return {{"reference_kind", c.reference_kind},
            {"reference_spp", c.reference_spp},
            {"reference_rel_error", finite_or_null(c.reference_rel_error)},
            {"points", pts},
            {"slope", finite_or_null(c.slope)}};
}

}  // namespace inlight::render
