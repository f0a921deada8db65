// gles/btf_export.cpp: the BTF export's atlases, matrices, shaders and manifest
// (gles/btf_export.h, docs/btf-gles.md).
#include "gles/btf_export.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "btf/sh_lighting.h"
#include "core/check.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/json_out.h"
#include "gles/export_glsl.h"
#include "image/image.h"
#include "render/btf_shade.h"
#include "sh/sh.h"

namespace inlight::gles {

namespace {

constexpr int kSlots = 3;              // groups drawn at once: the 3 nearest views' groups
constexpr int kVectorsPerSlab = 3;     // per slot: the 3 colours' weights (the decode folded in)
constexpr const char* kManifest = "btf-gles.json";
constexpr const char* kMatrices = "lighting-matrices.bin";

std::string atlas_file(int g) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "g%03d-atlas.png", g);
    return buf;
}

/// The 8-bit codes of one stored column (code = round(255 x stored), stored = code / 255).
std::vector<uint8_t> read_codes(const std::string& dir, const nlohmann::json& meta, int w, int h) {
    const std::string file = meta.at("file").get<std::string>();
    const std::string path = dir + "/" + file;
    if (file.size() < 4 || file.substr(file.size() - 4) != ".png")
        throw Error(str(path, ": the GLES export needs 8-bit PNG components (btf-pca --format png)"));
    const image::Image img = image::read_image(path, {false});
    if (img.width != w || img.height != h || img.channels != 1)
        throw Error(str(path, ": expected a ", w, "x", h, " one-channel image"));
    std::vector<uint8_t> codes(img.pixels.size());
    for (size_t i = 0; i < codes.size(); ++i) {
        const float c = std::round(img.pixels[i] * 255.0f);
        if (!(c >= 0 && c <= 255) || std::abs(c - img.pixels[i] * 255.0f) > 1e-3f)
            throw Error(str(path, ": not an 8-bit image (sample ", i, " is ", img.pixels[i] * 255.0f, "/255)"));
        codes[i] = static_cast<uint8_t>(c);
    }
    return codes;
}

std::string vertex_source(bool es3) {
    std::ostringstream s;
    s << (es3 ? "#version 300 es\n" : "#version 100\n")
      << "// inlight BTF export: passes the texture coordinate (docs/btf-gles.md).\n"
      << "uniform highp mat4 u_clip_from_object;\nuniform highp vec2 u_uv_scale;\n"
      << (es3 ? "in" : "attribute") << " highp vec3 a_position;\n"
      << (es3 ? "in" : "attribute") << " highp vec2 a_uv;\n"
      << (es3 ? "out" : "varying") << " highp vec2 v_uv;\n"
      << "void main() {\n  v_uv = a_uv * u_uv_scale;\n"
      << "  gl_Position = u_clip_from_object * vec4(a_position, 1.0);\n}\n";
    return s.str();
}

/// The fragment shader, unrolled with literal indices (GLSL ES 1.00 fragment shaders index
/// uniform arrays only with constant-index expressions).
std::string fragment_source(bool es3, int w, int h, int slabs, int used) {
    std::ostringstream s;
    s << (es3 ? "#version 300 es\n" : "#version 100\n")
      << "// inlight BTF export (docs/btf-gles.md): per slot g (the 3 nearest views' groups) and\n"
      << "// slab s, t = the atlas texel (RGBA8 code / 255, nearest, UV wrapped), radiance_ch =\n"
      << "// u_bias[ch] + sum of dot(t, u_weight[(g * 3 + ch) * S + s]) (the folder's decode, offset +\n"
      << "// scale x t, folded into the weights and the bias by the app each frame).\n"
      << "precision highp float;\n";
    if (es3) s << "precision highp int;\n";
    for (int g = 0; g < kSlots; ++g) s << "uniform highp sampler2D u_group" << g << ";  // highp: the default lowp result loses codes\n";
    const int n = kSlots * used;
    s << "uniform vec4 u_weight[" << 3 * n << "];\nuniform vec4 u_bias;\n"
      << (es3 ? "in" : "varying") << " highp vec2 v_uv;\n";
    if (es3) s << "layout(location = 0) out vec4 o_radiance;\n";
    s << "void main() {\n  vec2 f = fract(v_uv);\n"
      << "  vec2 texel = min(floor(f * vec2(" << w << ".0, " << h << ".0)), vec2(" << w - 1 << ".0, " << h - 1
      << ".0));\n  vec3 sum = u_bias.rgb;\n  vec4 t;\n";
    for (int g = 0; g < kSlots; ++g) {
        for (int sl = 0; sl < used; ++sl) {
            if (es3) {
                s << "  t = texelFetch(u_group" << g << ", ivec2(texel) + ivec2(0, " << sl * h << "), 0);\n";
            } else {
                s << "  t = texture2D(u_group" << g << ", vec2((texel.x + 0.5) / " << w << ".0, (texel.y + "
                  << sl * h << ".5) / " << h * slabs << ".0));\n";
            }
            s << "  sum += vec3(dot(t, u_weight[" << (g * 3) * used + sl << "]), dot(t, u_weight["
              << (g * 3 + 1) * used + sl << "]), dot(t, u_weight[" << (g * 3 + 2) * used + sl << "]));\n";
        }
    }
    s << "  " << (es3 ? "o_radiance" : "gl_FragColor") << " = vec4(sum, 1.0);\n}\n";
    return s.str();
}

void append_floats_le(std::string& out, const std::vector<float>& v) {
    for (float f : v) {
        uint32_t u;
        std::memcpy(&u, &f, 4);
        for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((u >> (8 * b)) & 0xff));
    }
}

/// How the manifest tells an app to spread a point light over the light directions, per rule
/// (btf::PointLightWeights is the implementation it describes).
std::string light_rule_text(btf::CellRule rule) {
    const std::string head = btf::to_string(rule) + ": a point light of flux Phi_i from unit d (fabric frame) ";
    const std::string below = "; one at or below the sample's plane (d_z <= 0) adds nothing (btf/lighting.h)";
    switch (rule) {
        case btf::CellRule::kCosine:
            return head + "above the sample's plane adds Phi_i d_z / k_z to the weight W_k of the light direction k "
                          "nearest d by angle among those more than 0.5 deg above the horizon" + below;
        case btf::CellRule::kConstant:
            return head + "adds Phi_i to the weight of the light direction nearest d by angle" + below;
        case btf::CellRule::kBarycentric:
        case btf::CellRule::kCosineBarycentric:
            return head + "lies in a triangle (a, b, c) of triangulation.triangles whose w = (d.(b x c), "
                          "a.(d x c), a.(b x d)) are all >= -1e-12 (on a shared edge either gives the same weights); "
                          "vertex i of it adds Phi_i beta_i" +
                   (rule == btf::CellRule::kCosineBarycentric ? std::string(" d_z / k_z") : std::string()) +
                   " to the weight of light direction k = triangulation.owner[i] (none when -1), beta_i = max(0, "
                   "w_i) / sum of max(0, w)" + below;
        case btf::CellRule::kExtrapolated:
            return head + "as cosine, and beyond an outer light k also as btf/lighting.h's extrapolated rule" + below;
    }
    return head;
}

}  // namespace

BtfGlesExport export_btf_gles(const std::string& dir, const BtfGlesOptions& given) {
    if (given.sh_bands < 1 || given.sh_bands > 9) throw UsageError(str("--bands must be in 1..9, got ", given.sh_bands));
    if (!(given.irradiance_w_m2 >= 0) || !std::isfinite(given.irradiance_w_m2))
        throw UsageError("--irradiance-w-m2 must be finite and > 0");
    const auto btf = btf::CompressedBtf::open(dir);
    const std::string manifest_path = dir + "/btf-pca.json";
    // E: given, else the folder's (btf-pca records a capture's), else 1.
    BtfGlesOptions o = given;
    if (o.irradiance_w_m2 == 0) {
        const nlohmann::json& pm = btf->manifest();
        o.irradiance_w_m2 = 1;
        if (pm.contains("irradiance_w_m2")) {
            const nlohmann::json& v = pm.at("irradiance_w_m2");
            if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() > 0))
                throw Error(str(manifest_path, ": irradiance_w_m2 must be a finite number > 0"));
            o.irradiance_w_m2 = v.get<double>();
        }
    }
    if (btf->fit_space() != btf::FitSpace::kLinear)
        throw Error(str(manifest_path, ": fit space '", btf::to_string(btf->fit_space()),
                        "': the GLES export folds lighting into component weights, which only the linear "
                        "fit space allows (compress with --fit-space linear)"));
    const nlohmann::json& m = btf->manifest();
    BtfGlesExport e;
    e.atlas_files = o.write_atlases;
    e.width = btf->shape().width;
    e.height = btf->shape().height;
    e.sh_bands = o.sh_bands;
    e.views = btf->shape().views;
    const int groups = static_cast<int>(m.at("groups").size());
    int max_c = 0;
    for (int g = 0; g < groups; ++g) {
        e.components.push_back(btf->components(g));
        max_c = std::max(max_c, e.components.back());
    }
    e.slabs = (1 + max_c + 3) / 4;
    for (const auto& sj : m.at("stream")) e.stream.emplace_back(sj.at(0).get<int>(), sj.at(1).get<int>());

    // Atlases: slab s = columns 4s .. 4s + 3 of [mean | components], stacked top to bottom.
    const size_t px = static_cast<size_t>(e.width) * e.height;
    std::vector<std::vector<std::string>> sources;  // per group and channel: the column's PNG ("" unused)
    for (int g = 0; g < groups; ++g) {
        const nlohmann::json& gj = m.at("groups")[static_cast<size_t>(g)];
        Texture8 atlas;
        atlas.width = e.width;
        atlas.height = e.height * e.slabs;
        atlas.rgba.assign(px * e.slabs * 4, 0);
        std::vector<float> scale(static_cast<size_t>(e.slabs) * 4, 0.f), offset(scale.size(), 0.f);
        std::vector<std::string> source(scale.size());
        for (int k = 0; k <= e.components[static_cast<size_t>(g)]; ++k) {
            const nlohmann::json& meta = k == 0 ? gj.at("mean") : gj.at("components")[static_cast<size_t>(k - 1)];
            const std::vector<uint8_t> codes = read_codes(dir, meta, e.width, e.height);
            source[static_cast<size_t>(k)] = meta.at("file").get<std::string>();
            // The decoder multiplies scale by stored = code / 255 (btf/compressed.cpp read_column).
            scale[static_cast<size_t>(k)] = meta.at("scale").get<float>();
            offset[static_cast<size_t>(k)] = meta.at("offset").get<float>();
            const size_t base = static_cast<size_t>(k / 4) * px * 4;
            for (size_t p = 0; p < px; ++p) atlas.rgba[base + p * 4 + static_cast<size_t>(k % 4)] = codes[p];
        }
        e.atlases.push_back(std::move(atlas));
        e.scale.push_back(std::move(scale));
        e.offset.push_back(std::move(offset));
        sources.push_back(std::move(source));
    }

    // M_v,ch for every view: the app's per-frame fold (CompressedBtf::lighting_matrix).
    const Eigen::MatrixXd a = btf::sh_light_weight_matrix(btf->shape().lights, o.sh_bands, o.lighting, o.map_height);
    const int j_count = sh::count(o.sh_bands);
    for (int v = 0; v < btf->shape().n_views(); ++v) {
        e.matrices_offset.push_back(static_cast<int64_t>(e.matrices.size()));
        for (int ch = 0; ch < 3; ++ch) {
            const Eigen::MatrixXd mv = btf->lighting_matrix(v, ch, a, o.irradiance_w_m2);
            for (Eigen::Index r = 0; r < mv.rows(); ++r) {
                for (int j = 0; j < j_count; ++j) e.matrices.push_back(static_cast<float>(mv(r, j)));
            }
        }
    }

    // [1^T; V_v,ch^T] / E per view: what a dominant light's weights at the light directions
    // fold through (lighting_matrix with A = identity).
    const int k_count = btf->shape().n_lights();
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(k_count, k_count);
    for (int v = 0; v < btf->shape().n_views(); ++v) {
        e.light_rows_offset.push_back(static_cast<int64_t>(e.light_rows.size()));
        for (int ch = 0; ch < 3; ++ch) {
            const Eigen::MatrixXd rows = btf->lighting_matrix(v, ch, identity, o.irradiance_w_m2);
            for (Eigen::Index r = 0; r < rows.rows(); ++r)
                for (int k = 0; k < k_count; ++k) e.light_rows.push_back(static_cast<float>(rows(r, k)));
        }
    }
    e.lights = btf->shape().lights;
    e.lighting = o.lighting;
    e.light_spread = std::make_shared<const btf::PointLightWeights>(e.lights, e.lighting);

    // Variants against their versions' guaranteed limits.
    nlohmann::json variants = nlohmann::json::array();
    for (GlslVersion ver : o.versions) {
        const bool es3 = ver == GlslVersion::kEs300;
        const Limits lim = Limits::minimum(ver);
        BtfGlesVariant var;
        var.version = ver;
        var.name = es3 ? "btf-es300-highp" : "btf-es100-highp";
        // Every variant reads every slab: 9 S + 1 vectors (u_weight, u_bias). ES 3.0 guarantees
        // 224 (S <= 24) and runs ES 1.00 shaders too, so that is the bound for both; ES 2.0
        // guarantees only 16 (S = 1) and devices report more (the load table's requires).
        const int es3_vectors = Limits::minimum(GlslVersion::kEs300).max_fragment_uniform_vectors;
        const int fit = (es3_vectors - 1) / (kSlots * kVectorsPerSlab);
        if (e.slabs > fit)
            throw Error(str(manifest_path, ": ", max_c, " components need ",
                            btf_fragment_uniform_vectors(e.slabs), " fragment uniform vectors, OpenGL ES 3.0 guarantees ",
                            es3_vectors, " (at most ", fit * 4 - 1, " components)"));
        var.slabs_used = e.slabs;
        var.fragment_uniform_vectors = btf_fragment_uniform_vectors(var.slabs_used);
        const int side = std::max(e.width, e.height * e.slabs);
        var.vertex_source = vertex_source(es3);
        var.fragment_source = fragment_source(es3, e.width, e.height, e.slabs, var.slabs_used);
        nlohmann::json tex = nlohmann::json::array();
        for (int g = 0; g < kSlots; ++g) {
            tex.push_back({{"uniform", str("u_group", g)}, {"unit", g},
                           {"file", "the atlas of the group slot " + std::to_string(g) +
                                        " shows this frame (textures.groups[g]: its file, or assembled)"}});
        }
        nlohmann::json vm = {
            {"name", var.name},
            {"vertex_shader", var.name + ".vert"},
            {"fragment_shader", var.name + ".frag"},
            {"glsl_version", es3 ? "300 es" : "100"},
            {"precision", "highp"},
            {"slabs_read", var.slabs_used},
            {"max_components_per_group", var.slabs_used * 4 - 1},
            {"texel_fetches_per_pixel", kSlots * var.slabs_used},
            {"multiply_adds_per_pixel", kSlots * var.slabs_used * 3 * 4},
            {"gl_limits_needed",
             {{"context", es3 ? "OpenGL ES 3.0" : "OpenGL ES 2.0"},
              {"max_fragment_uniform_vectors", var.fragment_uniform_vectors},
              {"max_fragment_uniform_vectors_guaranteed", lim.max_fragment_uniform_vectors},
              {"max_texture_image_units", kSlots},
              {"max_texture_size", side},
              {"max_texture_size_guaranteed", lim.max_texture_size},
              {"requires", es3 ? nlohmann::json::array()
                               : nlohmann::json::array({"GL_FRAGMENT_PRECISION_HIGH (highp in fragment shaders)"})}}}};
        std::vector<std::string> notes;
        if (var.fragment_uniform_vectors > lim.max_fragment_uniform_vectors)
            notes.push_back(str(var.fragment_uniform_vectors, " fragment uniform vectors (", e.slabs,
                                " slabs x 3 slots x 3 colours + u_bias), above the ", lim.max_fragment_uniform_vectors,
                                " every device guarantees: check GL_MAX_FRAGMENT_UNIFORM_VECTORS"));
        if (side > lim.max_texture_size)
            notes.push_back(str("the atlases are ", side, " texels on a side, above the ", lim.max_texture_size,
                                " every device guarantees: check GL_MAX_TEXTURE_SIZE"));
        if (!notes.empty()) {
            std::string joined;
            for (const std::string& n : notes) joined += (joined.empty() ? "" : "; ") + n;
            vm["gl_limits_needed"]["note"] = joined;
        }
        variants.push_back(vm);
        var.as_export.name = var.name;
        var.as_export.variant.version = ver;
        var.as_export.vertex_source = var.vertex_source;
        var.as_export.fragment_source = var.fragment_source;
        var.as_export.fragment_uniform_vectors = var.fragment_uniform_vectors;
        var.as_export.manifest = {{"variant", {{"glsl_version", es3 ? "300 es" : "100"}, {"sh_bands", o.sh_bands}}},
                                  {"textures", tex}};
        e.variants.push_back(std::move(var));
    }

    // The manifest.
    nlohmann::json groups_j = nlohmann::json::array();
    for (int g = 0; g < groups; ++g) {
        nlohmann::json channels = nlohmann::json::array();
        for (int k = 0; k < e.slabs * 4; ++k) {
            const std::string& src = sources[size_t(g)][size_t(k)];
            channels.push_back({{"column", k == 0 ? "mean" : (k <= e.components[size_t(g)] ? str("component ", k - 1) : "unused")},
                                {"file", src.empty() ? nlohmann::json() : nlohmann::json(src)},
                                {"scale", e.scale[size_t(g)][size_t(k)]}, {"offset", e.offset[size_t(g)][size_t(k)]}});
        }
        groups_j.push_back({{"file", e.atlas_files ? nlohmann::json(atlas_file(g)) : nlohmann::json()},
                            {"components", e.components[size_t(g)]}, {"channels", channels}});
    }
    nlohmann::json views_j = nlohmann::json::array();
    for (int v = 0; v < btf->shape().n_views(); ++v) {
        const int g = btf->group_of_view(v);
        views_j.push_back({{"theta_deg", e.views[size_t(v)].theta_deg}, {"phi_deg", e.views[size_t(v)].phi_deg},
                           {"group", g}, {"rows", 1 + e.components[size_t(g)]},
                           {"offset_bytes", e.matrices_offset[size_t(v)] * 4}});
    }
    nlohmann::json stream = nlohmann::json::array();
    for (const auto& [g, c] : e.stream) stream.push_back({g, c});
    const int64_t tex_bytes = static_cast<int64_t>(groups) * e.width * e.height * e.slabs * 4;
    e.manifest = {
        {"format", "inlight_btf_gles_export"},
        {"version", 1},
        {"source", {{"format", "inlight-btf-pca"}, {"color_space", "linear_srgb"}}},
        {"image", {{"width", e.width}, {"height", e.height}}},
        {"frames",
         {{"fabric", "x = the texture's +u direction, z = the fabric's normal (the BTF's sample frame: its views' "
                     "theta and phi, btf-pca.json)"},
          {"lighting", "c = the lighting file's coefficients (docs/formats.md; sh/sh.h order, no Condon-Shortley "
                       "phase) rotated into the fabric frame: the rotation the BRDF shaders' u_sh gets for the "
                       "device (docs/gles.md) composed with the fabric's orientation in the device frame"}}},
        {"variants", variants},
        {"textures",
         {{"groups", groups_j},
          {"layout", str("per view group one RGBA8 atlas, ", e.width, " x ", e.height * e.slabs, " texels: ", e.slabs,
                         " slabs of ", e.width, " x ", e.height, " stacked top to bottom; slab s channel k (r, g, b, "
                         "a) = column 4 s + k of [mean | components] (8-bit code)")},
          {"atlas_files", e.atlas_files},
          {"assembly",
           str(e.atlas_files ? "the atlases are written (groups[g].file); they equal this assembly: "
                             : "no atlas files (groups[g].file null): the app assembles each group's atlas from the "
                               "btf-pca folder's PNGs (in a fabric bundle: beside this file): ",
               "channel k (r, g, b, a = 0..3) of slab s (rows s x ", e.height, " .. (s + 1) x ", e.height,
               " - 1) of group g's atlas = the 8-bit code of groups[g].channels[4 s + k].file at the same pixel "
               "(the PNG decoded without gamma or colour management, rows top first), code 0 where that file is "
               "null (unused) or has not arrived")},
          {"encoding", "PNG, 8-bit RGBA, rows top first, decoded without gamma or colour management (the texel "
                       "bytes glTexImage2D takes, GL_RGBA / GL_UNSIGNED_BYTE)"},
          {"decode", "value = offset + scale x code / 255 per channel (the folder's own decode; unused channels "
                     "scale 0, offset 0)"},
          {"sampling", "GL_NEAREST, GL_CLAMP_TO_EDGE, no mipmaps; the shader wraps UV (fract) and picks the texel "
                       "floor(fract(uv) x (width, height)), v = 0 at the image's top row: nearest-texel sampling"},
          {"units", "u_group0, u_group1, u_group2 on texture units 0, 1, 2: the atlases of the frame's 3 group "
                    "slots; an unused slot (the blend touches fewer groups) binds slot 0's atlas (its weights are 0)"},
          {"streaming", "an atlas is uploaded when its group's mean arrives, with code 0 in channels whose "
                        "component has not arrived (their weight is 0), and updated with glTexSubImage2D as they do"},
          {"bytes_per_group", static_cast<int64_t>(e.width) * e.height * e.slabs * 4},
          {"bytes_total", tex_bytes}}},
        {"uniforms",
         {{"u_clip_from_object", "mat4: clip from object (vertex stage)"},
          {"u_uv_scale", "vec2: texture repeats per UV unit (vertex stage)"},
          {"u_weight", "vec4[9 S] (S = the variant's slabs_read): index (slot x 3 + ch) x S + s, channel k = "
                       "scale_4s+k x w_slot,ch[4 s + k] (scale: the slot's group's textures.groups[g].channels[4 s + "
                       "k].scale; 0 when that column has not arrived or is unused)"},
          {"u_bias", "vec4: (b_r, b_g, b_b, 0), b_ch = sum over slots and columns k of offset_k x w_slot,ch[k] (offset: "
                     "the slot's group's channels[k].offset; the columns that have arrived)"}}},
        {"weights",
         {{"per_frame", "blend = the 3 views nearest the view direction (fabric frame) by angle, alpha_v = (1 / angle_v) "
                        "/ sum (1 / angle); a view within 1e-9 degrees of a measured one takes it alone (alpha 1). "
                        "Slots: the distinct groups of the blend's views in blend order. w_slot,ch = sum over the "
                        "blend's views v in the slot's group of alpha_v M_v,ch c_ch (M_v,ch: (1 + C) x bands^2, "
                        "c_ch: the lighting's channel ch, bands^2 values); then row 0 weighs the mean, row 1 + i "
                        "component i"},
          {"neighbours", 3},
          {"weights_rule", "inverse angle (render::select_views)"},
          {"streaming", "with the first N entries of \"stream\" arrived, group g's components with index below the "
                        "number of entries naming g get their weight; the others 0 (the mean always)"},
          {"stream", stream}}},
        {"matrices",
         {{"file", kMatrices},
          {"dtype", "float32_le"},
          {"bands", o.sh_bands},
          {"columns", j_count},
          {"layout", "per view (views[v].offset_bytes), channel ch = 0, 1, 2, row r = 0 .. rows - 1, column j: "
                     "M_v,ch(r, j) at offset_bytes + 4 ((ch x rows + r) x columns + j)"},
          {"formula", "M_v,ch = [1^T; V_v,ch^T] A / E (btf/compressed.h lighting_matrix): A(k, j) = the light "
                      "weight of light k for SH basis function j (btf/sh_lighting.h, cell rule " +
                          btf::to_string(o.lighting.rule) + ", quadrature " + std::to_string(o.map_height) + ")"},
          {"irradiance_w_m2", o.irradiance_w_m2},
          {"bytes", static_cast<int64_t>(e.matrices.size()) * 4}}},
        {"views", views_j},
        {"output",
         {{"variable", "o_radiance (300 es) / gl_FragColor (100)"},
          {"quantity", "radiance (rgb; alpha 1)"},
          {"color_space", "linear_srgb"},
          {"clamped", false},
          {"units", "the lighting's radiance units (c)"},
          {"framebuffer", "RGBA32F (EXT_color_buffer_float) keeps HDR radiance; an 8-bit target clamps to [0, 1]"},
          {"encoding_8bit", detail::output_encoding_8bit()}}},
        {"precision",
         {{"declared", "highp"},
          {"mediump", "refused: a 10-bit mantissa on 3 x (1 + C) decoded terms of either sign, often 10 times the "
                      "pixel's value, bounds the error by 3 (1 + C) x 2^-11 x the terms' size, above one 8-bit code "
                      "(docs/btf-gles.md, \"Precision\")"}}},
        {"not_done", {"no filtering (nearest texel, no mipmaps)"}}};
    // Dominant lights: folded on the CPU through V (weights.bin), the shader unchanged.
    const bool triangulated =
        o.lighting.rule == btf::CellRule::kCosineBarycentric || o.lighting.rule == btf::CellRule::kBarycentric;
    e.manifest["lights"] = {
        {"input", "optional per frame: envmap-project's dominant lights (docs/formats.md: direction, flux Phi = "
                  "radiance x solid angle per colour, angular radius alpha), rotated into the fabric frame as c is"},
        {"spread", str("a light is ", kBtfCapSamples, " point lights of Phi / ", kBtfCapSamples,
                       " at Fibonacci points of equal solid angle on its cap: z_i = 1 - (1 - cos alpha) (i + 0.5) / ",
                       kBtfCapSamples, ", phi_i = i pi (3 - sqrt 5), turned from +z onto the light's direction by the "
                       "shortest rotation (a light of alpha 0 is one point light of Phi)")},
        {"cell_rule", light_rule_text(o.lighting.rule)},
        {"fold", "w_slot,ch += sum over the blend's views v in the slot's group of alpha_v [1^T; V_v,ch^T] W_ch / E "
                 "(rows as the matrices'): row 0 sum_k W_k,ch / E, row 1 + i sum_k V_v,ch(k, i) W_k,ch / E, with "
                 "V_v,ch(k, i) = row (index of v in its group x K + k) x 3 + ch, column i, of the group's V in "
                 "btf-pca.json's weights file (docs/btf.md, \"Storage and streaming\"), E = matrices.irradiance_w_m2"},
        {"cost_per_frame", str(kBtfCapSamples, " point lookups per light with a radius (1 for a point light): ",
                               triangulated ? "a triangle look-up each (walk from the previous point's triangle "
                                              "across the edge facing the point: a step or two for a cap)"
                                            : "K angle comparisons each",
                               ", then 3 colours x (1 + C) multiply-adds per lit light direction per blend view")}};
    if (triangulated) {
        const btf::LightTriangulation t = btf::light_triangulation(e.lights, o.lighting.rule);
        nlohmann::json vertices = nlohmann::json::array(), triangles = nlohmann::json::array();
        for (const Eigen::Vector3d& v : t.vertices) vertices.push_back({v.x(), v.y(), v.z()});
        for (const auto& tri : t.triangles) triangles.push_back({tri[0], tri[1], tri[2]});
        e.manifest["lights"]["triangulation"] = {
            {"vertices", vertices},
            {"owner", t.owner},
            {"triangles", triangles},
            {"layout", "vertices: unit vectors in the fabric frame, the K light directions in the manifest's order "
                       "and then horizon points; owner[i]: the light direction vertex i passes its weight to (-1: "
                       "none); triangles: vertex indices"}};
    }
    e.manifest["load"] = btf_load_choices(e);
    return e;
}

std::vector<std::pair<std::string, std::string>> BtfGlesExport::files() const {
    std::vector<std::pair<std::string, std::string>> out;
    out.emplace_back(kManifest, dump_finite(manifest, 2, kManifest) + "\n");
    for (const BtfGlesVariant& v : variants) {
        out.emplace_back(v.name + ".vert", v.vertex_source);
        out.emplace_back(v.name + ".frag", v.fragment_source);
    }
    for (size_t g = 0; atlas_files && g < atlases.size(); ++g) {
        const Texture8& t = atlases[g];
        image::Image img(t.width, t.height, 4);
        for (size_t i = 0; i < t.rgba.size(); ++i) img.pixels[i] = t.rgba[i] / 255.0f;
        image::WriteOptions wo;
        wo.encode_srgb = false;
        out.emplace_back(atlas_file(static_cast<int>(g)), image::encode_image(atlas_file(static_cast<int>(g)), img, wo));
    }
    std::string bin;
    append_floats_le(bin, matrices);
    out.emplace_back(kMatrices, bin);
    return out;
}

std::vector<Eigen::Vector3d> btf_light_weights(const BtfGlesExport& e, const std::vector<BtfLight>& lights) {
    std::vector<Eigen::Vector3d> out(e.lights.size(), Eigen::Vector3d::Zero());
    if (lights.empty()) return out;
    INLIGHT_CHECK(e.light_spread) << "an export not made by export_btf_gles";
    const btf::PointLightWeights& spread = *e.light_spread;
    size_t hint = 0;  // a cap's points are neighbours: each search starts at the last triangle
    for (const BtfLight& l : lights) {
        if (!l.irradiance_w_m2.allFinite()) throw Error("BTF GLES frame: a light's irradiance holds NaN or Inf");
        if (!(l.angular_radius >= 0 && l.angular_radius < kPi / 2))
            throw Error("BTF GLES frame: a light's angular radius must be in [0, pi/2)");
        if (!l.direction.allFinite() || std::abs(l.direction.norm() - 1) > 1e-6)
            throw Error("BTF GLES frame: a light's direction is not a finite unit vector");
        // The cap as equal point lights at Fibonacci points of equal solid angle around +z,
        // turned onto the light's direction (one point for a point light).
        const int n = l.angular_radius > 0 ? kBtfCapSamples : 1;
        const Eigen::Matrix3d turn =
            Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), l.direction).toRotationMatrix();
        const double golden = kPi * (3 - std::sqrt(5.0));
        for (int i = 0; i < n; ++i) {
            const double z = 1 - (1 - std::cos(l.angular_radius)) * (i + 0.5) / n;
            const double r = std::sqrt(std::max(0.0, 1 - z * z)), phi = golden * i;
            const Eigen::Vector3d d =
                n == 1 ? l.direction : (turn * Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z)).normalized();
            spread.add(d, l.irradiance_w_m2 / n, out, &hint);
        }
    }
    return out;
}

BtfFrame btf_frame_weights(const BtfGlesExport& e, const BtfGlesVariant& variant, const btf::Direction& view,
                           const Eigen::MatrixXd& sh, int64_t sent, const std::vector<BtfLight>& lights) {
    const int j_count = sh::count(e.sh_bands);
    if (sh.rows() < j_count || sh.cols() != 3 || !sh.allFinite())
        throw Error(str("BTF GLES frame: needs ", j_count, " x 3 finite lighting coefficients"));
    // The lights' weights at the BTF's light directions (a few non-zero: one or two per point).
    const int k_count = static_cast<int>(e.lights.size());
    std::vector<std::pair<int, Eigen::Vector3d>> light_w;
    const std::vector<Eigen::Vector3d> dense = btf_light_weights(e, lights);
    for (int k = 0; k < k_count; ++k)
        if (!dense[static_cast<size_t>(k)].isZero(0)) light_w.emplace_back(k, dense[static_cast<size_t>(k)]);
    const int groups = static_cast<int>(e.components.size());
    std::vector<int> arrived(static_cast<size_t>(groups), 0);
    for (int64_t i = 0; i < std::min<int64_t>(sent, static_cast<int64_t>(e.stream.size())); ++i)
        ++arrived[static_cast<size_t>(e.stream[static_cast<size_t>(i)].first)];
    const render::ViewBlend blend = render::select_views(e.views, view, 3);
    const int s_used = variant.slabs_used;
    BtfFrame f;
    // w_slot,ch[k] in double, in u_weight's layout; the decode is folded in below.
    std::vector<double> w_all(static_cast<size_t>(kSlots) * 3 * s_used * 4, 0.0);
    for (size_t i = 0; i < blend.views.size(); ++i) {
        const int v = blend.views[i];
        const int g = e.manifest.at("views").at(static_cast<size_t>(v)).at("group").get<int>();
        auto it = std::find(f.slot_group.begin(), f.slot_group.end(), g);
        const int slot = static_cast<int>(it - f.slot_group.begin());
        if (it == f.slot_group.end()) f.slot_group.push_back(g);
        const int comps = e.components[static_cast<size_t>(g)], rows = 1 + comps;
        const int live = 1 + arrived[static_cast<size_t>(g)];
        if (live > s_used * 4)
            throw Error(str("BTF GLES variant ", variant.name, ": group ", g, " has ", live - 1,
                            " components arrived, the variant shows at most ", s_used * 4 - 1));
        const float* m = e.matrices.data() + e.matrices_offset[static_cast<size_t>(v)];
        for (int ch = 0; ch < 3; ++ch) {
            const float* lr = e.light_rows.data() + e.light_rows_offset[static_cast<size_t>(v)];
            for (int r = 0; r < live; ++r) {
                double w = 0;
                for (int j = 0; j < j_count; ++j) w += double(m[(ch * rows + r) * j_count + j]) * sh(j, ch);
                for (const auto& [k, wk] : light_w) w += double(lr[(ch * rows + r) * k_count + k]) * wk[ch];
                w_all[static_cast<size_t>(((slot * 3 + ch) * s_used) * 4 + r)] += blend.weights[i] * w;
            }
        }
    }
    while (f.slot_group.size() < kSlots) f.slot_group.push_back(f.slot_group[0]);
    // The folder's decode, value = offset + scale x t, folded in: u_weight = scale x w and
    // u_bias = sum of offset x w (an unused slot's w is 0, so it adds nothing).
    f.weight.assign(w_all.size(), 0.f);
    double bias[3] = {0, 0, 0};
    for (int slot = 0; slot < kSlots; ++slot) {
        const auto& sc = e.scale[static_cast<size_t>(f.slot_group[static_cast<size_t>(slot)])];
        const auto& of = e.offset[static_cast<size_t>(f.slot_group[static_cast<size_t>(slot)])];
        for (int ch = 0; ch < 3; ++ch) {
            for (int k = 0; k < s_used * 4; ++k) {
                const size_t i = static_cast<size_t>(((slot * 3 + ch) * s_used) * 4 + k);
                f.weight[i] = static_cast<float>(double(sc[static_cast<size_t>(k)]) * w_all[i]);
                bias[ch] += double(of[static_cast<size_t>(k)]) * w_all[i];
            }
        }
    }
    f.bias = {static_cast<float>(bias[0]), static_cast<float>(bias[1]), static_cast<float>(bias[2]), 0.f};
    return f;
}

int btf_fragment_uniform_vectors(int slabs) { return kSlots * kVectorsPerSlab * slabs + 1; }

Bindings btf_bindings(const BtfGlesExport& e, const BtfFrame& frame) {
    Bindings b;
    b.sh = Eigen::MatrixXd::Zero(sh::count(e.sh_bands), 3);  // not a uniform of these shaders
    for (int slot = 0; slot < kSlots; ++slot)
        b.textures8.emplace_back(str("u_group", slot), &e.atlases[static_cast<size_t>(frame.slot_group[static_cast<size_t>(slot)])]);
    b.vec4_arrays = {{"u_weight", frame.weight}, {"u_bias", frame.bias}};
    return b;
}

}  // namespace inlight::gles
