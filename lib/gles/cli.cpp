#include "gles/cli.h"

#include "brdf/bake.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/validators.h"
#include "gles/scene.h"
#include "image/image.h"
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

void ExportArgs::add_textures(MaterialInputs& material, Report& report) const {
    const struct {
        const std::string& path;
        const char* option;
        Eigen::Vector2i& px;
        std::vector<uint8_t>& rgba8;
    } textures[] = {{albedo_texture, "--gles-albedo-texture", material.albedo_texture_px, material.albedo_rgba8},
                    {normal_texture, "--gles-normal-texture", material.normal_texture_px, material.normal_rgba8}};
    for (const auto& t : textures) {
        if (t.path.empty()) continue;
        const image::ImageInfo info = image::read_info(t.path);
        if (info.is_float || info.bits_per_channel != 8) {
            throw UsageError(str(t.option, ": ", t.path, " has ", info.bits_per_channel, "-bit ",
                                 info.is_float ? "float" : "integer",
                                 " samples; the shaders bind 8-bit texels: give the 8-bit PNG the "
                                 "bundle ships (bundle fabric-maps writes it)"));
        }
        if (&t.path == &normal_texture && info.channels < 3) {
            throw UsageError(str(t.option, ": ", t.path, " has ", info.channels,
                                 " channel(s); a normal map needs rgb (n = 2 rgb - 1)"));
        }
        report.add_input(t.path);
        image::ReadOptions raw;
        raw.decode_srgb = false;  // the codes as stored: the shader decodes sRGB itself
        const Texture8 texels = to_texture8(image::read_image(t.path, raw), false);
        t.px = {texels.width, texels.height};
        t.rgba8 = texels.rgba;
    }
    // The texture is the albedo, as in the validation scene (pipelines/validate-pair.sh: albedo
    // [1, 1, 1] times the bundle's albedo.png): u_albedo = 1, not the material file's albedo.
    if (!albedo_texture.empty()) material.brdf.albedo = Eigen::Vector3d::Ones();
    if (tile_size_m > 0) {
        material.uv_in_metres = true;
        material.uv_scale = Eigen::Vector2f::Constant(static_cast<float>(1.0 / tile_size_m));
    }
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

void add_texture_options(CLI::App& app, ExportArgs& a) {
    app.add_option("--gles-albedo-texture", a.albedo_texture,
                   "8-bit albedo PNG (sRGB) the shaders bind, e.g. the bundle's albedo.png; it "
                   "multiplies the material's albedo")
        ->check(CLI::ExistingFile);
    app.add_option("--gles-normal-texture", a.normal_texture,
                   "8-bit tangent-space normal map PNG (data, n = 2 rgb - 1) the shaders bind, "
                   "e.g. the bundle's normal.png")
        ->check(CLI::ExistingFile);
    app.add_option("--gles-tile-size-m", a.tile_size_m,
                   "Size of one texture tile on the fabric in metres: a_uv is then in metres "
                   "and u_uv_scale = 1 / this (0: a_uv in tiles)")
        ->check(app::finite_range(0.0, 1e3));
}

}  // namespace inlight::gles
