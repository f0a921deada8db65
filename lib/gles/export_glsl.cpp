// gles/export_glsl.cpp: the GLSL ES 1.00 / 3.00 generator: vertex and fragment sources of a
// variant, from its plan (export_glsl.h).
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

/// (2l+1)/(4 pi) (l-m)!/(l+m)!, square-rooted: the real SH normalisation K_lm.
double sh_norm(int l, int m) {
    double ratio = 1.0;
    for (int i = l - m + 1; i <= l + m; ++i) ratio /= i;
    return std::sqrt((2 * l + 1) / (4 * kPi) * ratio);
}


/// "b<t>.x" for 1 channel, "vec3(b<t>_0.x, b<t>_1.x, b<t>_2.x)" for 3: coefficient k of the
/// interpolated table per channel, as a float or a vec3.
std::string coeff_expr(const Plan& p, int k) {
    const int t = k / 4;
    const char comp = "xyzw"[k % 4];
    if (p.channels() == 1) return str("b", t, ".", comp);
    return str("vec3(b", t, "_0.", comp, ", b", t, "_1.", comp, ", b", t, "_2.", comp, ")");
}

}  // namespace

std::string vertex_source(const Plan& p, const std::string& name) {
    const bool es3 = p.es3();
    const bool uv = p.mat->has_albedo_texture() || p.mat->has_normal_texture();
    const char* in = es3 ? "in" : "attribute";
    const char* out = es3 ? "out" : "varying";
    std::ostringstream o;
    o << (es3 ? "#version 300 es\n" : "#version 100\n")
      << "// " << name << ": vertex shader (inlight GLES export; bindings in " << name
      << ".json). Device frame.\n"
      << "uniform mat4 u_clip_from_object;\n";
    if (uv) o << "uniform vec2 u_uv_scale;\n";
    o << in << " vec3 a_position;\n" << in << " vec3 a_normal;\n";
    if (p.mat->has_normal_texture()) o << in << " vec3 a_tangent;\n";
    if (uv) o << in << " vec2 a_uv;\n";
    o << out << " vec3 v_normal;\n";
    if (p.mat->has_normal_texture()) o << out << " vec3 v_tangent;\n";
    if (uv) o << out << " vec2 v_uv;\n";
    o << "void main() {\n    v_normal = a_normal;\n";
    if (p.mat->has_normal_texture()) o << "    v_tangent = a_tangent;\n";
    if (uv) o << "    v_uv = a_uv * u_uv_scale;  // tiles: the fragment shader wraps\n";
    o << "    gl_Position = u_clip_from_object * vec4(a_position, 1.0);\n}\n";
    return o.str();
}


namespace {

/// texture_bilinear[_srgb](sampler, size, uv): bilinear between texel centres with wrap, as
/// render::sample_texture; `decode` = sRGB-decode each texel in the shader (ES 1.00 albedo).
/// `rect`: texture_rect[_srgb](sampler, atlas, rect, uv), the same inside the rectangle rect =
/// (x, y, width, height) of an atlas of `atlas` texels (render::sample_level).
std::string bilinear_function(const Plan& p, bool decode, bool rect = false) {
    std::ostringstream o;
    const std::string fname = str(rect ? "texture_rect" : "texture_bilinear", decode ? "_srgb" : "");
    const std::string texels = rect ? "atlas" : "size";
    if (rect) {
        o << "// Bilinear between texel centres inside the atlas rectangle r = (x, y, width, height),\n"
          << "// wrapping within it (render::sample_level), from 4 texels"
          << (decode ? ", each sRGB-decoded\n// before filtering as on the CPU.\n" : ".\n")
          << "vec3 " << fname << "(" << (p.es3() ? "highp " : "")
          << "sampler2D tex, vec2 atlas, vec4 r, vec2 uv) {\n    vec2 size = r.zw;\n";
    } else {
        o << "// Bilinear between texel centres, wrapping (render::sample_texture), from 4 texels"
          << (decode ? ",\n// each sRGB-decoded before filtering as on the CPU.\n" : ".\n")
          << "vec3 " << fname << "(" << (p.es3() ? "highp " : "") << "sampler2D tex, vec2 size, vec2 uv) {\n";
    }
    o << "    vec2 q = uv * size - 0.5;\n    vec2 f = floor(q);\n    vec2 a = q - f;\n"
      << "    vec2 i0 = f - size * floor((f + 0.5) / size);\n"
      << "    vec2 i1 = i0 + 1.0 - size * step(size - 0.5, i0 + 1.0);\n";
    if (rect) o << "    i0 += r.xy;\n    i1 += r.xy;\n";
    auto fetch = [&](const std::string& x, const std::string& y) {
        std::string e = p.es3() ? str("texelFetch(tex, ivec2(int(", x, "), int(", y, ")), 0).rgb")
                                : str("snap8(texture2D(tex, (vec2(", x, ", ", y,
                                      ") + 0.5) / ", texels, ")).rgb");
        return decode ? "srgb_decode(" + e + ")" : e;
    };
    o << "    vec3 t00 = " << fetch("i0.x", "i0.y") << ";\n"
      << "    vec3 t10 = " << fetch("i1.x", "i0.y") << ";\n"
      << "    vec3 t01 = " << fetch("i0.x", "i1.y") << ";\n"
      << "    vec3 t11 = " << fetch("i1.x", "i1.y") << ";\n"
      << "    return mix(mix(t00, t10, a.x), mix(t01, t11, a.x), a.y);\n}\n";
    return o.str();
}

/// The level of detail of a trilinear variant (render::box_matched_lod of render::mip_lod)
/// from the quad's uv derivatives.
std::string lod_function() {
    return "// Level of detail (render/mip.h): rho^2 = the longer squared uv derivative per pixel in\n"
           "// level-0 texels (dFdx, dFdy: differences across the 2 x 2 quad), then the box-matched\n"
           "// level log2(rho^2 / 3 + 2 / 3) / 2 (render::box_matched_lod).\n"
           "float texture_lod(vec2 size0) {\n"
           "    vec2 dx = dFdx(v_uv) * size0;\n"
           "    vec2 dy = dFdy(v_uv) * size0;\n"
           "    return 0.5 * log2(max(dot(dx, dx), dot(dy, dy)) / 3.0 + 2.0 / 3.0);\n}\n";
}

std::string size_literal(const Eigen::Vector2i& px);

/// <which>_level(k) (the atlas rectangle of level k, k a whole number) and <which>_trilinear(uv,
/// lod) (render::sample_trilinear) of one material texture of a trilinear variant.
std::string trilinear_functions(const Plan& p, bool albedo) {
    const std::string which = albedo ? "albedo" : "normal";
    const std::vector<render::MipRect>& levels = albedo ? p.albedo_levels : p.normal_levels;
    const Eigen::Vector2i atlas = albedo ? p.albedo_atlas_px : p.normal_atlas_px;
    auto rect = [](const render::MipRect& r) {
        return str("vec4(", lit(r.x), ", ", lit(r.y), ", ", lit(r.width), ", ", lit(r.height), ")");
    };
    const std::string last = lit(static_cast<double>(levels.size() - 1));
    std::ostringstream o;
    o << "// The " << which << " atlas' level k: (x, y, width, height) in texels (manifest: mip.levels).\n"
      << "vec4 " << which << "_level(float k) {\n";
    for (size_t k = 0; k + 1 < levels.size(); ++k) {
        o << "    if (k < " << lit(k + 0.5) << ") return " << rect(levels[k]) << ";\n";
    }
    o << "    return " << rect(levels.back()) << ";\n}\n"
      << "// Trilinear (render::sample_trilinear): levels floor(l) and floor(l) + 1 mixed by fract(l),\n"
      << "// l = lod clamped to [0, " << levels.size() - 1 << "].\n"
      << "vec3 " << which << "_trilinear(vec2 uv, float lod) {\n"
      << "    float l = clamp(lod, 0.0, " << last << ");\n"
      << "    float l0 = floor(l);\n";
    const std::string call = str(albedo ? "texture_rect_srgb" : "texture_rect", "(u_", which, "_texture, ",
                                 size_literal(atlas), ", ", which, "_level(");
    o << "    vec3 a = " << call << "l0), uv);\n"
      << "    vec3 b = " << call << "min(l0 + 1.0, " << last << ")), uv);\n"
      << "    return mix(a, b, l - l0);\n}\n";
    return o.str();
}

std::string size_literal(const Eigen::Vector2i& px) {
    return str("vec2(", lit(px.x()), ", ", lit(px.y()), ")");
}

/// The irradiance matrix entries M_ij (R&H eq. 12, sh::irradiance_matrix) as vec3 expressions
/// over u_sh, i <= j; "" where the entry is 0.
std::string matrix_entry(int i, int j) {
    std::string e;
    for (int k = 0; k < 9; ++k) {
        double unit[9] = {};
        unit[k] = 1.0;
        const double c = sh::irradiance_matrix(unit)(i, j);
        if (c == 0.0) continue;
        e += str(e.empty() ? "" : " + ", lit(c), " * u_sh[", k, "]");
    }
    return e;
}

std::string monomial(int i, int j) {
    static const char* kAxis[4] = {"x", "y", "z", ""};
    std::string m;
    for (int a : {i, j}) {
        if (a == 3) continue;
        m += str(m.empty() ? "" : " * ", kAxis[a]);
    }
    return m;
}

/// The fragment's lighting: declares vec3 radiance.
std::string shading_source(const Plan& p) {
    std::ostringstream o;
    const int bands = p.v->sh_bands;
    const bool seed = p.v->mode == ShaderMode::kSeed;
    o << "    float x = n.x;\n    float y = n.y;\n    float z = n.z;\n";
    if (bands == 3) {
        o << "    // Irradiance matrix M per channel (Ramamoorthi and Hanrahan 2001, eq. 12), E = "
             "(n, 1)^T M (n, 1).\n";
        for (int i = 0; i < 4; ++i) {
            for (int j = i; j < 4; ++j) {
                const std::string e = matrix_entry(i, j);
                if (!e.empty()) o << "    vec3 m" << i << j << " = " << e << ";\n";
            }
        }
        // seed: the report's L_lm carry the Condon-Shortley phase (its Figure 6) that R&H's
        // matrix does not expect: the terms odd in (x, y) change sign, E = E(-x, -y, z).
        std::string sum;
        for (int i = 0; i < 4; ++i) {
            for (int j = i; j < 4; ++j) {
                if (matrix_entry(i, j).empty()) continue;
                const std::string mono = monomial(i, j);
                const bool flip = seed && ((i < 2) != (j < 2));  // odd degree in x, y
                sum += str(sum.empty() ? (flip ? "-" : "") : (flip ? "\n        - " : "\n        + "),
                           i == j ? "" : "2.0 * ", "m", i, j, mono.empty() ? "" : " * (" + mono + ")");
            }
        }
        if (seed) {
            o << "    // The report's slip: its L_lm carry the Condon-Shortley phase (its Figure 6) "
                 "that\n"
              << "    // this matrix does not expect, so the terms odd in (x, y) change sign: E at "
                 "(-x, -y, z).\n";
        }
        o << "    vec3 e = " << sum << ";\n";
    } else {
        // E = sum_lm A_l L_lm Y_lm(n) over the bands where A_l != 0 (l = 0, 1 and even l).
        const int lmax = bands - 1;
        const int luse = (lmax % 2 == 0 || lmax < 2) ? lmax : lmax - 1;
        o << "    // Irradiance E = sum A_l L_lm Y_lm(n) (R&H eq. 7-8); A_l = 0 for odd l > 1.\n"
          << "    // Y_lm = K_lm P~_l^m(z) Re/Im (x + iy)^m, P~ by the Legendre recurrence in z.\n";
        for (int m = 1; m <= luse; ++m) {
            if (m == 1) {
                o << "    float cs1 = x;\n    float sn1 = y;\n";
            } else {
                o << "    float cs" << m << " = x * cs" << m - 1 << " - y * sn" << m - 1 << ";\n"
                  << "    float sn" << m << " = x * sn" << m - 1 << " + y * cs" << m - 1 << ";\n";
            }
        }
        o << "    vec3 e = vec3(0.0);\n";
        for (int m = 0; m <= luse; ++m) {
            double pmm = 1.0;  // (2m - 1)!!
            for (int i = 1; i <= 2 * m - 1; i += 2) pmm *= i;
            for (int l = m; l <= luse; ++l) {
                const std::string pv = str("p", l, "_", m);
                if (l == m) {
                    o << "    float " << pv << " = " << lit(pmm) << ";\n";
                } else if (l == m + 1) {
                    o << "    float " << pv << " = " << lit(2 * m + 1) << " * z * p" << m << "_"
                      << m << ";\n";
                } else {
                    o << "    float " << pv << " = " << lit((2.0 * l - 1) / (l - m)) << " * z * p"
                      << l - 1 << "_" << m << " - " << lit((l + m - 1.0) / (l - m)) << " * p"
                      << l - 2 << "_" << m << ";\n";
                }
                if (l > 1 && l % 2 == 1) continue;  // A_l = 0: an intermediate only
                const double a = sh::cosine_zonal(l);
                if (m == 0) {
                    o << "    e += (" << lit(a * sh_norm(l, 0)) << " * " << pv << ") * u_sh["
                      << sh::index(l, 0) << "];\n";
                } else {
                    const double c = a * std::sqrt(2.0) * sh_norm(l, m);
                    o << "    e += (" << lit(c) << " * " << pv << " * cs" << m << ") * u_sh["
                      << sh::index(l, m) << "];\n"
                      << "    e += (" << lit(c) << " * " << pv << " * sn" << m << ") * u_sh["
                      << sh::index(l, -m) << "];\n";
                }
            }
        }
    }
    if (seed) {
        o << "    // The report's shader (section 2.6): each M entry times the BRDF coefficient "
             "of\n"
          << "    // that entry (the cosine lobe applied twice), its constants 0.743125 and "
             "0.247708.\n"
          << "    vec3 spec = vec3(0.0);\n";
        if (p.table) {
            static constexpr int kIndex[4][4] = {
                {8, 4, 7, 3}, {4, 8, 5, 1}, {7, 5, 6, 2}, {3, 1, 2, -1}};
            o << "    vec3 c5l20 = (m22 / 0.743125) * 0.247708;\n"
              << "    vec3 c4l00 = m33 + c5l20;\n"
              << "    spec = c4l00 * " << coeff_expr(p, 0) << " - c5l20 * " << coeff_expr(p, 6);
            for (int i = 0; i < 3; ++i) {
                for (int j = i; j < 4; ++j) {
                    const std::string mono = monomial(i, j);
                    o << "\n        + " << (i == j ? "" : "2.0 * ") << "m" << i << j << " * "
                      << coeff_expr(p, kIndex[i][j]) << " * (" << mono << ")";
                }
            }
            o << ";\n";
        }
        o << "    vec3 radiance = albedo * ((e.x + e.y + e.z) / 3.0 * 0.3) + spec * 0.05;\n";
    } else {
        o << "    vec3 radiance = albedo * " << lit(kInvPi) << " * e;\n";
        if (p.table) {
            o << "    // Specular: sum_k L_k B_k(n) (brdf/table.h).\n";
            for (int k = 0; k < sh::count(bands); ++k) {
                o << "    radiance += u_sh[" << k << "] * " << coeff_expr(p, k) << ";\n";
            }
        }
    }
    return o.str();
}

std::string pow2i_function() {
    return "// 2^k for an integer k in [-255, 255], exactly (products of powers of two).\n"
           "float pow2i(float k) {\n"
           "    float r = 1.0;\n"
           "    float b = k < 0.0 ? 0.5 : 2.0;\n"
           "    float n = abs(k);\n"
           "    for (int i = 0; i < 8; ++i) {\n"
           "        float h = floor(n * 0.5);\n"
           "        if (n - 2.0 * h > 0.5) r *= b;\n"
           "        n = h;\n"
           "        // Square only while bits remain: b never exceeds the result's own size\n"
           "        // (b = 2^16 would overflow mediump's 65504 and feed inf into r).\n"
           "        if (n > 0.5) b *= b;\n"
           "    }\n"
           "    return r;\n}\n";
}


}  // namespace

/// Needs pow2i_function() before it.
std::string exp_log_functions() {
    return "float exp_f32(float x) {\n"
           "    float k = floor(1.44269504 * x + 0.5);\n"
           "    float r = x - k * 0.693359375 + k * 2.12194440e-4;\n"
           "    float p = ((((1.9875691500e-4 * r + 1.3981999507e-3) * r + 8.3334519073e-3) * r\n"
           "               + 4.1665795894e-2) * r + 1.6666665459e-1) * r + 5.0000001201e-1;\n"
           "    return (p * r * r + r + 1.0) * pow2i(k);\n}\n"
           "// Natural log of x > 0.\n"
           "float log_f32(float x) {\n"
           "    float e = floor(log2(x));\n"
           "    float m = x / pow2i(e);\n"
           "    if (m < 1.0) { m *= 2.0; e -= 1.0; }\n"
           "    if (m >= 2.0) { m *= 0.5; e += 1.0; }\n"
           "    if (m > 1.41421356) { m *= 0.5; e += 1.0; }\n"
           "    float z = m - 1.0;\n"
           "    float z2 = z * z;\n"
           "    float y = ((((((((7.0376836292e-2 * z - 1.1514610310e-1) * z + 1.1676998740e-1) * z\n"
           "               - 1.2420140846e-1) * z + 1.4249322787e-1) * z - 1.6668057665e-1) * z\n"
           "               + 2.0000714765e-1) * z - 2.4999993993e-1) * z + 3.3333331174e-1) * z * z2;\n"
           "    y += -2.12194440e-4 * e - 0.5 * z2;\n"
           "    return z + y + 0.693359375 * e;\n}\n"
           "// x^y for y > 0 (0 for x <= 0).\n"
           "float pow_f32(float x, float y) {\n"
           "    return x > 0.0 ? exp_f32(y * log_f32(x)) : 0.0;\n}\n";
}

std::string fragment_source(const Plan& p, const std::string& name) {
    const bool es3 = p.es3();
    const MaterialInputs& mat = *p.mat;
    const bool uv = mat.has_albedo_texture() || mat.has_normal_texture();
    const std::string prec = to_string(p.v->precision);
    // Samplers: ES 3.00 guarantees highp in fragment shaders; ES 1.00 only with
    // GL_FRAGMENT_PRECISION_HIGH, which the highp variants require anyway.
    const std::string sampler = str(es3 ? "highp" : prec, " sampler2D");
    const int k_count = sh::count(p.v->sh_bands);
    const int t_count = p.texels_per_node;
    std::ostringstream o;
    o << (es3 ? "#version 300 es\n" : "#version 100\n")
      << (!es3 && uv && p.trilinear() ? "#extension GL_OES_standard_derivatives : require\n" : "")
      << "// " << name << ": fragment shader (inlight GLES export; bindings in " << name
      << ".json).\n"
      << "// Linear_srgb radiance of the " << to_string(p.v->mode) << " real-time model "
      << "(render/realtime.h), " << p.v->sh_bands << " SH bands, device frame.\n"
      << "precision " << prec << " float;\nprecision " << prec << " int;\n";
    if (es3) o << "out vec4 o_radiance;\n";
    const char* in = es3 ? "in" : "varying";
    o << in << " vec3 v_normal;\n";
    if (mat.has_normal_texture()) o << in << " vec3 v_tangent;\n";
    if (uv) o << in << " vec2 v_uv;\n";
    if (p.lighting == LightingLayout::kUniformArray) {
        o << "uniform vec3 u_sh[" << k_count << "];  // lighting L_lm, radiance, linear_srgb\n";
    } else {
        o << "uniform " << sampler << " u_sh_texture;  // lighting L_lm (" << to_string(p.lighting)
          << ")\n";
    }
    o << "uniform vec3 u_albedo;  // linear_srgb\n";
    if (p.v->lights > 0) {
        o << "uniform vec4 u_light_direction[" << p.v->lights
          << "];  // (d toward the light, sin alpha)\n"
          << "uniform vec3 u_light_irradiance[" << p.v->lights
          << "];  // E_perp = flux (1 + cos alpha) / 2, linear_srgb\n";
    }
    if (mat.has_normal_texture() || (p.v->lights > 0 && p.table)) {
        const Eigen::Vector3d view = p.table ? p.table->view : Eigen::Vector3d::UnitZ();
        o << "const vec3 VIEW = vec3(" << lit(view.x()) << ", " << lit(view.y()) << ", "
          << lit(view.z()) << ");  // the table's view, toward the viewer\n";
    }
    if (mat.has_albedo_texture()) o << "uniform " << sampler << " u_albedo_texture;\n";
    if (mat.has_normal_texture()) o << "uniform " << sampler << " u_normal_texture;\n";
    if (!es3 && (uv || p.layout == TableLayout::kRgba8Texture)) {
        // texture2D() of an 8-bit texel need not return code / 255 exactly (llvmpipe's
        // 8-bit path is off by up to 0.4%); the nearest code is exact on every driver.
        o << "vec4 snap8(vec4 t) { return floor(t * 255.0 + 0.5) / 255.0; }\n";
    }
    if (p.table) {
        const brdf::Table& t = *p.table;
        o << "const int BRDF_ROWS = " << t.grid.rows << ";\n"
          << "const int BRDF_COLS = " << t.grid.cols << ";\n";
        switch (p.layout) {
            case TableLayout::kUniformArray:
                o << "uniform vec4 u_brdf[" << t.channels * t.grid.node_count() * t_count
                  << "];  // texel ((ch * ROWS + i1) * COLS + i2) * " << t_count << " + t\n"
                  << "vec4 brdf_texel(int ch, int i1, int i2, int t) {\n"
                  << "    return u_brdf[((ch * BRDF_ROWS + i1) * BRDF_COLS + i2) * " << t_count
                  << " + t];\n}\n";
                break;
            case TableLayout::kFloatTexture:
                o << "uniform " << sampler << " u_brdf_texture;  // RGBA32F, NEAREST\n"
                  << "vec4 brdf_texel(int ch, int i1, int i2, int t) {\n";
                if (p.wrapped) {
                    o << "    // Texel i = ((ch * ROWS + i1) * COLS + i2) * " << t_count
                      << " + t in rows of " << p.data_width << " (GL_MAX_TEXTURE_SIZE).\n"
                      << "    int i = ((ch * BRDF_ROWS + i1) * BRDF_COLS + i2) * " << t_count
                      << " + t;\n"
                      << "    int y = i / " << p.data_width << ";\n"
                      << "    return texelFetch(u_brdf_texture, ivec2(i - y * " << p.data_width
                      << ", y), 0);\n}\n";
                } else {
                    o << "    return texelFetch(u_brdf_texture, ivec2(i2 * " << t_count
                      << " + t, ch * BRDF_ROWS + i1), 0);\n}\n";
                }
                break;
            case TableLayout::kRgba8Texture:
                o << "uniform " << sampler << " u_brdf_texture;  // RGBA8, NEAREST\n";
                if (!p.scale_in_texture) {
                    o << "uniform vec4 u_brdf_scale[" << t_count << "];\n"
                      << "uniform vec4 u_brdf_offset[" << t_count << "];\n";
                }
                o << "// Texel i (linear order) in rows of " << p.data_width << ", its bytes exact.\n"
                  << "vec4 brdf_texel_at(float i) {\n"
                  << "    float y = floor((i + 0.5) / " << lit(p.data_width) << ");\n"
                  << "    return snap8(texture2D(u_brdf_texture, (vec2(i - y * " << lit(p.data_width)
                  << ", y) + 0.5) / " << size_literal({p.data_width, p.data_height}) << "));\n}\n"
                  << "// Texel i = ((ch * ROWS + i1) * COLS + i2) * " << t_count << " + t.\n"
                  << "vec4 brdf_texel(int ch, int i1, int i2, int t) {\n"
                  << "    return brdf_texel_at(float(((ch * BRDF_ROWS + i1) * BRDF_COLS + i2) * "
                  << t_count << " + t));\n}\n";
                break;
            case TableLayout::kNone:
                break;
        }
        o << "// Bilinear over the cell: mix(mix(c00, c01, f.y), mix(c10, c11, f.y), f.x).\n"
          << "vec4 brdf_lerp(ivec4 cell, vec2 f, int ch, int t) {\n"
          << "    return mix(mix(brdf_texel(ch, cell.x, cell.z, t), brdf_texel(ch, cell.x, "
             "cell.w, t), f.y),\n"
          << "               mix(brdf_texel(ch, cell.y, cell.z, t), brdf_texel(ch, cell.y, "
             "cell.w, t), f.y), f.x);\n}\n"
          // mediump flushes the shared snippet's 1e-20 guards (nadir normals) to 0.
          << (p.v->precision == Precision::kHighp
                  ? brdf::glsl_grid_coord_source(t.grid, es3 ? 300 : 100)
                  : std::regex_replace(brdf::glsl_grid_coord_source(t.grid, es3 ? 300 : 100),
                                       std::regex(", 1e-20\\)"), ", 6.2e-5)"));
    }
    const bool charlie_lights = p.v->lights > 0 && p.table && mat.brdf.specular == brdf::Model::kCharlie;
    const bool unpack = p.lighting == LightingLayout::kRgba8Texture || p.scale_in_texture;
    if (charlie_lights || unpack) o << pow2i_function();
    if (unpack) {
        o << "// A float32 from 4 bytes (gles::bind_lighting): exponent + 127, then the mantissa\n"
          << "// with its leading 1 replaced by the sign. Exact.\n"
          << "float unpack_f32(vec4 t) {\n"
          << "    vec4 b = floor(t * 255.0 + 0.5);\n"
          << "    if (b.x == 0.0) return 0.0;\n"
          << "    float neg = step(128.0, b.y);\n"
          << "    // The 24-bit mantissa / 2^24 as ((y + (z + w / 256) / 256) / 256): every\n"
          << "    // step exact in highp and below 256 (mediump holds it, unlike 2^24 x 2^-24).\n"
          << "    float m = ((b.y - 128.0 * neg + 128.0) + (b.z + b.w / 256.0) / 256.0) / 256.0;\n"
          << "    return (1.0 - 2.0 * neg) * m * pow2i(b.x - 127.0);\n}\n";
    }
    if (p.lighting == LightingLayout::kFloatTexture) {
        o << "vec3 sh_coeff(int k) { return texelFetch(u_sh_texture, ivec2(k, 0), 0).rgb; }\n";
    } else if (p.lighting == LightingLayout::kRgba8Texture) {
        const std::string w = lit(k_count);
        o << "// Coefficient k: offset_k + scale_k q / 65535, q the 16 bits of rows 0 and 1.\n"
          << "vec3 sh_coeff(float k) {\n"
          << "    float x = (k + 0.5) / " << w << ";\n"
          << "    vec3 hi = floor(texture2D(u_sh_texture, vec2(x, 0.125)).rgb * 255.0 + 0.5);\n"
          << "    vec3 lo = floor(texture2D(u_sh_texture, vec2(x, 0.375)).rgb * 255.0 + 0.5);\n"
          << "    float scale = unpack_f32(texture2D(u_sh_texture, vec2(x, 0.625)));\n"
          << "    float offset = unpack_f32(texture2D(u_sh_texture, vec2(x, 0.875)));\n"
          << (p.v->precision == Precision::kHighp
                  ? "    return offset + scale * ((hi * 256.0 + lo) / 65535.0);\n}\n"
                  : "    // (hi 256 + lo) / 65535 without forming 65535 (mediump's maximum is 65504).\n"
                    "    return offset + scale * ((hi + lo / 256.0) * 0.00390631);\n}\n");
    }
    if (p.v->lights > 0) {
        const bool exact_cap = p.v->light_shading == envmap::LightShading::kCap;  // uses atan2
        if (exact_cap && (!p.table || !brdf::glsl_grid_coord_has_atan2(p.table->grid))) {
            o << brdf::glsl_atan2_source();
        }
        o << lights_functions(p);
    }
    if (mat.has_albedo_texture()) {
        // Decoded here, per texel, in both versions: drivers' sRGB texture decoders and pow()
        // are approximations (llvmpipe's GL_SRGB8_ALPHA8 decode is off by up to 5e-3
        // relative, its pow() by ~1e-3: measured, docs/gles.md); one Newton step on
        // y^5 = x^12 (y = x^2.4) brings pow() to float rounding.
        o << "vec3 srgb_decode(vec3 c) {\n"
          << "    vec3 x = (c + 0.055) / 1.055;\n"
          << "    vec3 y = pow(x, vec3(2.4));\n"
          << "    vec3 x3 = x * x * x;\n    vec3 x6 = x3 * x3;\n    vec3 y2 = y * y;\n"
          << (p.v->precision == Precision::kHighp
                  ? "    y = 0.8 * y + 0.2 * (x6 * x6) / (y2 * y2);\n"
                  // x^12 and y^4 underflow half floats for dark texels (0 / 0): the same
                  // step as (x^3 / y)^4, which stays near 1.
                  : "    vec3 q = x3 / y;\n    q *= q;\n    y = 0.8 * y + 0.2 * q * q;\n")
          << "    vec3 lo = c / 12.92;\n"
          << "    return vec3(c.r <= 0.04045 ? lo.r : y.r, c.g <= 0.04045 ? lo.g : y.g,\n"
          << "                c.b <= 0.04045 ? lo.b : y.b);\n}\n"
          << bilinear_function(p, true, p.trilinear());
    }
    if (mat.has_normal_texture()) {
        o << bilinear_function(p, false, p.trilinear());
    }
    if (uv && p.trilinear()) {
        o << lod_function();
        if (mat.has_albedo_texture()) o << trilinear_functions(p, true);
        if (mat.has_normal_texture()) o << trilinear_functions(p, false);
    }

    o << "void main() {\n";
    if (mat.has_albedo_texture()) {
        if (p.trilinear()) {
            o << "    vec3 albedo = u_albedo * albedo_trilinear(v_uv, texture_lod("
              << size_literal(mat.albedo_texture_px) << "));\n";
        } else {
            o << "    vec3 albedo = u_albedo * "
              << "texture_bilinear_srgb(u_albedo_texture, "
              << size_literal(mat.albedo_texture_px) << ", v_uv);\n";
        }
    } else {
        o << "    vec3 albedo = u_albedo;\n";
    }
    if (p.lighting != LightingLayout::kUniformArray) {
        for (int k = 0; k < k_count; ++k) {
            o << "    vec3 sh" << k << " = sh_coeff(" << (es3 ? str(k) : lit(k)) << ");\n";
        }
    }
    o << "    vec3 n = normalize(v_normal);\n";
    if (mat.has_normal_texture()) {
        o << "    // Normal map: data, 2 rgb - 1 in the frame (t, n x t, n) (render/material.h).\n"
          << "    vec3 c = "
          << (p.trilinear() ? str("normal_trilinear(v_uv, texture_lod(", size_literal(mat.normal_texture_px), "))")
                            : str("texture_bilinear(u_normal_texture, ", size_literal(mat.normal_texture_px), ", v_uv)"))
          << " * 2.0 - 1.0;\n"
          << "    vec3 mapped = v_tangent * c.x + cross(n, v_tangent) * c.y + n * c.z;\n"
          << "    vec3 ng = n;\n"
          << "    if (dot(mapped, mapped) > "
          << (p.v->precision == Precision::kHighp ? "1e-12" : "6.2e-5")  // mediump: > 0
          << ") n = normalize(mapped);\n"
          << "    if (dot(n, VIEW) <= 0.0) n = ng;\n";
    }
    if (p.scale_in_texture) {
        o << "    // The table's scale and offset per coefficient: float32 texels after the table's.\n";
        for (int t = 0; t < t_count; ++t) {
            for (const char* what : {"scale", "offset"}) {
                const int base = p.scale_texel + (what[0] == 'o' ? k_count : 0);
                std::string comps;
                for (int c = 0; c < 4; ++c) {
                    const int k = 4 * t + c;
                    comps += c ? ", " : "";
                    comps += k < k_count ? str("unpack_f32(brdf_texel_at(", lit(base + k), "))") : "0.0";
                }
                o << "    vec4 brdf_" << what << t << " = vec4(" << comps << ");\n";
            }
        }
    }
    if (p.table) {
        if (p.v->mode == ShaderMode::kSeed) {
            o << "    // The report's getBRDF takes phi = atan(y / x), losing the quadrant: a normal "
                 "with x < 0\n"
              << "    // reads the table at its mirror (-x, -y, z) (render/realtime.h, seed mode).\n"
              << "    ivec4 cell;\n    vec2 f;\n"
              << "    brdf_grid_coord(n.x < 0.0 ? vec3(-n.x, -n.y, n.z) : n, cell, f);\n";
        } else {
            o << "    ivec4 cell;\n    vec2 f;\n    brdf_grid_coord(n, cell, f);\n";
        }
        for (int t = 0; t < t_count; ++t) {
            for (int ch = 0; ch < p.channels(); ++ch) {
                const std::string var = p.channels() == 1 ? str("b", t) : str("b", t, "_", ch);
                const std::string lerp = str("brdf_lerp(cell, f, ", ch, ", ", t, ")");
                if (p.layout == TableLayout::kRgba8Texture && p.scale_in_texture) {
                    o << "    vec4 " << var << " = brdf_offset" << t << " + brdf_scale" << t << " * "
                      << lerp << ";\n";
                } else if (p.layout == TableLayout::kRgba8Texture) {
                    o << "    vec4 " << var << " = u_brdf_offset[" << t << "] + u_brdf_scale[" << t
                      << "] * " << lerp << ";\n";
                } else {
                    o << "    vec4 " << var << " = " << lerp << ";\n";
                }
            }
        }
    }
    o << shading_source(p);
    if (p.v->lights > 0) {
        o << "    // Dominant lights (render/realtime_lights.h): albedo / pi E + f_s E per light.\n";
    }
    for (int j = 0; j < p.v->lights; ++j) {
        o << "    vec3 e" << j << " = u_light_irradiance[" << j << "] * cap_factor(dot(n, u_light_direction["
          << j << "].xyz), u_light_direction[" << j << "].w);\n"
          << "    radiance += albedo * " << lit(kInvPi) << " * e" << j;
        if (p.table) o << " + lobe(n, u_light_direction[" << j << "].xyz) * e" << j;
        o << ";\n";
    }
    o << (es3 ? "    o_radiance" : "    gl_FragColor") << " = vec4(radiance, 1.0);\n}\n";
    if (p.lighting == LightingLayout::kUniformArray) return o.str();
    // The shading code names the coefficients u_sh[k]; here they are the locals sh<k>.
    return std::regex_replace(o.str(), std::regex(R"(u_sh\[(\d+)\])"), "sh$1");
}
}  // namespace inlight::gles::detail
