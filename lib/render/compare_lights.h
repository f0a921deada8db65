// render/compare_lights.h: render compare --rt-lighting: the real-time model lit by what
// envmap-project --max-error chose (SH of the residual map + extracted lights, shaded
// analytically: render/realtime_lights.h) against the ground truth, beside pure SH of the
// scene's environment at the same band count, with the shader cost of each (envmap/budget.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/bake.h"
#include "render/compare.h"
#include "render/realtime_lights.h"

namespace inlight::render {

/// The real-time model's inputs as the compare builds them: the scene environment's SH at
/// `bands` and one table per material (compare_tables).
RealtimeLighting compare_lighting(const Scene& scene, const CompareOptions& options, int bands);

/// Renders the consistent model with `file`'s coefficients and lights (BRDF tables baked at
/// the file's band count for the camera's view, options' grid and samples) and the same model
/// with pure SH of the scene's environment at that band count; compares both with `truth`.
/// Writes <prefix>_rt_lights.exr and <prefix>_compare_lights.png (truth | model with lights |
/// heat map). The file's lighting must be in the scene's world frame: envmap-project's
/// --rotate and --intensity are the scene's [environment] rotation and intensity (a mismatch
/// recorded in the file's metadata is warned about).
nlohmann::json compare_lighting_file(const Scene& scene, const RenderResult& truth,
                                     const CompareOptions& options, const LightingFile& file,
                                     const std::string& prefix, std::vector<WrittenFile>& written);

}  // namespace inlight::render
