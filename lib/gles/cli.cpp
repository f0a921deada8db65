#include "gles/cli.h"

#include "brdf/bake.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/validators.h"
#include "render/realtime_lights.h"

namespace inlight::gles {

ExportSet ExportArgs::set() const {
    ExportSet s;
    s.versions = glsl_versions_from_string(versions);
    s.modes = shader_modes_from_string(modes);
    s.precisions = precisions_from_string(precisions);
    s.max_sh_bands = max_sh_bands;
    s.max_texture_size = max_texture_size;
    s.texture_filter = texture_filter_from_string(texture_filter);
    for (GlslVersion v : s.versions) {  // below a version's minimum: a usage error
        try {
            export_limits(s, v);
        } catch (const UsageError& e) {
            throw UsageError(str("--gles-max-texture-size: ", e.what()));
        }
    }
    if (!lighting.empty()) s.lights = render::read_lighting_file(lighting).lights;
    return s;
}

ExportSet ExportArgs::prepare(Report& report) const {
    fs::declare_output(dir + "/index.json", dir_option);
    if (!lighting.empty()) report.add_input(lighting);
    return set();
}

void check_before_work(const std::function<void()>& check, const std::string& option) {
    const std::string prefix = option.empty() ? "" : option + ": ";
    try {
        check();
    } catch (const UsageError& e) {
        throw UsageError(prefix + e.what());
    } catch (const Error& e) {
        throw Error(prefix + e.what());
    }
}

void add_export_options(CLI::App& app, ExportArgs& a, bool with_dir) {
    if (with_dir) {
        app.add_option("--export-gles", a.dir,
                       "Also write GLES vertex + fragment shaders, manifests and BRDF data of "
                       "every variant into this folder (docs/gles.md)");
    }
    app.add_option("--gles-versions", a.versions, "GLSL ES versions to export: 100, 300")
        ->check(app::parses_with([](const std::string& s) { glsl_versions_from_string(s); },
                                 "LIST"))
        ->capture_default_str();
    app.add_option("--gles-modes", a.modes, "Shader modes to export: consistent, seed")
        ->check(app::parses_with([](const std::string& s) { shader_modes_from_string(s); },
                                 "LIST"))
        ->capture_default_str();
    app.add_option("--gles-precisions", a.precisions, "Float precisions: highp, mediump (mediump only on request: not validated on a "
                   "half-float driver, docs/gles.md 'Precision')")
        ->check(app::parses_with([](const std::string& s) { precisions_from_string(s); }, "LIST"))
        ->capture_default_str();
    app.add_option("--gles-max-bands", a.max_sh_bands,
                   "Consistent variants for lighting bands 3 .. this (seed: 3 only)")
        ->check(CLI::Range(3, brdf::kMaxBakeBands))
        ->capture_default_str();
    app.add_option("--gles-max-texture-size", a.max_texture_size,
                   "The target device's GL_MAX_TEXTURE_SIZE (texels per side): BRDF tables larger "
                   "than the specification minimum (64 for ES 2.0, 2048 for ES 3.0) are laid out "
                   "within it; 0 = that minimum")
        ->check(CLI::Range(0, 1 << 16))
        ->capture_default_str();
    app.add_option("--gles-texture-filter", a.texture_filter,
                   "How the shaders read a material's albedo and normal textures: bilinear (the "
                   "texture itself) or trilinear (its mip atlas, level of detail from dFdx/dFdy; "
                   "ES 1.00 needs GL_OES_standard_derivatives; docs/gles.md 'Texture filtering')")
        ->check(app::parses_with([](const std::string& s) { texture_filter_from_string(s); }, "NAME"))
        ->capture_default_str();
    app.add_option("--gles-lighting", a.lighting,
                   "Lighting file with dominant lights (envmap-project --max-error JSON, "
                   "docs/formats.md): the consistent variants shade its lights analytically");
}

}  // namespace inlight::gles
