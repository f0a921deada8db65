// render/mip.h: texture filtering as a phone draws it: an offline mip chain of a tiled material
// texture packed into one atlas, sampled trilinearly with the level of detail of the GL
// formula, and the normal map's lost variance turned into SH band attenuation.
//
// Mip chain: level 0 is the texture; level k+1 has max(1, floor(w_k / 2)) x max(1, floor(h_k /
// 2)) texels (non-power-of-two sizes allowed), down to 1 x 1. Each texel of level k is the
// exact average over its footprint (the level-0 rectangle [i w0/wk, (i+1) w0/wk) x [j h0/hk,
// (j+1) h0/hk)) of the texture as drawn, its bilinear reconstruction (MipFilter::kBilinear,
// what the path tracer integrates over a pixel), or of its texels (kBox, partial texels by
// covered area, what GL's generated mipmaps approximate), computed in the values the image
// holds: linear radiance for an albedo texture (decoded from sRGB at load,
// re-encoded only when stored in 8 bits), 2 rgb - 1 vectors for a normal map, averaged WITHOUT
// renormalising so that |m| < 1 carries the spread of the normals under the footprint.
//
// Atlas: level 0 at (0, 0); levels 1.. stacked top to bottom in a column at x = w0. Width w0 +
// w1, height max(h0, h1 + h2 + ...) (= h0 unless the texture is much wider than tall). Each level wraps inside its own rectangle, so one
// NEAREST texture without GL mipmaps serves ES 2.0 (non-power-of-two) and ES 3.0 alike.
//
// Level of detail (OpenGL ES 3.0 spec, 3.8.10, eq. 3.21 without the anisotropic clamp): rho =
// max(|d(uv w0,h0)/dx|, |d(uv w0,h0)/dy|) in level-0 texels per pixel, lod = log2(rho),
// clamped to [0, levels - 1]; trilinear = mix of the bilinear lookups of floor(lod) and
// floor(lod) + 1 by fract(lod).
//
// Derivatives: what the GPU's dFdx / dFdy give, not the analytic derivative. A GPU shades
// fragments in 2 x 2 quads aligned on the window's even columns and rows (GL: rows counted from
// the bottom) and takes a derivative as the difference of the attribute between the two
// fragments of the quad's row (dFdx) or column (dFdy); Mesa's llvmpipe does it per row and
// column ("fine"; a "coarse" GPU uses the quad's first row and column for all four, a second-
// order difference). A fragment of the quad outside the triangle still interpolates the
// attribute: its perspective-correct value on the triangle's plane. So the CPU model
// (render/realtime.h) takes duv/dx = uv(odd column) - uv(even column) at the pixel centres of
// the fragment's quad, the partner's uv where its ray meets the hit primitive's plane: at one
// fragment per pixel, the shader's own numbers for planar geometry. The analytic derivative
// (ray differentials) equals it only where uv is affine in the window (orthographic views);
// in perspective they differ by the uv's second derivative over half a pixel, which moves the
// level by up to a few hundredths at grazing views and so the trilinear mix by far more than
// an 8-bit code on a texture with contrast between its levels.
//
// Normal variance: a filtered normal m of length r in (0, 1] is read as the mean of a von
// Mises-Fisher distribution of normals around n = m / r with concentration kappa (Banerjee et
// al. 2005: kappa = (3 r - r^3) / (1 - r^2)); band l of a function convolved with it scales by
// exp(-l (l + 1) / (2 kappa)) (the large-kappa form of the vMF's zonal coefficients).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "image/image.h"

namespace inlight::render {

/// What a texture holds, which decides the 8-bit storage of its levels.
enum class TextureKind {
    kColor,      ///< linear values, stored sRGB-encoded in 8 bits
    kNormalMap,  ///< 2 rgb - 1 vectors (the image holds rgb in [0, 1]), stored as rgb bytes
};

/// One level's rectangle inside the atlas, in texels.
struct MipRect {
    int x = 0, y = 0, width = 0, height = 0;
};

/// The level rectangles of the atlas of a width x height texture (mip_sizes() placed as above):
/// what build_mip_atlas() fills and an exported shader reads (gles/export.h).
std::vector<MipRect> mip_atlas_levels(int width, int height);
/// The atlas' size (width, height) in texels: the bounding box of `levels`.
Eigen::Vector2i mip_atlas_size(const std::vector<MipRect>& levels);

/// How a textured surface is filtered: bilinear on level 0, or trilinear on the mip atlas.
enum class TextureFilter { kBilinear, kTrilinear };

/// A mip chain packed into one image (3 channels, same meaning as the source's).
struct MipAtlas {
    image::Image atlas;
    std::vector<MipRect> levels;  ///< levels[0] = the source at (0, 0)
};

/// Level sizes of a w x h texture: max(1, floor(n / 2)) per step down to 1 x 1.
std::vector<Eigen::Vector2i> mip_sizes(int width, int height);

/// What a level-k texel averages over its footprint.
enum class MipFilter {
    kBox,       ///< the level-0 texels (partial ones by covered area)
    kBilinear,  ///< the texture as it is drawn: its bilinear reconstruction (wrapping)
};

/// Builds the chain of `source` (channels >= 1; one channel is replicated). `quantize_8bit`:
/// store each level >= 1 as the 8-bit code the shipped texture holds (kind decides sRGB or
/// data), so the CPU model reads what the GPU reads. Throws Error on an empty image.
MipAtlas build_mip_atlas(const image::Image& source, TextureKind kind, bool quantize_8bit,
                         MipFilter filter = MipFilter::kBilinear);

/// Bilinear between texel centres of one level, wrapping inside its rectangle; uv in texture
/// units (1 = one repeat), v down. Level 0 equals render::sample_texture on the source.
Eigen::Vector3d sample_level(const MipAtlas& mip, int level, const Eigen::Vector2d& uv);

/// Level of detail of the GL formula for uv derivatives per pixel (texture units) on a
/// level-0 texture of `size` texels; unclamped (-inf for zero derivatives).
double mip_lod(const Eigen::Vector2d& duv_dx, const Eigen::Vector2d& duv_dy,
               const Eigen::Vector2i& size);

/// The level of detail whose trilinear filter has the variance of the pixel's box over the
/// bilinear reconstruction (what a box-filtered, supersampled image shows): a level-L lookup
/// is a box of 2^L texels then a tent of half-width 2^L, variance 4^L / 4; a box of rho
/// texels over the level-0 tent has rho^2 / 12 + 1 / 6. So L = log2(rho^2 / 3 + 2 / 3) / 2,
/// about the GL lod - 0.79 when minified, 0 at rho = 1. `gl_lod` = mip_lod().
double box_matched_lod(double gl_lod);

/// Trilinear lookup at `lod` (clamped to [0, levels - 1]).
Eigen::Vector3d sample_trilinear(const MipAtlas& mip, const Eigen::Vector2d& uv, double lod);

/// 1 / kappa of the vMF whose mean resultant length is r (r in [0, 1]; r = 1 gives 0, r -> 0
/// gives +inf).
double vmf_inv_kappa(double r);

/// Band-l attenuation exp(-l (l + 1) inv_kappa / 2).
double vmf_band_factor(int l, double inv_kappa);

}  // namespace inlight::render
