// render/btf_capture.h: a synthetic BTF measurement: a woven fabric (lib/weave) path-traced as
// the Bonn gonioreflectometer sees a sample (the BTF thesis, section 2): for each view
// direction, an image rectified to the sample's texture space per light direction, lit by a
// distant point light of known irradiance.
//
// Geometry (docs/conventions.md, "BTF sample frame"; lengths in mm): the image covers the
// window [origin, origin + period) of the weave's mid-plane z = 0, one repeat of the tile by
// default, +x to the right and +y up. Pixel (col, row) at image position (x, y) (pixel centres at
// +0.5, y down) looks at the mid-plane point P = origin + (x / W period_x, period_y - y / H
// period_y) along -v: the ray through P parallel to the view direction v, first hit wherever it
// is (rectification by projection onto the mid-plane, as the Bonn images are rectified onto the
// sample plane). Because the geometry and the ray family are both periodic, the images tile.
// The yarns are repeated around the window far enough (render/weave_geometry.h,
// slab_margin_mm at the largest theta, capped at 85 degrees) that shadows, masking and
// inter-reflection at the window's edges find their neighbours.
//
// Light: a distant point light from direction l delivering `irradiance_w_m2` on a plane
// perpendicular to l. A light with l.z <= 0 is behind the sample: its image is black (no
// sampling). Images hold reflected radiance (W sr^-1 m^-2, linear_srgb), so btf = image /
// irradiance (1/sr); the default irradiance pi makes a white Lambertian plate lit from the
// normal read 1.0.
//
// Transport (full path tracing, per pixel sample): one path from the camera ray, continued by
// BRDF sampling with Russian roulette (path_tracer.h), is shared by every light of the view:
// each light adds, at each vertex, beta f(wo, l) cos(theta_l) E times a shadow ray's visibility
// (next-event estimation; a point light can only be reached that way). The camera ray, its
// first hit and the whole path are therefore traced once per view and sample, and each light
// costs one shadow ray and one BRDF evaluation per vertex: self-shadowing (shadow rays),
// masking (first hits) and inter-reflection (vertices past the first) all show. Each light's
// estimate is unbiased; lights share paths, so their noise is correlated (smooth across lights).
//
// Determinism: pixel p of view index iv, sample s draws from the PCG stream (seed, iv * W * H
// + p, s); tiles of pixels run in parallel, each pixel's samples in order: the images are
// bit-identical for any thread count.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "btf/dome.h"
#include "image/image.h"
#include "render/scene.h"
#include "weave/weave.h"

namespace inlight::render {

struct CaptureOptions {
    int width_px = 128, height_px = 128;  ///< image size, 1..4096
    int spp = 16;                         ///< paths per pixel (shared by all lights of a view)
    uint64_t seed = 1;
    int max_depth = 8;  ///< path vertices that receive light (1 = direct light only)
    int rr_depth = 3;   ///< Russian roulette from this vertex on
    double irradiance_w_m2 = 3.14159265358979323846;  ///< perpendicular to the light, > 0
    bool jitter = true;       ///< box filter over the pixel; false = pixel centres only
    int tile_px = 16;         ///< square tiles, the unit of parallel work
    Eigen::Vector2d origin_mm{0, 0};  ///< the window's lower-left corner on the mid-plane
};

/// The capture's scene: the weave repeated over the window plus its margin, and a black
/// environment. Immutable; safe to share between threads.
class CaptureScene {
  public:
    /// `max_theta_deg`: the largest light or view polar angle the scene must serve (sets the
    /// margin). Throws Error on a bad weave.
    /// `environment`: what escaping paths see (default black: the capture's only light is the
    /// point light; the truth of btf_shade.h sets a map).
    CaptureScene(std::shared_ptr<const weave::Weave> weave, const CaptureOptions& options,
                 double max_theta_deg, const EnvironmentSpec* environment = nullptr);
    const Scene& scene() const { return *m_scene; }
    const weave::Weave& weave() const { return *m_weave; }
    const CaptureOptions& options() const { return m_options; }
    double margin_mm() const { return m_margin_mm; }
    int segments() const { return m_segments; }
    /// The rectified ray of image position (x, y) for view direction v (unit, v.z > 0).
    Ray view_ray(const Eigen::Vector3d& v, double x, double y) const;

  private:
    std::shared_ptr<const weave::Weave> m_weave;
    CaptureOptions m_options;
    double m_margin_mm = 0;
    int m_segments = 0;
    std::unique_ptr<Scene> m_scene;
};

/// One view's images, one per light (same order as the lights given).
struct ViewCapture {
    std::vector<image::Image> radiance;  ///< W x H x 3, linear_srgb, W sr^-1 m^-2
    /// Per light: relative noise, sqrt(mean over pixels of se_Y^2) / mean Y (Y luminance, se
    /// its standard error over the samples); NaN when the image is black or spp < 2.
    std::vector<double> rel_error;
    int64_t camera_rays = 0;  ///< closest-hit rays of the paths (shared by the lights)
    int64_t primary_misses = 0;   ///< camera rays that found no fabric (0 with enough margin)
    int64_t primary_backing = 0;  ///< camera rays whose first hit is the backing plate
    int64_t shadow_rays = 0;
    double path_time_s = 0;   ///< thread time building paths (camera rays, hits, bounces)
    double light_time_s = 0;  ///< thread time in the per-light loop (shadow rays, BRDFs)
};

/// Renders every light of one view. `view_index` keys the random streams (use the view's
/// index in the capture). Precondition: view.z > 0 (checked, Error "view ... at or below the
/// horizon").
ViewCapture capture_view(const CaptureScene& scene, const btf::Direction& view, int view_index,
                         const std::vector<btf::Direction>& lights);

/// What to capture: views, each with its own lights.
struct CaptureJob {
    btf::Direction view;
    std::vector<btf::Direction> lights;
};
/// The dome (views x lights) as jobs.
std::vector<CaptureJob> full_jobs(const std::vector<btf::Direction>& views,
                                  const std::vector<btf::Direction>& lights);
/// (light, view) pairs grouped by view, views in order of first appearance.
std::vector<CaptureJob> pair_jobs(const std::vector<btf::DirectionPair>& pairs);

/// How capture_btf stores images.
struct CaptureWriteOptions {
    std::string extension = "png";  ///< "png" (8-bit sRGB, as Bonn ships) or "exr" (float)
    bool per_view_folders = true;
};

struct CaptureResult {
    int64_t images = 0;
    double wall_time_s = 0, render_time_s = 0, write_time_s = 0;
    double images_per_s = 0;  ///< images / wall_time_s
    int64_t camera_rays = 0, shadow_rays = 0;
    double path_time_s = 0, light_time_s = 0;  ///< thread time, summed over views
    /// rel_error over the non-black images: median, 90th percentile, largest.
    double rel_error_median = 0, rel_error_p90 = 0, rel_error_max = 0;
    int64_t black_images = 0;  ///< lights behind the sample
};

/// Renders every job and writes each view's images under `dir` in UBO2003 naming (btf/dome.h)
/// as soon as the view is done, through image::write_image (staged in the run's
/// fs::OutputTransaction). `progress(done_views, total_views)` is called after each view.
CaptureResult capture_btf(const CaptureScene& scene, const std::vector<CaptureJob>& jobs,
                          const std::string& dir, const CaptureWriteOptions& write,
                          const std::function<void(int, int)>& progress = {});

/// Report metrics of a capture.
nlohmann::json to_json(const CaptureResult& result);

}  // namespace inlight::render
