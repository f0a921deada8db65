// gles/scene.h: the GLES exports of a render scene's materials (render export-gles): one BRDF
// table per material, baked for the view toward the camera (as render compare's real-time
// model does), and every variant of an ExportSet for it.
#pragma once

#include <string>
#include <vector>

#include "gles/export.h"
#include "gles/harness.h"
#include "render/compare.h"
#include "render/realtime_lights.h"
#include "render/scene.h"

namespace inlight::gles {

struct SceneExportOptions {
    ExportSet set;
    std::string grid = "thetaphi:9x32";  ///< BRDF table grid (brdf-sh-bake --grid)
    int bake_samples = 4096;             ///< BRDF table: integrand evaluations per normal
};

/// Exports every material of `scene` (Lambert materials without a table). Material names that
/// are not file-name safe have their other characters replaced by '_'. Throws as
/// export_material.
std::vector<Export> export_scene(const render::Scene& scene, const SceneExportOptions& options);

/// export_scene() without the bakes (on tables of the baked shape): throws as it would, so that
/// render refuses a variant that does not fit before any rendering or baking.
void check_scene_export(const render::Scene& scene, const SceneExportOptions& options);

/// An image's 8-bit texels as the app binds them (RGBA, alpha 255): each value in [0, 1] as its
/// code, sRGB-encoded first when `srgb` (an albedo the CPU holds decoded). Texel channel c is
/// the image's channel min(c, channels - 1), as the CPU model reads a texture
/// (render/material.cpp).
Texture8 to_texture8(const image::Image& img, bool srgb);

/// clip_from_world of the scene's camera (the rays of render::Camera: image row 0 at clip
/// y = +1), depth mapping [near, far] (world distance along the view) to [-1, 1].
Eigen::Matrix4f clip_from_world(const render::Camera& camera, double near, double far);

/// The triangles of the shapes of one material (index into Scene::materials()), in world
/// coordinates with the uv, normals and tangents the CPU shading uses: patches exact, meshes as
/// loaded (face normals where the file has none), spheres tessellated in latitude-longitude
/// (`sphere_rows` x 2 `sphere_rows` quads; the silhouette and normals then differ from the
/// analytic sphere by O(1/rows^2)).
Mesh scene_mesh(const render::Scene& scene, int material, int sphere_rows = 64);

/// The scene's camera view drawn with one export per material (`per_material[i]` for
/// Scene::materials()[i]), lighting `coeffs` (device = world frame). Pixels no surface covers
/// show the environment along the pixel-centre ray, as render_realtime does.
struct SceneFrame {
    image::Image radiance;  ///< linear_srgb
    double frame_ms = 0;    ///< least of `repeat` draws (glDrawArrays to glFinish)
};
SceneFrame render_scene(const Context& context, const render::Scene& scene,
                        const std::vector<Export>& per_material, const Eigen::MatrixXd& coeffs,
                        int repeat = 1, const std::vector<envmap::DirectionalLight>& lights = {});

/// render compare's GLES column: for ES 1.00 and 3.00 (highp), both modes at 3 bands and the
/// consistent mode at 3 .. options.max_bands, the scene drawn on the driver (frame time: the
/// least of 3 draws, after the first compiles) against the ground
/// truth (the same metrics, heat maps and PNGs as the CPU model: <prefix>_gles_<variant>_*)
/// and against the CPU model with one fragment per pixel (fraction of pixels within 1e-3
/// relative). Writes <prefix>_compare3_<variant>.png: truth | CPU model | GLES | GLES error.
/// Every variant and the CPU model use options.gles_texture_filter (render compare
/// --gles-texture-filter; trilinear variants are named "...-trilinear").
/// With `lighting` (render compare --rt-lighting FILE): also the consistent variants at the
/// file's bands (at least 3) with its lights, lit by its residual SH, beside the CPU model
/// lit the same way (render/realtime_lights.h); a file above the bake's 8 bands is reported
/// as skipped, never truncated.
nlohmann::json compare_scene(const render::Scene& scene, const render::RenderResult& truth,
                             const render::CompareOptions& options, const std::string& prefix,
                             std::vector<render::WrittenFile>& written,
                             const render::LightingFile* lighting = nullptr);

}  // namespace inlight::gles
