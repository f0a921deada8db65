// gles/btf_draw.h: the exported BTF shaders (gles/btf_export.h) drawn as the rectified image of
// the sample, the picture render shade-btf compares with the path-traced truth: one fragment
// per texel (pixel (x, y) shows texel (x, y), u_uv_scale 1), nearest texel as the shader reads
// it, into an RGBA32F target (HDR radiance, no 8-bit step).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "btf/dome.h"
#include "gles/btf_export.h"
#include "gles/harness.h"
#include "image/image.h"

namespace inlight::gles {

/// Two triangles filling the viewport, uv (0, 0) at the top-left corner and (1, 1) at the
/// bottom-right: at the export's width x height, pixel (x, y) shows texel (x, y).
Mesh btf_sample_quad();

/// One frame of `variant`: the view `view` (sample frame) under SH lighting `sh` (bands^2 x 3,
/// fabric frame) and dominant `lights`, as btf_frame_weights, with the first `sent` stream
/// entries arrived. Returns the
/// linear_srgb radiance (3 channels, e.width x e.height); `draw_ms` (optional) the draw's wall
/// time. Throws Error as btf_frame_weights and draw do (no RGBA32F target).
image::Image draw_btf(const Context& context, const BtfGlesExport& e, const BtfGlesVariant& variant,
                      const btf::Direction& view, const Eigen::MatrixXd& sh, int64_t sent,
                      double* draw_ms = nullptr, const std::vector<BtfLight>& lights = {});

}  // namespace inlight::gles
