// render/render_testing.h: scenes shared by the render tests and render_bench (header-only, not
// part of the library), so a test and the benchmark of the same case build one scene.
#pragma once

#include <string>

#include "brdf/bake.h"
#include "brdf/grid.h"
#include "core/conventions.h"
#include "image/image.h"
#include "render/realtime.h"
#include "render/scene.h"

namespace inlight::render::testscenes {

/// An empty scene seen by an orthographic camera at (0, 0, 2) looking down -z, 1.2 units high,
/// px x px pixels: a unit-diameter sphere at the origin fills its centre.
inline SceneDesc base_scene(int px) {
    SceneDesc d;
    d.camera.projection = Projection::kOrthographic;
    d.camera.position = {0, 0, 2};
    d.camera.look_at = {0, 0, 0};
    d.camera.ortho_height = 1.2;
    d.camera.width_px = d.camera.height_px = px;
    return d;
}

/// Band-limited lighting (l <= 2 only), positive everywhere, as a lat-long map.
inline image::Image band_limited_sky(int w, int h) {
    image::Image img(w, h, 3);
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < w; ++col) {
            const Eigen::Vector3d d = latlong_direction((col + 0.5) / w, (row + 0.5) / h);
            const double base = 1.5 + 0.5 * d.z() + 0.3 * d.x() + 0.2 * (3 * d.z() * d.z() - 1) +
                                0.25 * d.x() * d.y();
            img.at(col, row, 0) = static_cast<float>(base);
            img.at(col, row, 1) = static_cast<float>(0.8 * base + 0.2 * d.y());
            img.at(col, row, 2) = static_cast<float>(0.6 * base - 0.1 * d.z());
        }
    }
    return img;
}

/// `d` with material `m` and one object of `kind` in it, at the shape's defaults: a 1x1 patch at
/// z = 0 facing +z, or a sphere of radius 0.5, centred on the origin.
inline SceneDesc with_object(SceneDesc d, const SurfaceMaterial& m, ShapeKind kind) {
    d.materials.push_back(m);
    ObjectSpec o;
    o.shape.kind = kind;
    o.material = m.name;
    d.objects.push_back(o);
    return d;
}

/// The app's case in miniature: a 1x1 patch at z = 0 facing +z in material m, seen by the
/// default orthographic camera (px x px pixels, 0.8 wide: every pixel on the patch).
inline SceneDesc patch_scene(const SurfaceMaterial& m, int px) {
    SceneDesc d;
    d.camera.width_px = d.camera.height_px = px;
    d.camera.ortho_height = 0.8;  // inside the 1x1 patch
    return with_object(d, m, ShapeKind::kPatch);
}

/// The real-time model's inputs for a one-material scene: the environment's SH at `bands` and
/// the material's table (gauss-legendre, `samples` per normal) on `grid`, default view.
inline RealtimeLighting one_material_lighting(const Scene& scene, int bands,
                                              const std::string& grid, int samples) {
    RealtimeLighting lighting;
    lighting.coeffs = project_environment(scene.environment(), bands);
    brdf::BakeOptions bo;
    bo.sh_bands = bands;
    bo.samples = samples;
    lighting.tables.push_back(
        brdf::bake(scene.desc().materials.at(0).brdf, brdf::parse_grid(grid), bo));
    return lighting;
}

}  // namespace inlight::render::testscenes
