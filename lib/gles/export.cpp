// gles/export.cpp: one exported variant (its texture layouts chosen against the device limits,
// its plan printed by export_glsl.h), the lighting an app binds, and the material's set of variants.
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
#include "gles/export_glsl.h"
#include "image/color.h"
#include "image/image.h"
#include "sh/sh.h"

namespace inlight::gles {

using detail::fragment_source;
using detail::lit;
using detail::make_manifest;
using detail::texture_file_name;
using detail::Plan;
using detail::vertex_source;

namespace {
void pack_f32(float v, uint8_t* out);

/// The PNG of RGBA8 texels whose decoded samples are `rgba8` byte for byte: values code / 255
/// written linearly (no sRGB step, alpha never premultiplied: it is 255).
std::string texture_png(const std::vector<uint8_t>& rgba8, const Eigen::Vector2i& px,
                        const std::string& name) {
    image::Image img(px.x(), px.y(), 4, image::ColorSpace::kData);
    for (size_t i = 0; i < rgba8.size(); ++i) img.pixels[i] = rgba8[i] / 255.0f;
    image::WriteOptions w;
    w.encode_srgb = false;
    return image::encode_image(name, img, w);
}
}  // namespace

Export export_variant(const brdf::Table* table, const MaterialInputs& mat, const Variant& asked,
                      const Limits& limits) {
    // The texture filter of a material without textures changes nothing: such a variant is the
    // bilinear one (same code, name and manifest).
    Variant v = asked;
    if (!mat.has_albedo_texture() && !mat.has_normal_texture()) v.texture_filter = TextureFilter::kBilinear;
    if (!std::regex_match(mat.name, std::regex("[A-Za-z0-9_.-]+"))) {
        throw UsageError(str("GLES export: material name '", mat.name,
                             "' must be letters, digits, '_', '.' or '-'"));
    }
    Export e;
    e.variant = v;
    e.material = mat.name;
    e.name = str(mat.name, "-es", to_string(v.version), "-", to_string(v.mode), "-b", v.sh_bands,
                 v.lights > 0 ? str("-l", v.lights) : std::string(), "-", to_string(v.precision),
                 v.texture_filter == TextureFilter::kTrilinear ? "-trilinear" : "");
    const int max_bands = table ? table->sh_bands : brdf::kMaxBakeBands;
    if (v.sh_bands < 3 || v.sh_bands > max_bands) {
        throw UsageError(str("GLES export ", e.name, ": bands must be in 3 .. ", max_bands,
                             table ? " (the table's bands)" : "", ", got ", v.sh_bands));
    }
    if (v.mode == ShaderMode::kSeed && v.sh_bands != 3) {
        throw UsageError(str("GLES export ", e.name, ": the seed mode exists for 3 bands only"));
    }
    if (v.lights < 0 || (v.mode == ShaderMode::kSeed && v.lights > 0)) {
        throw UsageError(str("GLES export ", e.name, ": ", v.lights,
                             " lights (the seed mode, the report's shader, has none)"));
    }
    if (v.lights > 0 && table && mat.brdf.specular == brdf::Model::kLambert) {
        throw UsageError(str("GLES export ", e.name,
                             ": a BRDF table with a Lambert material has no lobe for the lights"));
    }
    Plan p;
    p.v = &v;
    p.mat = &mat;
    const int k_count = sh::count(v.sh_bands);
    const int lim_vectors = limits.max_fragment_uniform_vectors;
    const int lim_size = limits.max_texture_size;
    const int fixed_vectors = 1 + 2 * v.lights;  // u_albedo, u_light_*
    int units = (mat.has_albedo_texture() ? 1 : 0) + (mat.has_normal_texture() ? 1 : 0);
    bool lighting_in_texture = fixed_vectors + k_count > lim_vectors;
    int table_vectors = 0;  // uniform vectors the table takes (array or scale/offset)
    if (table) {
        brdf::Table bound;
        bound.grid = table->grid;
        bound.sh_bands = v.sh_bands;
        bound.channels = table->channels;
        bound.view = table->view;
        bound.resize();
        for (int ch = 0; ch < table->channels; ++ch) {
            for (int i1 = 0; i1 < table->grid.rows; ++i1) {
                for (int i2 = 0; i2 < table->grid.cols; ++i2) {
                    for (int k = 0; k < k_count; ++k) {
                        bound.coeffs[bound.index(ch, i1, i2, k)] = table->at(ch, i1, i2, k);
                    }
                }
            }
        }
        p.texels_per_node = (k_count + 3) / 4;
        const Eigen::Vector2i size = brdf::texture_size(bound);
        const int texel_count = size.x() * size.y();
        if (v.version == GlslVersion::kEs100) {
            p.layout = TableLayout::kRgba8Texture;
            // The cheapest arrangement that fits: all in uniforms; the table's scale and offset
            // (2 ceil(k / 4) vectors) in its texture (2 fetches per coefficient); the lighting
            // (k vectors) in its own (4 fetches per coefficient); both. None fits: refused below.
            const int scale_vectors = 2 * p.texels_per_node;
            const bool options[4][2] = {{false, false}, {false, true}, {true, false}, {true, true}};
            lighting_in_texture = e.table_scale_in_texture = true;
            for (const auto& o : options) {
                if (fixed_vectors + (o[0] ? 0 : k_count) + (o[1] ? 0 : scale_vectors) <= lim_vectors) {
                    lighting_in_texture = o[0];
                    e.table_scale_in_texture = o[1];
                    break;
                }
            }
            table_vectors = e.table_scale_in_texture ? 0 : scale_vectors;
        } else if (fixed_vectors + k_count + texel_count <= lim_vectors) {
            p.layout = TableLayout::kUniformArray;
            table_vectors = texel_count;
        } else {
            p.layout = TableLayout::kFloatTexture;
        }
        e.table_texels = brdf::texture_texels(bound);
        if (p.layout == TableLayout::kUniformArray) {
            e.data_width = texel_count;
            e.data_height = 1;
        } else {
            // The natural rows (cols x texels per node wide, one per channel and grid row) when
            // they fit GL_MAX_TEXTURE_SIZE, else the same linear order in rows of that size; the
            // scale/offset texels, if any, follow the table's. The last row padded.
            ++units;
            e.table_scale_texel = texel_count;
            const int total = texel_count + (e.table_scale_in_texture ? 2 * k_count : 0);
            e.data_width = size.x();
            e.data_height = (total + e.data_width - 1) / e.data_width;
            if (e.data_width > lim_size || e.data_height > lim_size) {
                e.table_wrapped = true;
                e.data_width = lim_size;
                e.data_height = (total + lim_size - 1) / lim_size;
            }
            if (e.data_height > lim_size) {
                throw Error(str("GLES export ", e.name, ": the BRDF table texture needs ", total,
                                " texels (", texel_count, " of the table, ", size.x(), "x", size.y(),
                                e.table_scale_in_texture ? str(", and ", 2 * k_count, " for its scale and offset") : "",
                                "), more than GL_MAX_TEXTURE_SIZE^2 = ", lim_size, "x", lim_size,
                                " holds; give the device's limit (--gles-max-texture-size) or use a "
                                "coarser grid or fewer bands"));
            }
            e.table_texels.resize(static_cast<size_t>(e.data_width) * e.data_height * 4, 0.0f);
        }
        if (p.layout == TableLayout::kRgba8Texture) {
            // Per coefficient k (texel component): value = offset_k + scale_k * byte / 255.
            const int slots = 4 * p.texels_per_node;
            std::vector<float> lo(slots, 0.0f), hi(slots, 0.0f);
            std::vector<bool> seen(slots, false);
            const size_t real = static_cast<size_t>(texel_count) * 4;  // not the padding
            for (size_t i = 0; i < real; ++i) {
                const int s = static_cast<int>(i % static_cast<size_t>(slots));
                const float val = e.table_texels[i];
                lo[s] = seen[s] ? std::min(lo[s], val) : val;
                hi[s] = seen[s] ? std::max(hi[s], val) : val;
                seen[s] = true;
            }
            e.table_scale.resize(slots);
            e.table_offset = lo;
            for (int s = 0; s < slots; ++s) e.table_scale[s] = hi[s] - lo[s];
            if (e.table_scale_in_texture) {  // as the shader unpacks them (subnormals: 0)
                for (float* f : {e.table_scale.data(), e.table_offset.data()}) {
                    for (int s = 0; s < slots; ++s) f[s] = std::abs(f[s]) < FLT_MIN ? 0.0f : f[s];
                }
            }
            e.table_bytes.resize(e.table_texels.size());
            for (size_t i = 0; i < real; ++i) {
                const int s = static_cast<int>(i % static_cast<size_t>(slots));
                const float q = e.table_scale[s] > 0
                                    ? (e.table_texels[i] - e.table_offset[s]) / e.table_scale[s] * 255.0f
                                    : 0.0f;
                e.table_bytes[i] = static_cast<uint8_t>(std::clamp(std::lround(q), 0L, 255L));
            }
            if (e.table_scale_in_texture) {
                for (int k = 0; k < k_count; ++k) {
                    pack_f32(e.table_scale[k], &e.table_bytes[(static_cast<size_t>(e.table_scale_texel) + k) * 4]);
                    pack_f32(e.table_offset[k],
                             &e.table_bytes[(static_cast<size_t>(e.table_scale_texel) + k_count + k) * 4]);
                }
            }
            // The table as the shader sees it.
            const int tn = p.texels_per_node;
            for (int ch = 0; ch < bound.channels; ++ch) {
                for (int i1 = 0; i1 < bound.grid.rows; ++i1) {
                    for (int i2 = 0; i2 < bound.grid.cols; ++i2) {
                        for (int k = 0; k < k_count; ++k) {
                            const size_t texel =  // linear: the wrapped layout keeps it
                                (static_cast<size_t>(ch * bound.grid.rows + i1) * bound.grid.cols +
                                 i2) * tn + k / 4;
                            const float b = e.table_bytes[texel * 4 + k % 4] / 255.0f;
                            bound.coeffs[bound.index(ch, i1, i2, k)] =
                                e.table_offset[k] + e.table_scale[k] * b;
                        }
                    }
                }
            }
        }
        e.table_as_bound = std::move(bound);
        p.table = &*e.table_as_bound;
    }
    e.table_layout = p.layout;
    p.data_width = e.data_width;
    p.data_height = e.data_height;
    p.wrapped = e.table_wrapped;
    p.scale_in_texture = e.table_scale_in_texture;
    p.scale_texel = e.table_scale_texel;
    if (lighting_in_texture) {
        // The lighting moves into a texture (never truncated): ES 3.00 RGBA32F, ES 1.00 RGBA8
        // with 16 bits per value (float textures are an ES 2.0 extension).
        p.lighting = p.es3() ? LightingLayout::kFloatTexture : LightingLayout::kRgba8Texture;
        ++units;
        if (k_count > lim_size) {
            throw Error(str("GLES export ", e.name, ": the lighting texture is ", k_count,
                            " texels wide, GL_MAX_TEXTURE_SIZE is ", lim_size));
        }
    }
    e.lighting_layout = p.lighting;
    const int vectors = fixed_vectors + (lighting_in_texture ? 0 : k_count) + table_vectors;
    e.fragment_uniform_vectors = vectors;
    // The material's own textures are the app's to size for its device: their size is stated
    // in gl_limits_needed, not checked against the specification minimum (64 texels in ES 2.0,
    // which no fabric texture meets and no device has).
    if (vectors > lim_vectors) {
        throw Error(str("GLES export ", e.name, ": needs ", vectors,
                        " fragment uniform vectors (",
                        p.lighting == LightingLayout::kUniformArray
                            ? str(k_count, " lighting coefficients")
                            : std::string("lighting in a texture, u_albedo"),
                        v.lights > 0 ? str(", ", 2 * v.lights, " for ", v.lights, " lights") : "",
                        table_vectors > 0 && p.layout == TableLayout::kRgba8Texture
                            ? ", the table's scale and offset"
                            : "",
                        "), GL_MAX_FRAGMENT_UNIFORM_VECTORS is ", lim_vectors,
                        "; use fewer bands or lights, or a device with more"));
    }
    if (units > limits.max_texture_image_units) {
        throw Error(str("GLES export ", e.name, ": needs ", units,
                        " texture units, GL_MAX_TEXTURE_IMAGE_UNITS is ",
                        limits.max_texture_image_units));
    }
    const std::pair<const std::vector<uint8_t>*, Eigen::Vector2i> textures[] = {
        {&mat.albedo_rgba8, mat.albedo_texture_px}, {&mat.normal_rgba8, mat.normal_texture_px}};
    for (int i = 0; i < 2; ++i) {
        const auto& [bytes, px] = textures[i];
        const char* which = i == 0 ? "albedo" : "normal";
        if (p.trilinear() && px.x() > 0) {
            // The atlas is the exporter's own texture (1.5 x the width): it must fit the device.
            (i == 0 ? p.albedo_levels : p.normal_levels) = render::mip_atlas_levels(px.x(), px.y());
            const auto& levels = i == 0 ? p.albedo_levels : p.normal_levels;
            const Eigen::Vector2i atlas = render::mip_atlas_size(levels);
            (i == 0 ? p.albedo_atlas_px : p.normal_atlas_px) = atlas;
            if (atlas.maxCoeff() > lim_size) {
                throw Error(str("GLES export ", e.name, ": the ", which, " texture's mip atlas is ", atlas.x(),
                                "x", atlas.y(), " texels (the ", px.x(), "x", px.y(),
                                " texture and its levels beside it), more than GL_MAX_TEXTURE_SIZE = ", lim_size,
                                "; give the device's limit (--gles-max-texture-size), a smaller texture or the "
                                "bilinear filter"));
            }
        }
        if (bytes->empty()) continue;
        if (bytes->size() != static_cast<size_t>(px.x()) * px.y() * 4) {
            throw UsageError(str("GLES export ", e.name, ": the ", which, " texture has ", bytes->size(),
                                 " bytes, its ", px.x(), "x", px.y(), " RGBA8 texels need ", px.x() * px.y() * 4));
        }
        const std::string file = texture_file_name(mat.name, i == 0, p.trilinear());
        if (p.trilinear()) {  // the mip atlas, the same PNG format
            const MipAtlas8 atlas = mip_atlas_rgba8(*bytes, px, i == 0);
            e.texture_files.emplace_back(file, texture_png(atlas.rgba, {atlas.width, atlas.height}, file));
        } else {
            e.texture_files.emplace_back(file, texture_png(*bytes, px, file));
        }
    }
    e.vertex_source = vertex_source(p, e.name);
    e.fragment_source = fragment_source(p, e.name);
    e.manifest = make_manifest(e, p, limits);
    return e;
}

MipAtlas8 mip_atlas_rgba8(const std::vector<uint8_t>& rgba8, const Eigen::Vector2i& size, bool srgb) {
    if (size.minCoeff() < 1 || rgba8.size() != static_cast<size_t>(size.x()) * size.y() * 4) {
        throw Error(str("mip atlas: ", rgba8.size(), " bytes are not ", size.x(), "x", size.y(), " RGBA8 texels"));
    }
    // The texture as the CPU model holds the same 8-bit file (render::load_textures).
    image::Image level0(size.x(), size.y(), 3);
    for (int y = 0; y < size.y(); ++y) {
        for (int x = 0; x < size.x(); ++x) {
            for (int c = 0; c < 3; ++c) {
                const float v = rgba8[(static_cast<size_t>(y) * size.x() + x) * 4 + c] / 255.0f;
                level0.at(x, y, c) = srgb ? image::srgb_decode(v) : v;
            }
        }
    }
    const render::MipAtlas mip = render::build_mip_atlas(
        level0, srgb ? render::TextureKind::kColor : render::TextureKind::kNormalMap, true);
    MipAtlas8 out;
    out.width = mip.atlas.width;
    out.height = mip.atlas.height;
    out.levels = mip.levels;
    out.rgba.assign(static_cast<size_t>(out.width) * out.height * 4, 0);
    for (size_t i = 3; i < out.rgba.size(); i += 4) out.rgba[i] = 255;  // padding (0, 0, 0, 255)
    for (size_t k = 0; k < mip.levels.size(); ++k) {
        const render::MipRect& r = mip.levels[k];
        for (int y = 0; y < r.height; ++y) {
            for (int x = 0; x < r.width; ++x) {
                uint8_t* t = &out.rgba[(static_cast<size_t>(r.y + y) * out.width + r.x + x) * 4];
                for (int c = 0; c < 3; ++c) {
                    if (k == 0) {  // the bytes themselves
                        t[c] = rgba8[(static_cast<size_t>(y) * size.x() + x) * 4 + c];
                        continue;
                    }
                    // Levels >= 1 hold quantised values: their code back, exactly.
                    const float v = mip.atlas.at(r.x + x, r.y + y, c);
                    const float e = srgb ? image::srgb_encode(v) : v;
                    t[c] = static_cast<uint8_t>(std::clamp(std::lround(e * 255.0f), 0L, 255L));
                }
            }
        }
    }
    return out;
}

namespace {
/// float32 in 4 bytes as the shaders' unpack_f32 reads it (BoundLighting).
void pack_f32(float v, uint8_t* out) {
    int e = 0;
    const float m = std::frexp(std::abs(v), &e);  // |v| = m 2^e, m in [0.5, 1)
    if (v == 0.0f || e + 127 < 1) {
        out[0] = out[1] = out[2] = out[3] = 0;
        return;
    }
    const auto mant = static_cast<uint32_t>(std::ldexp(m, 24));  // exact: 24 bits
    out[0] = static_cast<uint8_t>(e + 127);
    out[1] = static_cast<uint8_t>(((mant >> 16) & 0x7f) | (v < 0 ? 0x80 : 0));
    out[2] = static_cast<uint8_t>((mant >> 8) & 0xff);
    out[3] = static_cast<uint8_t>(mant & 0xff);
}
}  // namespace

BoundLighting bind_lighting(const Export& e, const Eigen::MatrixXd& sh) {
    const int k_count = sh::count(e.manifest["variant"]["sh_bands"].get<int>());
    if (e.lighting_layout == LightingLayout::kUniformArray) {
        throw Error(str("GLES variant ", e.name, ": its lighting is in uniforms, not a texture"));
    }
    if (sh.rows() < k_count || sh.cols() != 3 || !sh.topRows(k_count).allFinite()) {
        throw Error(str("GLES variant ", e.name, ": needs ", k_count,
                        "x3 finite lighting coefficients"));
    }
    BoundLighting b;
    b.width = k_count;
    b.as_bound = Eigen::MatrixXd(k_count, 3);
    if (e.lighting_layout == LightingLayout::kFloatTexture) {
        b.height = 1;
        for (int k = 0; k < k_count; ++k) {
            for (int c = 0; c < 3; ++c) {
                b.texels.push_back(static_cast<float>(sh(k, c)));
                b.as_bound(k, c) = b.texels.back();
            }
            b.texels.push_back(0.0f);
        }
        return b;
    }
    b.height = 4;
    b.bytes.assign(static_cast<size_t>(k_count) * 4 * 4, 0);
    auto texel = [&](int k, int row) { return &b.bytes[(static_cast<size_t>(row) * k_count + k) * 4]; };
    for (int k = 0; k < k_count; ++k) {
        const float offset = static_cast<float>(sh.row(k).minCoeff());
        const float scale = static_cast<float>(sh.row(k).maxCoeff() - offset);
        pack_f32(scale, texel(k, 2));
        pack_f32(offset, texel(k, 3));
        b.max_abs_error = std::max(b.max_abs_error, scale / 131070.0);
        for (int c = 0; c < 3; ++c) {
            const long q = scale > 0 ? std::clamp(std::lround((sh(k, c) - offset) / scale * 65535.0), 0L, 65535L) : 0L;
            texel(k, 0)[c] = static_cast<uint8_t>(q >> 8);
            texel(k, 1)[c] = static_cast<uint8_t>(q & 0xff);
            // As the shader computes it, in float.
            b.as_bound(k, c) = offset + scale * (static_cast<float>(q) / 65535.0f);
        }
    }
    return b;
}


brdf::Table table_shape(const brdf::Material& material, const brdf::Grid& grid, int sh_bands) {
    brdf::Table t;
    t.grid = grid;
    t.sh_bands = sh_bands;
    t.channels = brdf::baked_lobe_is_achromatic(material) ? 1 : 3;
    t.resize();
    return t;
}

Limits export_limits(const ExportSet& set, GlslVersion version) {
    Limits l = Limits::minimum(version);
    if (set.max_texture_size == 0) return l;
    if (set.max_texture_size < l.max_texture_size) {
        throw UsageError(str("GL_MAX_TEXTURE_SIZE ", set.max_texture_size, " is below the ",
                             version == GlslVersion::kEs100 ? "OpenGL ES 2.0" : "OpenGL ES 3.0",
                             " minimum ", l.max_texture_size, " (GLSL ES ", to_string(version),
                             " variants)"));
    }
    l.max_texture_size = set.max_texture_size;
    return l;
}

std::vector<Export> export_material(const brdf::Table* table, const MaterialInputs& material,
                                    const ExportSet& set) {
    std::vector<Export> out;
    for (GlslVersion version : set.versions) {
        for (ShaderMode mode : set.modes) {
            const int last = mode == ShaderMode::kSeed ? 3 : set.max_sh_bands;
            for (int bands = 3; bands <= last; ++bands) {
                const int lights =
                    mode == ShaderMode::kSeed ? 0 : static_cast<int>(set.lights.size());
                for (Precision precision : set.precisions) {
                    Export e = export_variant(table, material,
                                              {version, mode, bands, precision, lights,
                                               common_light_shading(set.lights), set.texture_filter},
                                              export_limits(set, version));
                    if (lights > 0) {  // the values the app binds for these lights
                        const LightUniformArrays a = light_uniform_arrays(set.lights);
                        for (auto& u : e.manifest["uniforms"]) {
                            if (u["name"] == "u_light_direction") u["value"] = a.direction_sin;
                            if (u["name"] == "u_light_irradiance") u["value"] = a.normal_irradiance;
                        }
                    }
                    out.push_back(std::move(e));
                }
            }
        }
    }
    return out;
}

std::vector<std::string> write_exports(const std::string& dir, const std::vector<Export>& exports) {
    std::vector<std::string> paths;
    nlohmann::json index = {{"format", "inlight_gles_export_index"}, {"version", 1}};
    index["variants"] = nlohmann::json::array();
    for (const Export& e : exports) {
        const auto files = export_files(e);
        for (const auto& t : e.manifest["textures"]) {  // every texture's file is written
            if (!t.contains("file") || t["file"].is_null()) continue;
            const std::string file = t["file"];
            if (std::none_of(files.begin(), files.end(), [&](const auto& f) { return f.first == file; })) {
                throw Error(str("GLES export ", e.name, ": ", t["uniform"].get<std::string>(), "'s file ",
                                file, " has no bytes (MaterialInputs' RGBA8 texels)"));
            }
        }
        for (const auto& [name, bytes] : files) {
            const std::string path = dir + "/" + name;
            // A material's texture files are shared by its variants: written once.
            if (std::find(paths.begin(), paths.end(), path) != paths.end()) continue;
            paths.push_back(path);
            fs::write_text_atomic(paths.back(), bytes);
        }
        index["variants"].push_back({{"name", e.name},
                                     {"manifest", e.name + ".json"},
                                     {"variant", e.manifest["variant"]},
                                     {"table_layout", to_string(e.table_layout)},
                                     {"gl_limits_needed", e.manifest["gl_limits_needed"]}});
    }
    index["load"] = load_choices(exports);
    paths.push_back(dir + "/index.json");
    fs::write_text_atomic(paths.back(), dump_finite(index, 2, paths.back()));
    return paths;
}

std::vector<std::pair<std::string, std::string>> export_files(const Export& e) {
    std::vector<std::pair<std::string, std::string>> files;
    files.emplace_back(e.name + ".vert", e.vertex_source);
    files.emplace_back(e.name + ".frag", e.fragment_source);
    files.emplace_back(e.name + ".json", dump_finite(e.manifest, 2, e.name + ".json"));
    if (e.table_layout == TableLayout::kRgba8Texture) {
        files.emplace_back(e.name + ".brdf.bin",
                           std::string(e.table_bytes.begin(), e.table_bytes.end()));
    } else if (e.table_layout != TableLayout::kNone) {
        // Little-endian float32, as brdf/table.h's binary (the build targets are little-endian).
        std::string bytes(e.table_texels.size() * sizeof(float), '\0');
        std::memcpy(bytes.data(), e.table_texels.data(), bytes.size());
        files.emplace_back(e.name + ".brdf.bin", std::move(bytes));
    }
    for (const auto& f : e.texture_files) files.push_back(f);
    return files;
}

}  // namespace inlight::gles
