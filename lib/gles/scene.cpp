#include "gles/scene.h"

#include <algorithm>
#include <cctype>

#include "brdf/bake.h"
#include "core/error.h"

namespace inlight::gles {

std::vector<Export> export_scene(const render::Scene& scene, const SceneExportOptions& options) {
    brdf::BakeOptions bo;
    bo.sh_bands = std::max(3, options.set.max_sh_bands);
    bo.samples = options.bake_samples;
    const render::Camera& cam = scene.camera();
    bo.view = (cam.position - cam.look_at).normalized();
    const brdf::Grid grid = brdf::parse_grid(options.grid);
    std::vector<Export> out;
    const auto& materials = scene.materials();  // textures loaded: their sizes are known
    for (size_t i = 0; i < materials.size(); ++i) {
        const render::SurfaceMaterial& m = materials[i];
        MaterialInputs in;
        in.name = m.name.empty() ? str("material", i) : m.name;
        std::replace_if(
            in.name.begin(), in.name.end(),
            [](char c) { return !(std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
                                  c == '.' || c == '-'); },
            '_');
        if (m.albedo_texture) in.albedo_texture_px = {m.albedo_texture->width, m.albedo_texture->height};
        if (m.normal_texture) in.normal_texture_px = {m.normal_texture->width, m.normal_texture->height};
        if (m.brdf.specular == brdf::Model::kLambert) {
            for (Export& e : export_material(nullptr, in, options.set)) out.push_back(std::move(e));
        } else {
            const brdf::Table table = brdf::bake(m.brdf, grid, bo);
            for (Export& e : export_material(&table, in, options.set)) out.push_back(std::move(e));
        }
    }
    return out;
}

}  // namespace inlight::gles
