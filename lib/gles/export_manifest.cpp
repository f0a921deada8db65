// gles/export_manifest.cpp: the manifest of an exported variant (docs/gles.md, "Manifest").
#include "gles/export_glsl.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <regex>
#include <sstream>

#include "brdf/bake.h"
#include "brdf/glsl.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/json_out.h"
#include "sh/sh.h"

namespace inlight::gles::detail {

namespace {

constexpr const char* kPngRgba8 =
    "PNG, 8-bit RGBA: the decoded samples are the texel bytes glTexImage2D takes (rows top first; decode without "
    "gamma, colour management or premultiplication: alpha is 255)";
constexpr const char* kRawRgba8 =
    "raw RGBA8, width x height x 4 bytes, rows top first (the file's first row is glTexImage2D's first), no header";

}  // namespace

nlohmann::json output_encoding_8bit() {
    return {{"exposure", {{"default", "auto"},
                          {"auto", "exposure = 0.18 / Y_mean, Y_mean = the mean over the frame's drawn pixels of "
                                   "0.2126 R + 0.7152 G + 0.0722 B (linear_srgb radiance); 1 when Y_mean <= 0 "
                                   "(render's auto exposure, as render --exposure 0)"},
                          {"fixed", "an app with an exposure control uses its own multiplier instead (render --exposure E)"}}},
            {"steps", {"v = exposure x radiance per channel (rgb)", "v = clamp(v, 0, 1)",
                       "e = v <= 0.0031308 ? 12.92 v : 1.055 v^(1/2.4) - 0.055 (the sRGB OETF, IEC 61966-2-1)",
                       "code = round(255 e), 0 .. 255; alpha 255"}},
            {"where", "on the float target's pixels (a post pass or the readback); a target without float "
                      "colour buffers needs a fixed exposure and the steps appended to the output line: "
                      "out = vec4(oetf(clamp(exposure * radiance, 0.0, 1.0)), 1.0) in an RGBA8 (not sRGB) target"}};
}

namespace {

/// A trilinear variant's texture entry: the file is the mip atlas (render/mip.h); its size,
/// level rectangles, the level-of-detail rule and the lookup.
void add_mip(nlohmann::json& t, const std::vector<render::MipRect>& levels, const Eigen::Vector2i& atlas, bool albedo) {
    nlohmann::json rects = nlohmann::json::array();
    for (size_t k = 0; k < levels.size(); ++k) {
        const render::MipRect& r = levels[k];
        rects.push_back({{"level", k}, {"x", r.x}, {"y", r.y}, {"width", r.width}, {"height", r.height}});
    }
    t["width"] = atlas.x();
    t["height"] = atlas.y();
    t["meaning"] = str(t["meaning"].get<std::string>(), "; as its mip atlas (mip)");
    t["padding"] = "texels outside every level's rectangle (the column's foot) are (0, 0, 0, 255) and never read";
    t["mip"] = {
        {"filter", "trilinear"},
        {"atlas", "level 0 (the texture) at (0, 0); levels 1 .. in a column at x = level 0's width, top to bottom; "
                  "level k+1 is max(1, floor(w_k / 2)) x max(1, floor(h_k / 2)) texels, down to 1 x 1"},
        {"levels", rects},
        {"level_texels", albedo ? "level k >= 1: each texel the exact average, over its footprint on level 0, of level 0's "
                                  "bilinear reconstruction (wrapping), in linear values (the sRGB bytes decoded), stored "
                                  "sRGB-encoded as the nearest code (render::build_mip_atlas)"
                                : "level k >= 1: each texel the exact average, over its footprint on level 0, of level 0's "
                                  "bilinear reconstruction (wrapping) of the bytes / 255, not renormalised, stored as the "
                                  "nearest code (render::build_mip_atlas)"},
        {"level_of_detail", "size0 = level 0's (width, height); dx = dFdx(v_uv) * size0, dy = dFdy(v_uv) * size0 (texels "
                            "per pixel, differences across the 2 x 2 quad); lod = 0.5 * log2(max(dot(dx, dx), dot(dy, dy)) "
                            "/ 3 + 2 / 3) (the box-matched level, render::box_matched_lod); l = clamp(lod, 0, levels - 1)"},
        {"lookup", str("bilinear between texel centres in level floor(l) and in level min(floor(l) + 1, levels - 1), each "
                       "wrapping inside its own rectangle (texel i of a w-texel level at x + (i mod w)), mixed by l - floor(l); "
                       "8 texel fetches per fragment", albedo ? ", each sRGB-decoded before filtering" : "")},
        {"gl", "NEAREST, no GL mipmaps, CLAMP_TO_EDGE: the shader wraps and filters (ES 2.0 NPOT textures allow this)"}};
}

}  // namespace

nlohmann::json make_manifest(const Export& e, const Plan& p, const Limits& limits) {
    using nlohmann::json;
    const MaterialInputs& mat = *p.mat;
    const bool es3 = p.es3();
    const bool uv = mat.has_albedo_texture() || mat.has_normal_texture();
    json m;
    m["format"] = "inlight_gles_export";
    m["version"] = 1;
    m["name"] = e.name;
    m["variant"] = {{"glsl_version", es3 ? "300 es" : "100"},
                    {"mode", to_string(p.v->mode)},
                    {"sh_bands", p.v->sh_bands},
                    {"precision", to_string(p.v->precision)},
                    {"material", mat.name}};
    const std::string albedo_file = texture_file_name(mat.name, true, p.trilinear());
    const std::string normal_file = texture_file_name(mat.name, false, p.trilinear());
    m["files"] = {{"vertex", e.name + ".vert"},
                  {"fragment", e.name + ".frag"},
                  {"brdf_data", p.table ? json(e.name + ".brdf.bin") : json(nullptr)},
                  {"albedo_texture", mat.has_albedo_texture() ? json(albedo_file) : json(nullptr)},
                  {"normal_texture", mat.has_normal_texture() ? json(normal_file) : json(nullptr)}};
    m["texture_filter"] = to_string(p.v->texture_filter);
    m["paths"] = "every file named here is relative to this manifest's folder";
    m["frame"] = "device: +z out of the screen toward the viewer (docs/conventions.md)";
    json attrs = json::array();
    attrs.push_back({{"name", "a_position"}, {"type", "vec3"}, {"meaning", "position, device frame"}});
    attrs.push_back({{"name", "a_normal"}, {"type", "vec3"}, {"meaning", "unit geometric normal, device frame, facing the viewer"}});
    if (mat.has_normal_texture()) {
        attrs.push_back({{"name", "a_tangent"}, {"type", "vec3"}, {"meaning", "dp/du, device frame (normal-map x axis)"}});
    }
    if (uv) {
        attrs.push_back({{"name", "a_uv"}, {"type", "vec2"},
                         {"meaning", mat.uv_in_metres ? "position on the fabric in metres (u along a_tangent, v down): the quad's "
                                                        "physical size, so the weave shows at its real scale"
                                                      : "texture uv, v down (1 = one tile)"},
                         {"units", mat.uv_in_metres ? "m" : "tiles"}});
    }
    m["attributes"] = attrs;
    json uniforms = json::array();
    uniforms.push_back({{"name", "u_clip_from_object"}, {"type", "mat4"}, {"count", 1}, {"stage", "vertex"},
                        {"meaning", "clip from device frame"},
                        {"source", {{"from", "camera"},
                                    {"how", "the app's camera each frame: projection x view (x the object's placement in "
                                            "the device frame); glUniformMatrix4fv column-major, transpose GL_FALSE. A "
                                            "scene export (render export-gles) gives its camera's in scene.clip_from_object"}}}});
    if (uv) {
        uniforms.push_back({{"name", "u_uv_scale"}, {"type", "vec2"}, {"count", 1}, {"stage", "vertex"},
                            {"meaning", mat.uv_in_metres ? "tiles per metre of a_uv (1 / the tile size in metres)" : "tiles per unit of a_uv"},
                            {"units", mat.uv_in_metres ? "tiles per m" : "tiles"},
                            {"value", {mat.uv_scale.x(), mat.uv_scale.y()}}});
    }
    const int sh_count = sh::count(p.v->sh_bands);
    const char* sh_meaning = "lighting SH coefficients L_lm (R, G, B), device frame, real SH without Condon-Shortley phase, index l(l+1)+m";
    const json sh_source = {
        {"from", "lighting_file.coefficients"},
        {"file", "the lighting file (docs/formats.md, \"SH coefficients\": envmap-project's JSON; with \"lights\", the "
                 "residual's coefficients), rotated into the device frame when the device turns (sh/rotation.h)"},
        {"count", sh_count},
        {"padding", str("coefficient k (k = 0 .. ", sh_count - 1, ") = the file's row k when the file has more than k rows; "
                        "(0, 0, 0) when it has fewer bands than the variant's ", p.v->sh_bands,
                        " (rows k >= sh_bands_file^2); rows beyond ", sh_count, " (more bands than the variant) are not bound")}};
    if (p.lighting == LightingLayout::kUniformArray) {
        uniforms.push_back({{"name", "u_sh"}, {"type", "vec3"}, {"count", sh_count}, {"stage", "fragment"},
                            {"meaning", sh_meaning}, {"units", "radiance (linear_srgb, the environment's units)"},
                            {"source", sh_source}});
    }
    uniforms.push_back({{"name", "u_albedo"}, {"type", "vec3"}, {"count", 1}, {"stage", "fragment"},
                        {"meaning", mat.has_albedo_texture() ? "material albedo, linear_srgb (multiplies the albedo texture's decoded texels)"
                                                             : "material albedo, linear_srgb"},
                        {"range", {0.0, 1.0}},
                        {"value", {mat.brdf.albedo.x(), mat.brdf.albedo.y(), mat.brdf.albedo.z()}}});
    if (p.v->lights > 0) {
        uniforms.push_back({{"name", "u_light_direction"}, {"type", "vec4"}, {"count", p.v->lights}, {"stage", "fragment"},
                            {"meaning", "per dominant light j: xyz = unit direction toward the light (device frame, as u_sh: rotate it "
                                        "with the device), w = sin(angular_radius), 0 below 1e-4 rad (a point light)"},
                            {"units", "xyz dimensionless; w = sine of the cap's half-angle alpha"},
                            {"range", {-1.0, 1.0}},
                            {"from_lighting_file", "direction normalised; w = alpha < 1e-4 rad ? 0 : sin(alpha), alpha = angular_radius_deg in radians"},
                            {"source", {{"from", "lighting_file.lights"},
                                        {"how", "light j = the lighting file's lights[j] (docs/formats.md, \"SH coefficients with "
                                                "lights\"), as from_lighting_file; \"value\", when present, holds them for the "
                                                "lights the variant was exported with (--gles-lighting)"}}}});
        uniforms.push_back({{"name", "u_light_irradiance"}, {"type", "vec3"}, {"count", p.v->lights}, {"stage", "fragment"},
                            {"meaning", "per dominant light j: E_perp, the irradiance of its uniform cap on a surface facing it (linear_srgb)"},
                            {"units", "radiance x sr (the environment's radiance units times steradians)"},
                            {"range", {0.0, "unbounded (HDR: a sun is ~1e4 x the sky)"}},
                            {"from_lighting_file", "flux * (1 + cos(alpha)) / 2 per channel"},
                            {"source", {{"from", "lighting_file.lights"},
                                        {"how", "as u_light_direction, light j = lights[j]"}}}});
        json lights = {{"count", p.v->lights},
                       {"lighting_file", "docs/formats.md, \"SH coefficients with lights\": envmap-project --max-error's lights array; "
                                         "u_sh then holds the residual map's coefficients"},
                       {"shading", p.v->light_shading == envmap::LightShading::kSmoothCap
                                       ? "per light: albedo / pi E(n) + f_s(n; view, d) E(n), E = E_perp J(n.d, alpha), J = the smooth "
                                         "cap: c = n.d above sin(alpha), 0 below -sin(alpha), (c + sin alpha)^2 / (4 sin alpha) between; "
                                         "f_s the material's lobe"
                                       : "per light: albedo / pi E(n) + f_s(n; view, d) E(n), E = E_perp J(n.d, alpha), J = Snyder's cap "
                                         "integral over pi sin^2(alpha) (= max(0, n.d) for a point); f_s the material's lobe"},
                       {"irradiance", envmap::to_string(p.v->light_shading)},
                       {"uniform_vectors", 2 * p.v->lights}};
        if (p.table) {
            const brdf::Material& b = mat.brdf;
            lights["lobe"] = {{"model", brdf::to_string(b.specular)}, {"alpha", b.alpha},
                              {"f0", {b.f0.x(), b.f0.y(), b.f0.z()}}, {"report_f", b.report_f}, {"report_r", b.report_r},
                              {"sheen_color", {b.sheen_color.x(), b.sheen_color.y(), b.sheen_color.z()}},
                              {"specular_scale", b.specular_scale},
                              {"note", "constants in the shader: the lobe the BRDF table was baked from, at the table's view"}};
        } else {
            lights["lobe"] = nullptr;
        }
        m["lights"] = lights;
    }
    json textures = json::array();
    int unit = 0;
    if (mat.has_albedo_texture()) {
        textures.push_back({{"uniform", "u_albedo_texture"}, {"unit", unit++},
                            {"internal_format", es3 ? "RGBA8" : "RGBA"}, {"format", "RGBA"}, {"type", "UNSIGNED_BYTE"},
                            {"width", mat.albedo_texture_px.x()}, {"height", mat.albedo_texture_px.y()},
                            {"filter", "NEAREST"}, {"wrap", "CLAMP_TO_EDGE"}, {"color_space", "srgb"},
                            {"meaning", "albedo texture, sRGB bytes (not an sRGB internal format): the shader decodes each texel exactly, then filters"},
                            {"range", {0.0, 1.0}}, {"file", albedo_file}, {"file_format", kPngRgba8},
                            {"padding", "none"}});
        if (p.trilinear()) add_mip(textures.back(), p.albedo_levels, p.albedo_atlas_px, true);
    }
    if (mat.has_normal_texture()) {
        textures.push_back({{"uniform", "u_normal_texture"}, {"unit", unit++}, {"internal_format", "RGBA8"}, {"format", "RGBA"},
                            {"type", "UNSIGNED_BYTE"}, {"width", mat.normal_texture_px.x()}, {"height", mat.normal_texture_px.y()},
                            {"filter", "NEAREST"}, {"wrap", "CLAMP_TO_EDGE"}, {"color_space", "data"},
                            {"meaning", "tangent-space normal map, n = 2 rgb - 1"}, {"range", {0.0, 1.0}},
                            {"file", normal_file}, {"file_format", kPngRgba8}, {"padding", "none"}});
        if (p.trilinear()) add_mip(textures.back(), p.normal_levels, p.normal_atlas_px, false);
    }
    if (p.table) {
        const brdf::Table& t = *p.table;
        float lo = 0, hi = 0;
        if (!e.table_texels.empty()) {
            lo = *std::min_element(e.table_texels.begin(), e.table_texels.end());
            hi = *std::max_element(e.table_texels.begin(), e.table_texels.end());
        }
        json table = {{"grid", brdf::to_string(t.grid)}, {"layout", to_string(p.layout)},
                      {"sh_bands", t.sh_bands}, {"coeff_count", t.coeff_count()}, {"channels", t.channels},
                      {"texels_per_node", p.texels_per_node},
                      {"view", {t.view.x(), t.view.y(), t.view.z()}},
                      {"texel_of", p.layout == TableLayout::kUniformArray
                                       ? "u_brdf[i], i = ((channel * rows + i1) * cols + i2) * texels_per_node + k / 4, component k % 4 (one vector per texel, no rows)"
                                       : !p.wrapped
                                       ? "x = i2 * texels_per_node + k / 4, y = channel * rows + i1, component k % 4 (= linear texel i = ((channel * rows + i1) * cols + i2) * texels_per_node + k / 4 in rows of width)"
                                       : "i = ((channel * rows + i1) * cols + i2) * texels_per_node + k / 4, x = i % width, y = i / width, component k % 4 (rows of GL_MAX_TEXTURE_SIZE: the natural rows do not fit)"},
                      {"wrapped", p.wrapped},
                      {"units", "dimensionless (reflected radiance per unit lighting coefficient)"},
                      {"value_range", {lo, hi}}};
        if (p.layout == TableLayout::kUniformArray) {
            uniforms.push_back({{"name", "u_brdf"}, {"type", "vec4"}, {"count", e.data_width}, {"stage", "fragment"},
                                {"meaning", "BRDF SH table: u_brdf[i] = the file's texel i (brdf_table.texel_of)"},
                                {"file", e.name + ".brdf.bin"},
                                {"value", {{"file", e.name + ".brdf.bin"},
                                           {"file_format", str("float32 little-endian, 4 per vector, ", e.data_width,
                                                               " vectors: glUniform4fv(u_brdf, ", e.data_width, ", file)")}}},
                                {"range", {lo, hi}}});
        } else {
            const bool rgba8 = p.layout == TableLayout::kRgba8Texture;
            textures.push_back({{"uniform", "u_brdf_texture"}, {"unit", unit++},
                                {"internal_format", rgba8 ? "RGBA" : "RGBA32F"}, {"format", "RGBA"},
                                {"type", rgba8 ? "UNSIGNED_BYTE" : "FLOAT"}, {"width", e.data_width}, {"height", e.data_height},
                                {"filter", "NEAREST"}, {"wrap", "CLAMP_TO_EDGE"}, {"color_space", "data"},
                                {"file", e.name + ".brdf.bin"},
                                {"file_format", rgba8 ? kRawRgba8 : "raw RGBA float32 little-endian, width x height texels, "
                                                                    "rows top first (the file's first row is glTexImage2D's first), no header"},
                                {"meaning", rgba8 ? "BRDF SH table, value = offset_k + scale_k x texel (texel = byte / 255) per coefficient k"
                                                  : "BRDF SH table"},
                                {"padding", str("texels ", (p.scale_in_texture ? 2 * sh::count(p.v->sh_bands) : 0) + brdf::texture_size(t).prod(),
                                                " .. width x height - 1 (the last row's end) are zero")},
                                {"range", rgba8 ? json({0.0, 1.0}) : json({lo, hi})}});
        }
        if (p.layout == TableLayout::kRgba8Texture && p.scale_in_texture) {
            const int k_count = sh::count(p.v->sh_bands);
            table["scale_offset"] = {
                {"where", "in the table texture: linear texel scale_texel + k holds scale_k, scale_texel + coeff_count + k "
                          "offset_k, each a float32 in 4 bytes (byte 0 = exponent + 127, 0 = zero; bytes 1-3 = mantissa, its "
                          "leading 1 replaced by the sign), as u_sh_texture's rows 2 and 3"},
                {"scale_texel", p.scale_texel},
                {"why", "as uniforms they would take 2 ceil(coeff_count / 4) fragment uniform vectors, more than the limits given leave"},
                {"scale", std::vector<float>(e.table_scale.begin(), e.table_scale.begin() + k_count)},
                {"offset", std::vector<float>(e.table_offset.begin(), e.table_offset.begin() + k_count)}};
        } else if (p.layout == TableLayout::kRgba8Texture) {
            uniforms.push_back({{"name", "u_brdf_scale"}, {"type", "vec4"}, {"count", p.texels_per_node}, {"stage", "fragment"},
                                {"meaning", "scale_k of the RGBA8 table, coefficient k = component k % 4 of vector k / 4: "
                                            "table value = offset_k + scale_k x texel (texel = byte / 255 as sampled)"},
                                {"units", "as brdf_table.units"},
                                {"value", e.table_scale}});
            uniforms.push_back({{"name", "u_brdf_offset"}, {"type", "vec4"}, {"count", p.texels_per_node}, {"stage", "fragment"},
                                {"meaning", "offset_k of the RGBA8 table (the least value of coefficient k over the table), "
                                            "coefficient k = component k % 4 of vector k / 4: table value = offset_k + scale_k x texel"},
                                {"units", "as brdf_table.units"},
                                {"value", e.table_offset}});
        }
        if (p.layout == TableLayout::kRgba8Texture) {
            const int slots = 4 * p.texels_per_node;
            double err = 0;
            for (int s = 0; s < slots; ++s) err = std::max(err, e.table_scale[s] / 510.0);
            table["quantization_max_abs_error"] = err;
        }
        m["brdf_table"] = table;
    }
    const int k_count = sh::count(p.v->sh_bands);
    if (p.lighting != LightingLayout::kUniformArray) {
        const bool rgba8 = p.lighting == LightingLayout::kRgba8Texture;
        json t = {{"uniform", "u_sh_texture"}, {"unit", unit++}, {"internal_format", rgba8 ? "RGBA" : "RGBA32F"},
                  {"format", "RGBA"}, {"type", rgba8 ? "UNSIGNED_BYTE" : "FLOAT"}, {"width", k_count},
                  {"height", rgba8 ? 4 : 1}, {"filter", "NEAREST"}, {"wrap", "CLAMP_TO_EDGE"}, {"color_space", "data"},
                  {"meaning", sh_meaning}, {"units", "radiance (linear_srgb, the environment's units)"},
                  {"packing", rgba8 ? "gles::bind_lighting: column k = coefficient k; rows 0, 1 = high, low byte of "
                                      "q = round((L - offset_k) / scale_k * 65535) per channel (rgb); rows 2, 3 = scale_k, "
                                      "offset_k as float32 (byte 0 = exponent + 127, 0 = zero; bytes 1-3 = mantissa, its "
                                      "leading 1 replaced by the sign); offset_k = least channel, scale_k = their spread"
                                    : "texel k: rgb = L_k, a unused"},
                  {"updated", "whenever the lighting changes (device rotation): re-pack and re-upload"},
                  {"file", nullptr},
                  {"source", sh_source},
                  {"file_format", "none: the app packs it from the lighting each frame (packing)"},
                  {"padding", "none"}};
        if (rgba8) t["quantization_max_abs_error"] = "scale_k / 131070 per coefficient (16 bits), scale_k the spread of L_k over R, G, B";
        textures.push_back(t);
    }
    m["lighting_layout"] = to_string(p.lighting);
    m["uniforms"] = uniforms;
    m["textures"] = textures;
    int max_side = std::max(mat.albedo_texture_px.maxCoeff(), mat.normal_texture_px.maxCoeff());
    if (p.trilinear()) max_side = std::max({max_side, p.albedo_atlas_px.maxCoeff(), p.normal_atlas_px.maxCoeff()});
    if (p.table && p.layout != TableLayout::kUniformArray) max_side = std::max({max_side, e.data_width, e.data_height});
    if (p.lighting != LightingLayout::kUniformArray) max_side = std::max(max_side, sh::count(p.v->sh_bands));
    json ext = json::array();
    if (!es3 && p.v->precision == Precision::kHighp) ext.push_back("GL_FRAGMENT_PRECISION_HIGH (highp in fragment shaders)");
    if (!es3 && uv && p.trilinear()) ext.push_back("GL_OES_standard_derivatives (dFdx, dFdy: the trilinear level of detail)");
    m["gl_limits_needed"] = {{"context", es3 ? "OpenGL ES 3.0" : "OpenGL ES 2.0"},
                             {"max_fragment_uniform_vectors", e.fragment_uniform_vectors},
                             {"max_texture_image_units", unit},
                             {"max_texture_size", max_side},
                             {"requires", ext},
                             {"limits_given", {{"max_fragment_uniform_vectors", limits.max_fragment_uniform_vectors},
                                               {"max_texture_size", limits.max_texture_size},
                                               {"max_texture_image_units", limits.max_texture_image_units}}}};
    m["output"] = {{"variable", es3 ? "o_radiance" : "gl_FragColor"}, {"quantity", "radiance (rgb; alpha 1)"},
                   {"color_space", "linear_srgb"}, {"clamped", false},
                   {"units", "the lighting's radiance units (u_sh, u_light_irradiance / sr)"},
                   {"range", {0.0, "unbounded (HDR)"}},
                   {"framebuffer", "RGBA32F (EXT_color_buffer_float) keeps HDR radiance; an 8-bit target clamps to [0, 1]"},
                   {"encoding_8bit", output_encoding_8bit()}};
    m["precision"] = {{"declared", to_string(p.v->precision)}, {"safe", "highp"},
                      {"mediump", "unsafe for float output: mediump guarantees a 10-bit mantissa (relative step 2^-10 = 9.8e-4, "
                                  "the whole 1e-3 budget before any arithmetic) and magnitudes below 2^14; the SH sums cancel "
                                  "terms of either sign, so their error is a multiple of that step (measured in docs/gles.md)"}};
    return m;
}
}  // namespace inlight::gles::detail
