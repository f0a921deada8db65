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

namespace {

std::string lit(double v) { return brdf::glsl_float(static_cast<float>(v)); }

/// (2l+1)/(4 pi) (l-m)!/(l+m)!, square-rooted: the real SH normalisation K_lm.
double sh_norm(int l, int m) {
    double ratio = 1.0;
    for (int i = l - m + 1; i <= l + m; ++i) ratio /= i;
    return std::sqrt((2 * l + 1) / (4 * kPi) * ratio);
}

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
    bool es3() const { return v->version == GlslVersion::kEs300; }
    int channels() const { return table ? table->channels : 0; }
};

/// "b<t>.x" for 1 channel, "vec3(b<t>_0.x, b<t>_1.x, b<t>_2.x)" for 3: coefficient k of the
/// interpolated table per channel, as a float or a vec3.
std::string coeff_expr(const Plan& p, int k) {
    const int t = k / 4;
    const char comp = "xyzw"[k % 4];
    if (p.channels() == 1) return str("b", t, ".", comp);
    return str("vec3(b", t, "_0.", comp, ", b", t, "_1.", comp, ", b", t, "_2.", comp, ")");
}

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

/// texture_bilinear[_srgb](sampler, size, uv): bilinear between texel centres with wrap, as
/// render::sample_texture; `decode` = sRGB-decode each texel in the shader (ES 1.00 albedo).
std::string bilinear_function(const Plan& p, bool decode) {
    std::ostringstream o;
    const std::string fname = decode ? "texture_bilinear_srgb" : "texture_bilinear";
    o << "// Bilinear between texel centres, wrapping (render::sample_texture), from 4 texels"
      << (decode ? ",\n// each sRGB-decoded before filtering as on the CPU.\n" : ".\n")
      << "vec3 " << fname << "(" << (p.es3() ? "highp " : "") << "sampler2D tex, vec2 size, vec2 uv) {\n"
      << "    vec2 q = uv * size - 0.5;\n    vec2 f = floor(q);\n    vec2 a = q - f;\n"
      << "    vec2 i0 = f - size * floor((f + 0.5) / size);\n"
      << "    vec2 i1 = i0 + 1.0 - size * step(size - 0.5, i0 + 1.0);\n";
    auto fetch = [&](const std::string& x, const std::string& y) {
        std::string e = p.es3() ? str("texelFetch(tex, ivec2(int(", x, "), int(", y, ")), 0).rgb")
                                : str("snap8(texture2D(tex, (vec2(", x, ", ", y,
                                      ") + 0.5) / size)).rgb");
        return decode ? "srgb_decode(" + e + ")" : e;
    };
    o << "    vec3 t00 = " << fetch("i0.x", "i0.y") << ";\n"
      << "    vec3 t10 = " << fetch("i1.x", "i0.y") << ";\n"
      << "    vec3 t01 = " << fetch("i0.x", "i1.y") << ";\n"
      << "    vec3 t11 = " << fetch("i1.x", "i1.y") << ";\n"
      << "    return mix(mix(t00, t10, a.x), mix(t01, t11, a.x), a.y);\n}\n";
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

/// exp_f32, log_f32 and pow_f32 to float accuracy (Cephes expf/logf: range reduction, then a
/// polynomial, from +, *, / and floor): drivers' exp(), log() and pow() carry no accuracy
/// requirement (llvmpipe's pow is ~1.5e-3 off, docs/gles.md). The driver's log2() only picks
/// the binade, corrected by one step either way; powers of two come from exact products.
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

/// The dominant lights' functions (render/realtime_lights.h, envmap/lights.h): the cap's
/// irradiance factor and, with a table, the material's specular lobe. Needs atan2_f32.
std::string lights_functions(const Plan& p) {
    std::ostringstream o;
    if (p.v->light_shading == envmap::LightShading::kSmoothCap) {
        o << "// The smooth cap's factor over E_perp (envmap::smooth_cap_cosine): c above the\n"
          << "// horizon band |c| < sa, 0 below it, the C1 quadratic (c + sa)^2 / (4 sa) across it.\n"
          << "float cap_factor(float c, float sa) {\n"
          << "    if (c >= sa) return c;\n"
          << "    if (c <= -sa) return 0.0;\n"
          << "    return (c + sa) * (c + sa) / (4.0 * sa);\n}\n";
    } else {
        o << "// Irradiance of a uniform cap of half-angle alpha centred at cosine c from the normal,\n"
          << "// over E_perp: J = I(c, alpha) / (pi sin^2 alpha), I = Snyder 1996's integral of\n"
          << "// max(0, n.w) over the cap (envmap::cap_cosine_integral). sa = sin alpha (0: a point).\n"
          << "// Near the horizon the atan and x t terms cancel to O(alpha^3); for u = t tan alpha <\n"
          << "// 0.1 their difference atan(u) - u is summed as a series instead (float-accurate).\n"
          << "float cap_factor(float c, float sa) {\n"
          << "    if (c >= sa) return c;\n"
          << "    if (c <= -sa) return 0.0;\n"
          << "    float ca = sqrt(1.0 - sa * sa);\n"
          << "    float sb = sqrt(1.0 - c * c);\n"
          << "    float x = ca / sa;\n"
          << "    float y = clamp(-x * c / sb, -1.0, 1.0);\n"
          << "    float r = sqrt((1.0 - y) * (1.0 + y));\n"
          << "    float t = sb * r;\n"
          << "    float acos_y = atan2_f32(r, y);\n"
          << "    float j;\n"
          << "    if (t * sa < 0.1 * ca) {\n"
          << "        float u = t * sa / ca;\n"
          << "        float u2 = u * u;\n"
          << "        float d = u * u2 * (-0.333333333 + u2 * (0.2 + u2 * (-0.142857143 + u2 * "
             "0.111111111)));\n"
          << "        j = (c * acos_y + u) * " << lit(kInvPi) << " + d / (" << lit(kPi)
          << " * sa * sa);\n"
          << "    } else {\n"
          << "        j = (c * acos_y - x * t) * " << lit(kInvPi) << " + atan2_f32(t, x) / ("
          << lit(kPi) << " * sa * sa);\n"
          << "    }\n"
          << "    return max(j, 0.0);\n}\n";
    }
    if (!p.table) return o.str();
    const brdf::Material& m = p.mat->brdf;
    const double scale = m.specular_scale;
    // Charlie's fitted Lambda at this alpha: L(x) = A / (1 + B x^C) + D x + E (brdf.cpp).
    const double ch_a = std::clamp(m.alpha, brdf::kMinAlpha, 1.0);
    const double ch_t = (1.0 - ch_a) * (1.0 - ch_a);
    auto lerp = [ch_t](double at1, double at0) { return at0 + ch_t * (at1 - at0); };
    const double ca = lerp(25.3245, 21.5473), cb = lerp(3.32435, 3.82987),
                 cc = lerp(0.16801, 0.19823), cd = lerp(-1.27393, -1.97760),
                 ce = lerp(-4.85967, -4.32054);
    if (m.specular == brdf::Model::kCharlie) {
        const double l_half = ca / (1.0 + cb * std::pow(0.5, cc)) + cd * 0.5 + ce;
        o << exp_log_functions()
          << "// Estevez and Kulla 2017's fitted L(x) at this alpha (brdf::charlie_lambda).\n"
          << "float charlie_l(float x) {\n"
          << "    return " << lit(ca) << " / (1.0 + " << lit(cb) << " * pow_f32(x, " << lit(cc)
          << ")) + " << lit(cd) << " * x + " << lit(ce) << ";\n}\n"
          << "float charlie_lambda(float c) {\n"
          << "    if (c < 0.5) return exp_f32(charlie_l(c));\n"
          << "    return exp_f32(" << lit(2.0 * l_half) << " - charlie_l(1.0 - c));\n}\n";
    }
    // The lobe's grazing guard: the CPU model's 1e-9 in highp. mediump flushes 1e-9 to zero
    // (its guaranteed range starts near 2^-14), and 4 nv nl and nv^2 must stay normal in it:
    // 2^-6 keeps them >= 2^-12, at the cost of no specular from a light within 0.9 degrees
    // of the horizon or a view that grazing (docs/gles.md, "Precision").
    const std::string g = p.v->precision == Precision::kHighp ? "1e-9" : "0.015625";
    o << "// The material's " << brdf::to_string(m.specular)
      << " lobe f_s(n; VIEW, l) in 1/sr (brdf::eval_specular),\n"
      << "// from dot products only: the lobe is isotropic.\n"
      << "vec3 lobe(vec3 n, vec3 l) {\n"
      << "    float nv = dot(n, VIEW);\n    float nl = dot(n, l);\n"
      << "    if (nv < " << g << " || nl < " << g << ") return vec3(0.0);\n"
      << "    vec3 h = normalize(VIEW + l);\n"
      << "    float nh = dot(n, h);\n"
      << "    float vh = clamp(dot(VIEW, h), 0.0, 1.0);\n";
    auto schlick5 = [&]() {
        o << "    float m1 = 1.0 - vh;\n    float m5 = m1 * m1 * m1 * m1 * m1;\n";
    };
    switch (m.specular) {
        case brdf::Model::kGgx: {
            const double a = std::max(m.alpha, brdf::kMinAlpha);
            const std::string a2 = lit(a * a);
            schlick5();
            o << "    if (nh <= 0.0) return vec3(0.0);\n"
              << "    float q = nh * nh * (" << a2 << " - 1.0) + 1.0;\n"
              << "    float dist = " << a2 << " / (" << lit(kPi) << " * q * q);\n"
              << "    float co = max(nv, " << g << ");\n    float ci = max(nl, " << g << ");\n"
              << "    float lo = 0.5 * (-1.0 + sqrt(1.0 + " << a2
              << " * max(0.0, 1.0 - co * co) / (co * co)));\n"
              << "    float li = 0.5 * (-1.0 + sqrt(1.0 + " << a2
              << " * max(0.0, 1.0 - ci * ci) / (ci * ci)));\n"
              << "    vec3 f0 = vec3(" << lit(m.f0.x()) << ", " << lit(m.f0.y()) << ", "
              << lit(m.f0.z()) << ");\n"
              << "    return (f0 + (1.0 - f0) * m5) * (" << lit(scale)
              << " * dist / ((1.0 + lo + li) * 4.0 * nv * nl));\n";
            break;
        }
        case brdf::Model::kCookTorranceReport: {
            const double r = std::max(m.report_r, brdf::kMinAlpha);
            schlick5();
            o << "    if (vh <= 0.0) return vec3(0.0);\n"
              << "    float f = " << lit(m.report_f) << " + " << lit(1.0 - m.report_f)
              << " * m5;\n"
              << "    float g = min(1.0, min(2.0 * nh * nv / vh, 2.0 * nh * nl / vh));\n"
              << "    float q = nh * nh * " << lit(r * r) << " + 1.0;\n"
              << "    float dist = " << lit(r * r / kPi) << " / (q * q);\n"
              << "    return vec3(" << lit(scale) << " * f * g * dist / (4.0 * nv * nl));\n";
            break;
        }
        case brdf::Model::kCharlie: {
            const double a = ch_a;
            o << "    float sin2 = max(0.0, 1.0 - nh * nh);\n"
              << "    float dist = " << lit((2.0 + 1.0 / a) / (2.0 * kPi)) << " * pow_f32(sin2, "
              << lit(0.5 / a) << ");\n"
              << "    float g = 1.0 / (1.0 + charlie_lambda(clamp(nv, 0.0, 1.0)) + "
                 "charlie_lambda(clamp(nl, 0.0, 1.0)));\n"
              << "    return vec3(" << lit(m.sheen_color.x()) << ", " << lit(m.sheen_color.y())
              << ", " << lit(m.sheen_color.z()) << ") * (" << lit(scale)
              << " * dist * g / (4.0 * nv * nl));\n";
            break;
        }
        case brdf::Model::kLambert:
            break;
    }
    o << "}\n";
    return o.str();
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
          << bilinear_function(p, true);
    }
    if (mat.has_normal_texture()) {
        o << bilinear_function(p, false);
    }

    o << "void main() {\n";
    if (mat.has_albedo_texture()) {
        o << "    vec3 albedo = u_albedo * "
          << "texture_bilinear_srgb(u_albedo_texture, "
          << size_literal(mat.albedo_texture_px) << ", v_uv);\n";
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
          << "    vec3 c = texture_bilinear(u_normal_texture, " << size_literal(mat.normal_texture_px)
          << ", v_uv) * 2.0 - 1.0;\n"
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
    m["files"] = {{"vertex", e.name + ".vert"},
                  {"fragment", e.name + ".frag"},
                  {"brdf_data", p.table ? json(e.name + ".brdf.bin") : json(nullptr)}};
    m["frame"] = "device: +z out of the screen toward the viewer (docs/conventions.md)";
    json attrs = json::array();
    attrs.push_back({{"name", "a_position"}, {"type", "vec3"}, {"meaning", "position, device frame"}});
    attrs.push_back({{"name", "a_normal"}, {"type", "vec3"}, {"meaning", "unit geometric normal, device frame, facing the viewer"}});
    if (mat.has_normal_texture()) {
        attrs.push_back({{"name", "a_tangent"}, {"type", "vec3"}, {"meaning", "dp/du, device frame (normal-map x axis)"}});
    }
    if (uv) attrs.push_back({{"name", "a_uv"}, {"type", "vec2"}, {"meaning", "texture uv, v down (1 = one tile)"}});
    m["attributes"] = attrs;
    json uniforms = json::array();
    uniforms.push_back({{"name", "u_clip_from_object"}, {"type", "mat4"}, {"count", 1}, {"stage", "vertex"}, {"meaning", "clip from device frame"}});
    if (uv) uniforms.push_back({{"name", "u_uv_scale"}, {"type", "vec2"}, {"count", 1}, {"stage", "vertex"}, {"meaning", "tiles per unit of a_uv"}});
    const char* sh_meaning = "lighting SH coefficients L_lm (R, G, B), device frame, real SH without Condon-Shortley phase, index l(l+1)+m";
    if (p.lighting == LightingLayout::kUniformArray) {
        uniforms.push_back({{"name", "u_sh"}, {"type", "vec3"}, {"count", sh::count(p.v->sh_bands)}, {"stage", "fragment"},
                            {"meaning", sh_meaning}, {"units", "radiance (linear_srgb, the environment's units)"}});
    }
    uniforms.push_back({{"name", "u_albedo"}, {"type", "vec3"}, {"count", 1}, {"stage", "fragment"}, {"meaning", "material albedo, linear_srgb"}, {"range", {0.0, 1.0}}});
    if (p.v->lights > 0) {
        uniforms.push_back({{"name", "u_light_direction"}, {"type", "vec4"}, {"count", p.v->lights}, {"stage", "fragment"},
                            {"meaning", "per dominant light j: xyz = unit direction toward the light (device frame, as u_sh: rotate it "
                                        "with the device), w = sin(angular_radius), 0 below 1e-4 rad (a point light)"},
                            {"units", "xyz dimensionless; w = sine of the cap's half-angle alpha"},
                            {"range", {-1.0, 1.0}},
                            {"from_lighting_file", "direction normalised; w = alpha < 1e-4 rad ? 0 : sin(alpha), alpha = angular_radius_deg in radians"}});
        uniforms.push_back({{"name", "u_light_irradiance"}, {"type", "vec3"}, {"count", p.v->lights}, {"stage", "fragment"},
                            {"meaning", "per dominant light j: E_perp, the irradiance of its uniform cap on a surface facing it (linear_srgb)"},
                            {"units", "radiance x sr (the environment's radiance units times steradians)"},
                            {"range", {0.0, "unbounded (HDR: a sun is ~1e4 x the sky)"}},
                            {"from_lighting_file", "flux * (1 + cos(alpha)) / 2 per channel"}});
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
                            {"range", {0.0, 1.0}}});
    }
    if (mat.has_normal_texture()) {
        textures.push_back({{"uniform", "u_normal_texture"}, {"unit", unit++}, {"internal_format", "RGBA8"}, {"format", "RGBA"},
                            {"type", "UNSIGNED_BYTE"}, {"width", mat.normal_texture_px.x()}, {"height", mat.normal_texture_px.y()},
                            {"filter", "NEAREST"}, {"wrap", "CLAMP_TO_EDGE"}, {"color_space", "data"},
                            {"meaning", "tangent-space normal map, n = 2 rgb - 1"}, {"range", {0.0, 1.0}}});
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
                      {"texel_of", p.layout == TableLayout::kUniformArray || !p.wrapped
                                       ? "x = i2 * texels_per_node + k / 4, y = channel * rows + i1, component k % 4 (= linear texel i = ((channel * rows + i1) * cols + i2) * texels_per_node + k / 4 in rows of width)"
                                       : "i = ((channel * rows + i1) * cols + i2) * texels_per_node + k / 4, x = i % width, y = i / width, component k % 4 (rows of GL_MAX_TEXTURE_SIZE: the natural rows do not fit)"},
                      {"wrapped", p.wrapped},
                      {"units", "dimensionless (reflected radiance per unit lighting coefficient)"},
                      {"value_range", {lo, hi}}};
        if (p.layout == TableLayout::kUniformArray) {
            uniforms.push_back({{"name", "u_brdf"}, {"type", "vec4"}, {"count", e.data_width}, {"stage", "fragment"},
                                {"meaning", "BRDF SH table, texel y * width + x of the texture layout"}, {"file", e.name + ".brdf.bin"},
                                {"range", {lo, hi}}});
        } else {
            const bool rgba8 = p.layout == TableLayout::kRgba8Texture;
            textures.push_back({{"uniform", "u_brdf_texture"}, {"unit", unit++},
                                {"internal_format", rgba8 ? "RGBA" : "RGBA32F"}, {"format", "RGBA"},
                                {"type", rgba8 ? "UNSIGNED_BYTE" : "FLOAT"}, {"width", e.data_width}, {"height", e.data_height},
                                {"filter", "NEAREST"}, {"wrap", "CLAMP_TO_EDGE"}, {"color_space", "data"},
                                {"file", e.name + ".brdf.bin"}, {"meaning", "BRDF SH table"},
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
                                {"meaning", "per coefficient k (component k of the array): value = offset + scale * texel"},
                                {"values", e.table_scale}});
            uniforms.push_back({{"name", "u_brdf_offset"}, {"type", "vec4"}, {"count", p.texels_per_node}, {"stage", "fragment"},
                                {"values", e.table_offset}});
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
                  {"updated", "whenever the lighting changes (device rotation): re-pack and re-upload"}};
        if (rgba8) t["quantization_max_abs_error"] = "scale_k / 131070 per coefficient (16 bits), scale_k the spread of L_k over R, G, B";
        textures.push_back(t);
    }
    m["lighting_layout"] = to_string(p.lighting);
    m["uniforms"] = uniforms;
    m["textures"] = textures;
    int max_side = std::max(mat.albedo_texture_px.maxCoeff(), mat.normal_texture_px.maxCoeff());
    if (p.table && p.layout != TableLayout::kUniformArray) max_side = std::max({max_side, e.data_width, e.data_height});
    if (p.lighting != LightingLayout::kUniformArray) max_side = std::max(max_side, sh::count(p.v->sh_bands));
    json ext = json::array();
    if (!es3 && p.v->precision == Precision::kHighp) ext.push_back("GL_FRAGMENT_PRECISION_HIGH (highp in fragment shaders)");
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
                   {"framebuffer", "RGBA32F (EXT_color_buffer_float) keeps HDR radiance; an 8-bit target clamps to [0, 1]"}};
    m["precision"] = {{"declared", to_string(p.v->precision)}, {"safe", "highp"},
                      {"mediump", "unsafe for float output: mediump guarantees a 10-bit mantissa (relative step 2^-10 = 9.8e-4, "
                                  "the whole 1e-3 budget before any arithmetic) and magnitudes below 2^14; the SH sums cancel "
                                  "terms of either sign, so their error is a multiple of that step (measured in docs/gles.md)"}};
    return m;
}

}  // namespace

namespace {
void pack_f32(float v, uint8_t* out);
}  // namespace

Export export_variant(const brdf::Table* table, const MaterialInputs& mat, const Variant& v,
                      const Limits& limits) {
    if (!std::regex_match(mat.name, std::regex("[A-Za-z0-9_.-]+"))) {
        throw UsageError(str("GLES export: material name '", mat.name,
                             "' must be letters, digits, '_', '.' or '-'"));
    }
    Export e;
    e.variant = v;
    e.material = mat.name;
    e.name = str(mat.name, "-es", to_string(v.version), "-", to_string(v.mode), "-b", v.sh_bands,
                 v.lights > 0 ? str("-l", v.lights) : std::string(), "-", to_string(v.precision));
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
    e.vertex_source = vertex_source(p, e.name);
    e.fragment_source = fragment_source(p, e.name);
    e.manifest = make_manifest(e, p, limits);
    return e;
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

LightUniforms light_uniforms(const envmap::DirectionalLight& light) {
    const double a = light.angular_radius;
    const Eigen::Vector3d d = light.direction.normalized();
    LightUniforms u;
    // Below 1e-4 rad envmap::light_irradiance takes the point limit: sin alpha = 0 selects it.
    u.direction_sin << d.cast<float>(), static_cast<float>(a < 1e-4 ? 0.0 : std::sin(a));
    u.normal_irradiance = (light.flux * (0.5 * (1.0 + std::cos(a)))).cast<float>();
    return u;
}

LightUniformArrays light_uniform_arrays(const std::vector<envmap::DirectionalLight>& lights) {
    LightUniformArrays a;
    for (const auto& l : lights) {
        const LightUniforms u = light_uniforms(l);
        a.direction_sin.insert(a.direction_sin.end(), u.direction_sin.data(), u.direction_sin.data() + 4);
        a.normal_irradiance.insert(a.normal_irradiance.end(), u.normal_irradiance.data(),
                                   u.normal_irradiance.data() + 3);
    }
    return a;
}

envmap::LightShading common_light_shading(const std::vector<envmap::DirectionalLight>& lights) {
    if (lights.empty()) return envmap::LightShading::kCap;
    for (const envmap::DirectionalLight& l : lights) {
        if (l.shading != lights.front().shading) {
            throw UsageError(str("GLES export: the lighting file mixes light irradiance formulas (",
                                 envmap::to_string(lights.front().shading), " and ",
                                 envmap::to_string(l.shading),
                                 "); a variant shades all its lights with one"));
        }
    }
    return lights.front().shading;
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
                                               common_light_shading(set.lights)},
                                              export_limits(set, version));
                    if (lights > 0) {  // the values the app binds for these lights
                        const LightUniformArrays a = light_uniform_arrays(set.lights);
                        for (auto& u : e.manifest["uniforms"]) {
                            if (u["name"] == "u_light_direction") u["values"] = a.direction_sin;
                            if (u["name"] == "u_light_irradiance") u["values"] = a.normal_irradiance;
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
        for (const auto& [name, bytes] : export_files(e)) {
            paths.push_back(dir + "/" + name);
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
    return files;
}

}  // namespace inlight::gles
