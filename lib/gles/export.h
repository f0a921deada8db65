// gles/export.h: complete OpenGL ES shaders for the app's real-time shading, generated per
// material and variant, with a JSON manifest of everything the app must bind. The fragment
// shader computes term for term what render/realtime.h computes on the CPU (that model is the
// specification; gles_test.cpp runs both on the same inputs through gles/harness.h).
//
// A variant = GLSL ES version (1.00, the inlight report's OpenGL ES 2.0 target, or 3.00) x mode
// (consistent | seed, as RealtimeMode) x lighting bands (3 .. the table's bands; seed: 3) x
// float precision (highp | mediump). The source holds only the code that variant runs: no
// #ifdef, no unused uniform, no unused function.
//
// Frames and units (docs/gles.md): positions, normals and tangents in the device frame (+z out
// of the screen toward the viewer, core/conventions.h); lighting SH coefficients u_sh[k]
// (radiance, linear_srgb, device frame, real SH without Condon-Shortley phase, index
// l(l+1)+m, sh/sh.h); the fragment output is linear_srgb radiance (not clamped, not encoded).
// The app rotates the coefficients on the CPU (sh/rotation.h) when the device turns: the BRDF
// table is tabulated in the device frame, so a rotation uniform could not serve its lookup.
//
// Per fragment (render/material.cpp shade() and render/realtime.cpp):
//   uv      = v_uv (the vertex shader multiplies a_uv by u_uv_scale; tiles wrap)
//   albedo  = u_albedo x albedo texture (RGBA8 sRGB bytes; the shader decodes each of the 4
//             nearest texels exactly, then filters: decode before filtering, as the CPU model;
//             drivers' own sRGB decoders are approximations, docs/gles.md)
//   filter  Variant::texture_filter: kBilinear reads level 0 (4 texels per texture); kTrilinear
//             binds each texture as its mip atlas (render/mip.h, levels built by
//             render::build_mip_atlas and stored as 8-bit codes, exactly what the CPU model
//             reads) and reads it trilinearly (8 texels per texture) at the level of detail
//             lod = log2(rho^2 / 3 + 2 / 3) / 2 (render::box_matched_lod), rho^2 = max(|dFdx
//             (v_uv) size0|^2, |dFdy(v_uv) size0|^2), clamped to the levels; each level wraps
//             inside its own rectangle (NEAREST, no GL mipmaps: ES 2.0 NPOT works). ES 1.00
//             needs GL_OES_standard_derivatives (the manifest lists it).
//   n       = normalize(v_normal), then the normal map (data, 2 rgb - 1, tangent frame (t,
//             n x t, n), bilinear in the shader), falling back to v_normal when it faces away
//             from the table's view (a constant: the table is baked for one view)
//   radiance: consistent = albedo / pi E(n) + sum_k L_k B_k(n); seed = the report's shader.
// Data layouts (chosen from the Limits given; an export that does not fit is an Error naming
// what it needs, never a truncated table):
//   BRDF table  ES 3.00: uniform vec4 array (4 coefficients per vector) when it fits, else an
//               RGBA32F texture (brdf/table.h texture_texels(), read with texelFetch).
//               ES 1.00: always an RGBA8 texture (fragment uniform arrays may only be indexed
//               by constants in ES 1.00, and float textures are an extension), value =
//               offset_k + scale_k x texel, scale/offset per coefficient in uniforms when they
//               fit, else as float32 bytes in texels after the table's (Export::
//               table_scale_in_texture). A texture wider or taller than GL_MAX_TEXTURE_SIZE
//               keeps its texels' linear order in rows of that size (both versions).
//   Lighting    uniform vec3 u_sh[count(bands)] when it fits beside everything else, else a
//               texture u_sh_texture (LightingLayout, BoundLighting). ES 1.00 takes the
//               cheapest arrangement that fits: all in uniforms; the table's scale/offset in
//               its texture (2 fetches per coefficient); the lighting in its texture (4); both.
//   Lights      (consistent mode, Variant::lights > 0) per light j two uniform vectors:
//               u_light_direction[j] = (d, sin alpha) and u_light_irradiance[j] = E_perp =
//               flux (1 + cos alpha) / 2 (light_uniforms()); each light adds
//               albedo / pi E_j(n) + f_s(n; VIEW, d) E_j(n) with E_j the uniform cap's exact
//               irradiance and f_s the material's lobe, as render/realtime_lights.h.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/table.h"
#include "envmap/lights.h"
#include "render/mip.h"

namespace inlight::gles {

enum class GlslVersion { kEs100, kEs300 };
enum class ShaderMode { kConsistent, kSeed };
enum class Precision { kHighp, kMediump };
enum class TableLayout { kNone, kUniformArray, kFloatTexture, kRgba8Texture };
/// Where the lighting coefficients L_lm sit: uniform vec3 u_sh[] when they fit, else a texture
/// u_sh_texture (ES 3.00: RGBA32F, count x 1; ES 1.00: RGBA8, count x 4, 16 bits per value
/// with a scale and offset per coefficient stored in the texture, see bind_lighting()).
enum class LightingLayout { kUniformArray, kFloatTexture, kRgba8Texture };

/// "100" | "300"; "consistent" | "seed"; "highp" | "mediump". Throw UsageError otherwise.
GlslVersion glsl_version_from_string(const std::string& name);
ShaderMode shader_mode_from_string(const std::string& name);
Precision precision_from_string(const std::string& name);
std::string to_string(GlslVersion v);
std::string to_string(ShaderMode m);
std::string to_string(Precision p);
std::string to_string(TableLayout l);
std::string to_string(LightingLayout l);
/// The material textures' filter in the shader (render/mip.h; the CPU model's
/// RealtimeOptions::texture_filter): "bilinear" | "trilinear". Throws UsageError otherwise.
using render::TextureFilter;
TextureFilter texture_filter_from_string(const std::string& name);
std::string to_string(TextureFilter f);

/// The GL limits an export must fit (glGetIntegerv names in comments).
struct Limits {
    int max_fragment_uniform_vectors = 224;  ///< GL_MAX_FRAGMENT_UNIFORM_VECTORS
    int max_texture_size = 2048;             ///< GL_MAX_TEXTURE_SIZE (texels per side)
    int max_texture_image_units = 16;        ///< GL_MAX_TEXTURE_IMAGE_UNITS (fragment)
    /// The minimum every conforming implementation offers: ES 2.0 (16, 64, 8) for GLSL ES 1.00,
    /// ES 3.0 (224, 2048, 16) for GLSL ES 3.00.
    static Limits minimum(GlslVersion version);
};

/// What the exporter must know about the material besides its BRDF table.
struct MaterialInputs {
    std::string name = "material";           ///< [A-Za-z0-9_.-]+, used in file names
    Eigen::Vector2i albedo_texture_px{0, 0};  ///< width, height; 0 x 0 = no albedo texture
    Eigen::Vector2i normal_texture_px{0, 0};  ///< width, height; 0 x 0 = no normal map
    /// The material's BRDF: its specular lobe (model and parameters, not its albedo, which is
    /// the u_albedo uniform) is evaluated analytically for the dominant lights (variants with
    /// lights and a table only; the lobe the table was baked from).
    brdf::Material brdf;
    Eigen::Vector2f uv_scale{1, 1};  ///< tiles per unit of a_uv: u_uv_scale's value
    /// a_uv's unit: false = tiles (the mesh's own uv, 1 = one tile), true = metres on the
    /// fabric (u along the tangent, v down), so u_uv_scale = 1 / tile size in metres and the
    /// app's quad shows the fabric at its physical scale (brdf-sh-bake --gles-tile-size-m).
    bool uv_in_metres = false;
    /// The textures' RGBA8 bytes exactly as the app binds them (width x height x 4, rows top
    /// first: the first row is glTexImage2D's first): written beside the manifest as the PNGs
    /// <name>.albedo.png and <name>.normal.png (trilinear variants: their mip atlases,
    /// <name>.albedo.mip.png and <name>.normal.mip.png), which the manifest names. Empty = not
    /// written (write_exports() then refuses a manifest that names them).
    std::vector<uint8_t> albedo_rgba8, normal_rgba8;
    bool has_albedo_texture() const { return albedo_texture_px.x() > 0; }
    bool has_normal_texture() const { return normal_texture_px.x() > 0; }
};

struct Variant {
    GlslVersion version = GlslVersion::kEs300;
    ShaderMode mode = ShaderMode::kConsistent;
    int sh_bands = 3;  ///< lighting bands, 3 .. table bands (kMaxBakeBands without a table)
    Precision precision = Precision::kHighp;
    /// Dominant lights shaded analytically (consistent mode only; the report's shader has none).
    int lights = 0;
    /// How those lights' irradiance is shaded (the lighting file's per-light "irradiance":
    /// envmap::LightShading, docs/formats.md); one formula for all lights of a variant.
    envmap::LightShading light_shading = envmap::LightShading::kCap;
    /// How the material textures are read: kTrilinear binds each as its mip atlas (MipAtlas8)
    /// and names the variant "...-trilinear". A material without textures always gets the
    /// bilinear variant (Export::variant says which was made).
    TextureFilter texture_filter = TextureFilter::kBilinear;
};

/// A material texture as a trilinear variant binds it: the mip atlas (render/mip.h) of its RGBA8
/// texels (level 0 = those bytes; levels >= 1 by render::build_mip_atlas with MipFilter::kBilinear,
/// averaged in linear values, 8-bit codes: sRGB-encoded for albedo, data for a normal map; alpha
/// 255), rows top first, and its level rectangles (render::mip_atlas_levels).
struct MipAtlas8 {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;  ///< width x height x 4
    std::vector<render::MipRect> levels;
};
/// Throws Error when `rgba8` is not size.x() x size.y() x 4 bytes or the size is empty.
MipAtlas8 mip_atlas_rgba8(const std::vector<uint8_t>& rgba8, const Eigen::Vector2i& size, bool srgb);

/// The one irradiance formula of `lights` (kCap when empty); UsageError when they mix formulas.
envmap::LightShading common_light_shading(const std::vector<envmap::DirectionalLight>& lights);

/// One light's uniforms as the shader takes them: direction_sin = (d, sin alpha), with sin
/// alpha = 0 below alpha = 1e-4 rad (the point limit, as envmap::light_irradiance), and
/// normal_irradiance = E_perp = flux (1 + cos alpha) / 2 (the cap's irradiance on a surface
/// facing it wholly above the horizon, per linear_srgb channel).
struct LightUniforms {
    Eigen::Vector4f direction_sin;
    Eigen::Vector3f normal_irradiance;
};
LightUniforms light_uniforms(const envmap::DirectionalLight& light);
/// The arrays glUniform4fv / glUniform3fv take for u_light_direction and u_light_irradiance.
struct LightUniformArrays {
    std::vector<float> direction_sin, normal_irradiance;  ///< 4 and 3 floats per light
};
LightUniformArrays light_uniform_arrays(const std::vector<envmap::DirectionalLight>& lights);

/// One exported variant: sources, manifest and the BRDF data exactly as the app binds it.
struct Export {
    std::string name;  ///< "<material>-es300-consistent-b3-highp"
    std::string material;  ///< MaterialInputs::name
    Variant variant;
    std::string vertex_source, fragment_source;
    nlohmann::json manifest;
    TableLayout table_layout = TableLayout::kNone;
    LightingLayout lighting_layout = LightingLayout::kUniformArray;
    int data_width = 0, data_height = 0;  ///< texels of the table data (uniform: count x 1)
    std::vector<float> table_texels;      ///< RGBA float texels (uniform and float layouts)
    std::vector<uint8_t> table_bytes;     ///< RGBA8 texels (RGBA8 layout)
    std::vector<float> table_scale, table_offset;  ///< per coefficient (RGBA8 layout, 4 per texel)
    /// RGBA8 layout: scale_k and offset_k are not uniforms but texels table_scale_texel + k and
    /// table_scale_texel + count + k of the table texture (linear index, count = the variant's
    /// coefficients), each a float32 in 4 bytes as BoundLighting's rows 2 and 3.
    bool table_scale_in_texture = false;
    int table_scale_texel = 0;
    bool table_wrapped = false;  ///< texels in rows of GL_MAX_TEXTURE_SIZE, not the natural rows
    /// The table the shader sees: truncated to the variant's bands and, for RGBA8, dequantized
    /// (offset + scale x byte / 255 in float). Give this to the CPU model to compare.
    std::optional<brdf::Table> table_as_bound;
    int fragment_uniform_vectors = 0;  ///< as counted by the GLSL ES packing of its declarations
    /// The material's texture files (file name -> bytes, MaterialInputs' RGBA8 bytes) the
    /// manifest names; shared by every variant of the material.
    std::vector<std::pair<std::string, std::string>> texture_files;
};

/// Generates a variant. `table` may be null (a Lambert material: no specular term). Throws
/// UsageError on an impossible variant (bands outside 3 .. table bands, seed with bands != 3,
/// a table with fewer than 3 bands) and Error when it does not fit `limits`, naming the
/// variant, the resource and both numbers.
Export export_variant(const brdf::Table* table, const MaterialInputs& material,
                      const Variant& variant, const Limits& limits);

/// The lighting as a variant with a lighting texture takes it (the app re-packs it whenever the
/// coefficients change, e.g. when the device turns). ES 1.00 RGBA8, count x 4 texels: column k
/// holds coefficient k; rows 0 and 1 the high and low bytes of q_c = round((L_kc - offset_k) /
/// scale_k x 65535) per channel (rgb), rows 2 and 3 scale_k and offset_k (offset = the least of
/// the three channels, scale = their spread) as float32 in 4 bytes: byte 0 = exponent + 127 (0 =
/// zero), bytes 1-3 the 24-bit mantissa with its leading 1 replaced by the sign. Then L_kc =
/// offset_k + scale_k q_c / 65535, within scale_k / 131070 of the float value. ES 3.00 RGBA32F:
/// count x 1 texels, rgb = L_k, exact.
struct BoundLighting {
    int width = 0, height = 0;
    std::vector<float> texels;    ///< RGBA32F layout
    std::vector<uint8_t> bytes;   ///< RGBA8 layout
    Eigen::MatrixXd as_bound;     ///< count x 3: what the shader reads (give it to the CPU model)
    double max_abs_error = 0;     ///< the bound max_k scale_k / 131070 (RGBA8), else 0
};
/// Throws Error when `sh` has fewer than the variant's coefficients or a non-finite value, and
/// when the export keeps its lighting in uniforms.
BoundLighting bind_lighting(const Export& e, const Eigen::MatrixXd& sh);

/// Which variants a tool exports for each material.
struct ExportSet {
    std::vector<GlslVersion> versions{GlslVersion::kEs100, GlslVersion::kEs300};
    std::vector<ShaderMode> modes{ShaderMode::kConsistent, ShaderMode::kSeed};
    /// highp only by default: mediump variants are not validated on a half-float driver
    /// (docs/gles.md, "Precision"); they are exported only when asked for.
    std::vector<Precision> precisions{Precision::kHighp};
    int max_sh_bands = 3;  ///< consistent variants for bands 3 .. this (seed: 3 only)
    /// Dominant lights (a lighting file's, render/realtime_lights.h): the consistent variants
    /// shade this many analytically and their manifests carry these lights' uniform values.
    std::vector<envmap::DirectionalLight> lights;
    /// The target device's GL_MAX_TEXTURE_SIZE; 0 = the specification minimum of each version
    /// (64 for ES 2.0, 2048 for ES 3.0). Below a version's minimum: UsageError.
    int max_texture_size = 0;
    /// The material textures' filter of every variant (Variant::texture_filter).
    TextureFilter texture_filter = TextureFilter::kBilinear;
};
/// The limits `set` exports `version` against: Limits::minimum(version) with the set's
/// max_texture_size. Throws UsageError when that is below the version's minimum.
Limits export_limits(const ExportSet& set, GlslVersion version);
/// Parses comma lists: "100,300", "consistent,seed", "highp,mediump". Throws UsageError.
std::vector<GlslVersion> glsl_versions_from_string(const std::string& list);
std::vector<ShaderMode> shader_modes_from_string(const std::string& list);
std::vector<Precision> precisions_from_string(const std::string& list);

/// A zero table of the shape brdf::bake() gives `material` on `grid` at `sh_bands` (its
/// channels): export_material() on it checks that every variant fits before the bake.
brdf::Table table_shape(const brdf::Material& material, const brdf::Grid& grid, int sh_bands);

/// Every variant of `set` for one material, each against export_limits() of its version (by
/// default the minimum: an export runs on every conforming device). Throws as export_variant,
/// naming the variant.
std::vector<Export> export_material(const brdf::Table* table, const MaterialInputs& material,
                                    const ExportSet& set);

/// Writes export_files() of every export into `dir` (atomically, inside the run's output
/// transaction when there is one) and `dir`/index.json listing them; returns the paths written.
std::vector<std::string> write_exports(const std::string& dir, const std::vector<Export>& exports);

/// index.json's "load": per material, the variant an app loads for each capability (OpenGL ES
/// 3.0+; ES 2.0 with GL_FRAGMENT_PRECISION_HIGH; ES 2.0 without it) and why, from `exports`:
/// consistent before seed (the seed reproduces the report's slips), then the most bands (the
/// closest to the truth), highp before mediump (mediump is not validated), ES 3.00 before 1.00
/// on ES 3 (RGBA32F data, exact texel fetches). "variant" is null, with the reason, when no
/// exported variant runs correctly on that capability.
nlohmann::json load_choices(const std::vector<Export>& exports);

/// The files of an export, name -> bytes: <name>.vert, <name>.frag, <name>.json (manifest),
/// <name>.brdf.bin (the table data, raw little-endian texels as the manifest describes;
/// absent without a table) and the material's texture files (Export::texture_files).
std::vector<std::pair<std::string, std::string>> export_files(const Export& e);

}  // namespace inlight::gles
