#include "render/realtime_lights.h"

#include "core/json_in.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::render {

Eigen::Vector3d shade_lights(const std::vector<envmap::DirectionalLight>& lights,
                             const Eigen::Vector3d& n, const brdf::Material& material,
                             const Eigen::Vector3d* view) {
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (const auto& l : lights) {
        out += material.albedo.cwiseProduct(envmap::light_irradiance(l, n)) * kInvPi;
        if (view) out += envmap::light_specular(l, n, *view, material);
    }
    return out;
}

LightingFile read_lighting_file(const std::string& path) {
    const nlohmann::json doc = json_in::read_file(path);
    LightingFile f;
    f.sh = sh::from_json(doc, path);
    if (f.sh.coeffs.cols() != 3)
        throw Error(str(path, ": lighting needs 3 channels, the file has ", f.sh.coeffs.cols()));
    if (!f.sh.coeffs.allFinite()) throw Error(str(path, ": coefficients are not finite"));
    if (!doc.contains("lights")) return f;
    if (!doc["lights"].is_array()) throw Error(str(path, ": \"lights\" must be an array"));
    for (size_t i = 0; i < doc["lights"].size(); ++i)
        f.lights.push_back(
            envmap::light_from_json(doc["lights"][i], str(path, ": lights[", i, "]")));
    return f;
}

}  // namespace inlight::render
