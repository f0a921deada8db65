// image/normal_map.h: tangent-space normal maps derived from height fields, and the height
// field a woven texture implies, for fabrics that come with an albedo texture only.
//
// Frame (the one render's normal_texture and the exported shaders read, docs/conventions.md):
// tangent x along +u (image right), tangent y = screen up (toward row 0), z out of the surface.
// A height field h(column, row), in texels, is the surface z = h over the texel grid; its normal
// is n = normalize(-dh/dx, -dh/dy_up, 1) = normalize(-dh/dcolumn, +dh/drow, 1).
#pragma once

#include "image/image.h"

namespace inlight::image {

/// How normal_map_from_height treats the borders.
enum class Border {
    kWrap,   ///< the texture tiles: neighbours wrap around (fabrics)
    kClamp,  ///< one-sided differences at the border
};

/// Normals of the height field `height` (first channel, in texels: a value of 1 rises one
/// texel pitch) by central differences, (h[x+1] - h[x-1]) / 2, which are exact for heights
/// linear or quadratic in x and, for a sinusoid of period P texels, underestimate the slope
/// by the factor sinc(2 pi / P) = sin(2 pi / P) / (2 pi / P) (the NormalMap tests hold both).
/// Returns a 3-channel `data` image of unit vectors in the frame above (values in [-1, 1]).
/// Throws Error for an empty image or non-finite heights.
Image normal_map_from_height(const Image& height, Border border = Border::kWrap);

/// A height field from a woven texture's albedo: the threads catch the light and the gaps
/// between them are dark, so height follows Rec.709 luminance of the linear albedo, blurred by
/// a (2 blur_px + 1)^2 box (wrapping) to suppress dye noise, then scaled so its range spans
/// `relief_texels` (0 when the texture is uniform). Returns 1 channel, `data`. Throws Error
/// for an empty image, non-finite values, relief_texels < 0 or not finite, or blur_px < 0.
Image height_from_albedo(const Image& albedo, double relief_texels, int blur_px = 1);

/// Encodes unit normals for an 8-bit linear PNG: rgb = (n + 1) / 2 (the inverse of render's
/// n = 2 rgb - 1). Returns 3 channels, `data`.
Image encode_normal_map(const Image& normals);

/// Box-filters `img` down (or nearest-samples it up) to width x height pixels: each output
/// pixel averages the input pixels whose centres fall inside it (at least the nearest one).
/// Keeps the colour space. Precondition: width, height > 0 (checked).
Image resize_box(const Image& img, int width, int height);

}  // namespace inlight::image
