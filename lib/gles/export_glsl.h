// gles/export_glsl.h: inside the exporter, not part of gles' interface. The plan that a
// variant's sources and manifest are printed from, and the printers: the GLSL generator
// (export_glsl.cpp), the dominant lights' functions (export_lights.cpp) and the manifest
// (export_manifest.cpp). export.cpp chooses the texture layouts, fills the plan and calls them.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "brdf/glsl.h"
#include "gles/export.h"

namespace inlight::gles::detail {

/// A float literal GLSL ES reads back to the same float.
inline std::string lit(double v) { return brdf::glsl_float(static_cast<float>(v)); }

/// Everything the generator decides before printing.
struct Plan {
    const Variant* v = nullptr;
    const MaterialInputs* mat = nullptr;
    const brdf::Table* table = nullptr;  ///< the bound table (bands = variant bands) or null
    TableLayout layout = TableLayout::kNone;
    LightingLayout lighting = LightingLayout::kUniformArray;
    int texels_per_node = 0;
    int data_width = 0, data_height = 0;  ///< of the table texture
    bool wrapped = false;                 ///< the texels in rows of data_width (linear order)
    bool scale_in_texture = false;        ///< RGBA8: scale/offset texels after the table's
    int scale_texel = 0;                  ///< the first of them (linear index)
    /// Trilinear variants: the atlas level rectangles of each material texture (empty = none
    /// or bilinear) and the atlas size (texels).
    std::vector<render::MipRect> albedo_levels, normal_levels;
    Eigen::Vector2i albedo_atlas_px{0, 0}, normal_atlas_px{0, 0};
    bool trilinear() const { return v->texture_filter == TextureFilter::kTrilinear; }
    bool es3() const { return v->version == GlslVersion::kEs300; }
    int channels() const { return table ? table->channels : 0; }
};

/// The vertex and fragment shader sources of the plan's variant (`name` goes in a comment).
std::string vertex_source(const Plan& p, const std::string& name);
std::string fragment_source(const Plan& p, const std::string& name);

/// exp_f32, log_f32 and pow_f32 to float accuracy (Cephes expf/logf: range reduction, then a
/// polynomial, from +, *, / and floor): drivers' exp(), log() and pow() carry no accuracy
/// requirement (llvmpipe's pow is ~1.5e-3 off, docs/gles.md). The driver's log2() only picks
/// the binade, corrected by one step either way; powers of two come from exact products.
/// Returns pow2i, exp_f32, log_f32 and pow_f32 in GLSL.
std::string exp_log_functions();

/// The dominant lights' functions (render/realtime_lights.h, envmap/lights.h): the cap's
/// irradiance factor and, with a table, the material's specular lobe. Needs atan2_f32.
std::string lights_functions(const Plan& p);

/// "<material>.albedo.png" | "<material>.normal.png": a material texture's file beside the
/// manifests (an 8-bit RGBA PNG whose samples are the texel bytes, rows top first; PNG, not raw
/// texels, because the app downloads it: about a quarter of the raw size for the sample
/// fabrics); its mip atlas (trilinear variants): "<material>.albedo.mip.png" |
/// "<material>.normal.mip.png", the same format.
inline std::string texture_file_name(const std::string& material, bool albedo, bool mip = false) {
    return material + (albedo ? ".albedo" : ".normal") + (mip ? ".mip" : "") + ".png";
}

/// The variant's manifest: every uniform with its value or source, every texture with its file,
/// layout and encoding (docs/gles.md).
/// How an app turns the linear HDR output into 8-bit display codes (docs/gles.md, "What the app
/// binds"): the recipe render's PNGs, the harness comparisons and the BTF export follow.
nlohmann::json output_encoding_8bit();

nlohmann::json make_manifest(const Export& e, const Plan& p, const Limits& limits);

}  // namespace inlight::gles::detail
