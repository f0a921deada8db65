// render/material.h: surface materials of the renderer: a brdf-sh-bake model (lib/brdf) with
// optional tiled textures, and the shading frame at a hit.
//
// Textures (tiled: uv is multiplied by uv_scale and wraps; bilinear between texel centres):
//   albedo_texture     colour image, sRGB-decoded to linear; multiplies the material's albedo.
//   normal_texture     tangent-space normal map, read as data: n = 2 rgb - 1, x along the
//                      tangent dp/du, y along n x t (screen up for the patch), z along the
//                      normal. This is the report's shader convention (its patch faces +z, so
//                      the map's normal is the device-frame normal).
//   roughness_texture  data, first channel in [0, 1]; multiplies alpha and report_r.
// Surfaces are two-sided: the frame is flipped to the side the ray arrives from.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "brdf/brdf.h"
#include "image/image.h"
#include "render/accel.h"

namespace inlight::render {

/// A material as the scene declares it, with its textures loaded.
struct SurfaceMaterial {
    std::string name;
    brdf::Material brdf;
    std::string albedo_texture_path, normal_texture_path, roughness_texture_path;
    std::shared_ptr<const image::Image> albedo_texture, normal_texture, roughness_texture;
    Eigen::Vector2d uv_scale{1, 1};  ///< texture repeats per unit of the shape's uv
};

/// Loads the textures named by the *_path fields (empty = none). Throws Error naming the file.
void load_textures(SurfaceMaterial& material);

/// Bilinear lookup with wrap-around of the first three channels (a one-channel image is
/// replicated), texel centres at +0.5, uv in texture units (1 = one repeat), v down.
Eigen::Vector3d sample_texture(const image::Image& img, const Eigen::Vector2d& uv);

/// The same lookup inside the rectangle [x0, x0 + width) x [y0, y0 + height) of `img`, which
/// it wraps as a texture of its own (a mip level in an atlas, render/mip.h).
Eigen::Vector3d sample_texture_rect(const image::Image& img, int x0_px, int y0_px, int width,
                                    int height, const Eigen::Vector2d& uv);

/// What the integrator needs at a hit: the BRDF parameters there and the local frame.
struct ShadingPoint {
    brdf::Material brdf;
    Eigen::Matrix3d world_from_local;  ///< columns: tangent, bitangent, shading normal
    Eigen::Vector3d ng;                ///< unit geometric normal on the side of wo
    /// Length of the filtered normal-map vector before normalising, in (0, 1]: below 1 where
    /// the lookup averaged differing normals (render/mip.h); 1 without a normal map.
    double normal_length = 1;
};

struct MipAtlas;

/// Mip-mapped lookups in place of the bilinear ones (render/mip.h): the material's textures
/// as mip atlases (null = that texture keeps the bilinear lookup) and the derivatives of the
/// hit's uv (before uv_scale) per pixel along the image's x and y.
struct FilteredLookup {
    const MipAtlas* albedo = nullptr;
    const MipAtlas* normal = nullptr;
    Eigen::Vector2d duv_dx = Eigen::Vector2d::Zero(), duv_dy = Eigen::Vector2d::Zero();
    bool box_matched_lod = false;  ///< render::box_matched_lod in place of the GL lod
};

/// Applies textures at hit.uv and builds the shading frame on the side of `wo` (unit, world,
/// pointing away from the surface). A normal-mapped normal that faces away from wo falls back
/// to the geometric normal.
/// With `filtered`, the albedo and normal textures are read trilinearly from their mip
/// atlases at the level of detail of the derivatives (what the exported shader does).
ShadingPoint shade(const SurfaceMaterial& material, const SurfaceHit& hit,
                   const Eigen::Vector3d& wo, const FilteredLookup* filtered = nullptr);

}  // namespace inlight::render
