// gles/export_lights.cpp: the dominant lights in the exported shaders: their GLSL functions
// and the uniforms an app sets per light (export.h).
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

}  // namespace inlight::gles::detail

namespace inlight::gles {

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

}  // namespace inlight::gles
