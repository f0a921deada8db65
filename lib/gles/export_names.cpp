// gles/export_names.cpp: the names of the exporter's choices (GLSL version, mode, precision,
// layouts) as options and manifests spell them, and the GLES minimum limits.
#include "gles/export.h"

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

namespace inlight::gles {

constexpr EnumName<GlslVersion> kGlslVersionNames[] = {{GlslVersion::kEs100, "100"},
                                                       {GlslVersion::kEs300, "300"}};
constexpr EnumName<ShaderMode> kShaderModeNames[] = {{ShaderMode::kConsistent, "consistent"},
                                                     {ShaderMode::kSeed, "seed"}};
constexpr EnumName<Precision> kPrecisionNames[] = {{Precision::kHighp, "highp"},
                                                   {Precision::kMediump, "mediump"}};
constexpr EnumName<TableLayout> kTableLayoutNames[] = {
    {TableLayout::kNone, "none"},
    {TableLayout::kUniformArray, "uniform_array"},
    {TableLayout::kFloatTexture, "rgba32f_texture"},
    {TableLayout::kRgba8Texture, "rgba8_texture"},
};
constexpr EnumName<LightingLayout> kLightingLayoutNames[] = {
    {LightingLayout::kUniformArray, "uniform_array"},
    {LightingLayout::kFloatTexture, "rgba32f_texture"},
    {LightingLayout::kRgba8Texture, "rgba8_texture_16bit"},
};

constexpr EnumName<TextureFilter> kTextureFilterNames[] = {{TextureFilter::kBilinear, "bilinear"},
                                                           {TextureFilter::kTrilinear, "trilinear"}};

TextureFilter texture_filter_from_string(const std::string& name) {
    return enum_from_string(kTextureFilterNames, name, "texture filter");
}
std::string to_string(TextureFilter f) { return enum_to_string(kTextureFilterNames, f); }

GlslVersion glsl_version_from_string(const std::string& name) {
    return enum_from_string(kGlslVersionNames, name, "GLSL ES version");
}
ShaderMode shader_mode_from_string(const std::string& name) {
    return enum_from_string(kShaderModeNames, name, "shader mode");
}
Precision precision_from_string(const std::string& name) {
    return enum_from_string(kPrecisionNames, name, "precision");
}
std::string to_string(GlslVersion v) { return enum_to_string(kGlslVersionNames, v); }
std::string to_string(ShaderMode m) { return enum_to_string(kShaderModeNames, m); }
std::string to_string(Precision p) { return enum_to_string(kPrecisionNames, p); }
std::string to_string(TableLayout l) { return enum_to_string(kTableLayoutNames, l); }
std::string to_string(LightingLayout l) { return enum_to_string(kLightingLayoutNames, l); }

namespace {
template <typename T>
std::vector<T> parse_list(const std::string& list, T (*parse)(const std::string&)) {
    std::vector<T> out;
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(parse(item));
    if (out.empty()) throw UsageError(str("empty list '", list, "'"));
    return out;
}
}  // namespace

std::vector<GlslVersion> glsl_versions_from_string(const std::string& list) {
    return parse_list(list, glsl_version_from_string);
}
std::vector<ShaderMode> shader_modes_from_string(const std::string& list) {
    return parse_list(list, shader_mode_from_string);
}
std::vector<Precision> precisions_from_string(const std::string& list) {
    return parse_list(list, precision_from_string);
}

Limits Limits::minimum(GlslVersion version) {
    Limits l;
    if (version == GlslVersion::kEs100) {
        l.max_fragment_uniform_vectors = 16;
        l.max_texture_size = 64;
        l.max_texture_image_units = 8;
    }
    return l;
}


}  // namespace inlight::gles
