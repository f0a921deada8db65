// render/btf_shade.h: a surface carrying a raw (uncompressed) BTF shaded under a lat-long
// environment, and the same woven geometry path-traced under that environment as the truth,
// both as the rectified image of the sample (render/btf_capture.h), so they compare pixel by
// pixel. The difference is the cost of the BTF's 81-direction sampling itself (before any
// compression, which btf-pca adds).
//
// Shading (btf/lighting.h): L(x, v) = sum_k btf(x, l_k, v) W_k, btf = image / irradiance, W_k the
// environment integrated over light k's cell of the hemisphere. The view direction selects the
// BTF's views: its nearest view, or with `view_neighbours` = 3 the three nearest blended by
// inverse angular distance (exact when the view is one of the BTF's).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <vector>

#include "btf/dataset.h"
#include "btf/interp.h"
#include "btf/lighting.h"
#include "image/image.h"
#include "render/btf_capture.h"
#include "render/environment.h"

namespace inlight::render {

/// The BTF's views that a view direction uses, with weights summing to 1.
struct ViewBlend {
    std::vector<int> views;
    std::vector<double> weights;
};
/// `neighbours` 1..n_views nearest views (by angle) of `view`, weighted by inverse angle
/// (a view within 1e-9 deg of one of them takes it alone). Precondition: views non-empty.
ViewBlend select_views(const std::vector<btf::Direction>& views, const btf::Direction& view,
                       int neighbours);

/// The BTF's views that `view` blends under an angular interpolation scheme (btf/interp.h:
/// thesis or spherical Delaunay over the BTF's view set), as a ViewBlend.
ViewBlend interpolate_views(const btf::DirectionInterpolator& views, const btf::Direction& view);

/// The shaded rectified image (BTF size, linear_srgb radiance). `irradiance_w_m2` is the
/// capture's (capture.json). Images are read through `btf` (each once).
image::Image shade_btf(const btf::BtfSource& btf, const btf::DomeLighting& lighting,
                       const ViewBlend& blend, double irradiance_w_m2);

/// Path-traced truth: the capture scene's rectified view of `view` under `env` (the
/// environment's frame is the sample frame: +z the fabric normal), `spp` paths per pixel with
/// the path tracer's MIS estimator (path_tracer.h trace_path), deterministic for any thread
/// count. Returns the radiance and its relative noise in *rel_error.
image::Image truth_under_environment(const std::shared_ptr<const weave::Weave>& weave,
                                     const CaptureOptions& options,
                                     const EnvironmentSpec& env, const btf::Direction& view,
                                     double* rel_error);

}  // namespace inlight::render
