// gles/scene.h: the GLES exports of a render scene's materials (render --export-gles): one BRDF
// table per material, baked for the view toward the camera (as render --compare's real-time
// model does), and every variant of an ExportSet for it.
#pragma once

#include <string>
#include <vector>

#include "gles/export.h"
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

}  // namespace inlight::gles
