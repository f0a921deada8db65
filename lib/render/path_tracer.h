// render/path_tracer.h: the ground-truth renderer: a unidirectional path tracer lit by the
// environment, with next-event estimation by environment importance sampling, BSDF sampling,
// multiple importance sampling (power heuristic, beta = 2), Russian roulette, and progressive
// passes with a per-pixel running mean and variance.
//
// References: Veach 1997, PhD thesis, ch. 9 (MIS, eq. 9.13 power heuristic); Pharr, Jakob and
// Humphreys, PBR 3rd ed., sec. 14.5 (path tracing with NEE and MIS), 13.7 (Russian roulette);
// Welford 1962 (running variance).
//
// Sampling: render/sampler.h (Owen-scrambled Sobol in Morton order by default, or independent).
// Noise: the standard error of each pixel comes from the spread of its samples (independent) or
// of its scramble groups' means (Sobol), so it predicts the error either way.
//
// Determinism: sample s of pixel p is a pure function of (seed, p, s, dimension), pixels
// are rendered in fixed tiles over core/parallel.h, and each pixel's samples are accumulated in
// sample order, so the output is bit-identical for any thread count and any pass schedule (the
// time budget changes only how many samples are taken).
//
// Unbiasedness of MIS: the power heuristic weights sum to one over the strategies whose pdf is
// non-zero at a direction, so each direction that carries light is counted once as long as one
// strategy can produce it: the environment strategy covers every pixel with non-zero radiance
// (render/environment.h) and BSDF sampling covers the rest of the hemisphere.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/reference.h"
#include "render/sampler.h"
#include "render/sampling.h"
#include "render/scene.h"

namespace inlight::render {

/// Which estimator lights each bounce (kMis is the renderer; the others exist for tests).
enum class Strategy {
    kMis,    ///< environment sample + BSDF sample, power-heuristic weights
    kBsdf,   ///< BSDF sampling only (environment found when the path escapes)
    kLight,  ///< environment sampling only at each bounce (escaping paths add nothing)
};
/// "mis" | "bsdf" | "light"; throws UsageError otherwise.
Strategy strategy_from_string(const std::string& name);

struct RenderOptions {
    /// Samples per pixel (the maximum when a stop rule is given); adaptive: the mean over the
    /// image (the budget is spp x pixels).
    int spp = 64;
    uint64_t seed = 1;
    int max_depth = 32;           ///< surface interactions per path (a cap: RR ends most paths)
    int rr_depth = 3;             ///< Russian roulette after this many interactions
    double time_budget_s = 0;     ///< > 0: stop after the pass that reaches this render time
    double target_rel_error = 0;  ///< > 0: stop when rel_error (RenderResult) <= this
    int tile_px = 16;             ///< square tiles, the unit of parallel work
    bool jitter = true;           ///< box filter over the pixel; false = the pixel centre only
    Strategy strategy = Strategy::kMis;
    SamplerKind sampler = SamplerKind::kSobol;
    /// Sobol only: independently scrambled sample groups per pixel, whose spread is the noise
    /// estimate (render/sampler.h); >= 2. More groups give a steadier per-pixel estimate (G - 1
    /// dof) but each group is a shorter sequence, so the image's error grows with G: 2 (the
    /// default) has 7-24% less error than 4 at equal samples (docs/benchmarks.md),
    /// and its 1-dof map still predicts the image's error (its sum over pixels has many dof).
    int scramble_groups = 2;
    std::vector<int> snapshot_spp;  ///< also keep the image after these sample counts
    /// Adaptive sampling: after adaptive_min_spp uniform samples (at least 2 per scramble
    /// group), each pass goes to the pixels whose neighbourhood variance of the mean per sample
    /// is at or above the image's mean (equalising the marginal gain, which minimises the
    /// image's MSE for the samples spent), each pixel up to adaptive_max_factor x spp.
    bool adaptive = false;
    int adaptive_min_spp = 16;
    int adaptive_max_factor = 16;
};

/// The image after a given number of samples (for convergence studies).
struct Snapshot {
    int spp = 0;          ///< the snapshot asked for
    double mean_spp = 0;  ///< samples per pixel taken (>= spp when adaptive passes overshoot)
    double time_s = 0;  ///< render time until then
    double cpu_time_s = 0;  ///< process CPU time until then (all threads; steadier on a shared machine)
    image::Image radiance;
    image::Image std_error;  ///< as RenderResult::std_error
};

struct RenderResult {
    image::Image radiance;   ///< 3 channels, linear_srgb: mean of the samples
    /// 3 channels, data: standard error of that mean (0 when spp < 2, or below one sample per
    /// scramble group)
    image::Image std_error;
    int spp = 0;             ///< samples per pixel taken (adaptive: the mean, rounded down)
    double mean_spp = 0;     ///< samples / pixels
    int64_t max_pixel_spp = 0;
    int passes = 0;
    int64_t samples = 0;            ///< camera paths
    int64_t rays = 0;               ///< closest-hit plus shadow rays
    int64_t nonfinite_samples = 0;  ///< NaN/Inf path values, counted and replaced by 0
    double render_time_s = 0;
    double cpu_time_s = 0;  ///< process CPU time of the render (all threads)
    /// Relative noise of the image: sqrt(mean over pixels of se_Y^2) / mean over pixels of Y,
    /// Y = Rec.709 luminance, se_Y its standard error. NaN when spp < 2 (Sobol: < scramble_groups) or the image is black.
    double rel_error = 0;
    std::string stop_reason;  ///< "spp" | "time_budget" | "target_rel_error"
    std::vector<Snapshot> snapshots;
};

/// Renders the scene's camera view progressively. `progress`, if given, is called on the
/// calling thread after each pass with the samples per pixel done so far.
RenderResult render(const Scene& scene, const RenderOptions& options,
                    const std::function<void(int)>& progress = {});

/// A ray leaving the surface at `p` in direction `dir`, its origin pushed off the surface along
/// the geometric normal `ng` (to the side of dir) by 1e-5 (scene_scale + |p|_inf), well clear of
/// Embree's float precision and far below a pixel.
Ray spawn_ray(const Eigen::Vector3d& p, const Eigen::Vector3d& ng, const Eigen::Vector3d& dir,
              double scene_scale);

/// Russian roulette (PBR 3rd ed. sec. 13.7): survives with probability q = min(1, max beta)
/// and divides beta by q; returns false when the path ends (also for beta <= 0).
bool russian_roulette(Eigen::Vector3d& beta, Rng& rng);
/// The same with the uniform from dimension `dim` of a sampler stream.
bool russian_roulette(Eigen::Vector3d& beta, Sampler::Stream& u, int dim);

/// One path's radiance estimate along `ray` (exposed for tests). Adds the rays it traces to
/// *rays.
Eigen::Vector3d trace_path(const Scene& scene, const Ray& ray, Sampler::Stream& u,
                           const RenderOptions& options, int64_t* rays);

/// Error of the path tracer against sample count (it must fall as 1/sqrt(N)).
struct ConvergencePoint {
    int spp = 0;
    double mean_spp = 0;  ///< samples per pixel actually taken (adaptive passes overshoot)
    double time_s = 0;
    double cpu_time_s = 0;
    double rel_rmse = 0;  ///< sqrt(mean (x - ref)^2) / mean(ref) over pixels and channels
    /// The same with the reference's own noise subtracted: sqrt(max(0, mse - mean se_ref^2)).
    double rel_rmse_corrected = 0;
    /// The error the noise map predicts: sqrt(mean se^2 + mean se_ref^2) / mean(ref), to set
    /// against rel_rmse (their ratio is 1 for an honest map).
    double predicted_rel_rmse = 0;
    /// Mean over the object pixels (ConvergenceReference::object_mask) of |Y - Y_ref| / Y_ref,
    /// Y = Rec.709 luminance (the metric; with a noisy reference it includes the
    /// reference's noise). NaN when no pixel sees an object.
    double mean_rel_error = 0;
};
struct ConvergenceResult {
    std::string reference_kind;  ///< ConvergenceReference::kind
    int reference_spp = 0;
    double reference_rel_error = 0;
    std::vector<ConvergencePoint> points;
    /// Least-squares slope of log(rel_rmse_corrected) against log(mean_spp): -0.5 for an
    /// unbiased Monte Carlo estimator with independent samples.
    double slope = 0;
};
/// A uniform render with `reference_spp` (seed ^ a constant: independent of the measured run).
ConvergenceReference render_reference(const Scene& scene, const RenderOptions& options,
                                      int reference_spp);
/// Renders the measured run with snapshots at `spp_list`, compares each with `reference` (same
/// size as the camera) and fits the slope.
ConvergenceResult convergence_study(const Scene& scene, const RenderOptions& options,
                                    const ConvergenceReference& reference,
                                    const std::vector<int>& spp_list);
/// The same against render_reference(scene, options, reference_spp).
ConvergenceResult convergence_study(const Scene& scene, const RenderOptions& options,
                                    int reference_spp, const std::vector<int>& spp_list);

/// Report metrics of a render: spp, mean_spp, max_pixel_spp, passes, samples, rays, render_time_s,
/// cpu_time_s, samples_per_s,
/// rays_per_s, rel_error (null when undefined), stop_reason, nonfinite_samples.
nlohmann::json to_json(const RenderResult& result);
/// Report metrics of a convergence study: reference_kind, reference_spp, reference_rel_error,
/// points [{spp, mean_spp, time_s, cpu_time_s, rel_rmse, rel_rmse_corrected,
/// predicted_rel_rmse, mean_rel_error}], slope.
nlohmann::json to_json(const ConvergenceResult& result);

}  // namespace inlight::render
