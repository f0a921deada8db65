#include "brdf/glsl.h"

#include <cstdio>
#include <sstream>

#include "core/check.h"

namespace inlight::brdf {

std::string glsl_float(float f) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.9g", static_cast<double>(f));
    std::string s = buf;
    if (s.find_first_of(".eE") == std::string::npos) s += ".0";
    return s;
}

std::string glsl_atan2_source() {
    // GLSL's acos() and atan() carry no accuracy requirement and some drivers approximate
    // them coarsely (llvmpipe: ~1e-3 rad, 0.5% of a table value between nodes). This
    // atan2 is Cephes' atanf (range reduction to |t| <= tan(pi/8), odd polynomial;
    // ~1e-7 relative) from +, *, / and comparisons only, which GLSL computes to float.
    std::ostringstream o;
    o << "// atan(y, x) to float accuracy for (x, y) != (0, 0) (Cephes atanf).\n"
      << "float atan2_f32(float y, float x) {\n"
      << "    float ax = abs(x);\n    float ay = abs(y);\n"
      << "    float t = min(ax, ay) / max(ax, ay);\n"
      << "    float base = 0.0;\n"
      << "    if (t > 0.414213562) { base = 0.785398163; t = (t - 1.0) / (t + 1.0); }\n"
      << "    float z = t * t;\n"
      << "    float a = base + ((((0.0805374449538 * z - 0.138776856032) * z + "
         "0.199777106478) * z\n"
      << "                       - 0.333329491539) * z * t + t);\n"
      << "    if (ay > ax) a = 1.57079633 - a;\n"
      << "    if (x < 0.0) a = 3.14159265 - a;\n"
      << "    return y < 0.0 ? -a : a;\n}\n";
    return o.str();
}

bool glsl_grid_coord_has_atan2(const Grid& g) {
    return g.kind == GridKind::kReport5x5 || g.kind == GridKind::kThetaPhi;
}

std::string glsl_grid_coord_source(const Grid& g, int glsl_version) {
    INLIGHT_CHECK(glsl_version == 100 || glsl_version == 300) << "GLSL ES version " << glsl_version;
    std::ostringstream o;
    if (glsl_grid_coord_has_atan2(g)) {
        o << glsl_atan2_source();
    }
    o << "// Cell (r0, r1, c0, c1) and fractions (toward r1, toward c1) of normal n.\n"
      << "void brdf_grid_coord(vec3 n, out ivec4 cell, out vec2 f) {\n"
      << "    vec3 m = normalize(n);\n";
    const std::string last_r = glsl_float(static_cast<float>(g.rows - 1));
    const std::string last_c = glsl_float(static_cast<float>(g.cols - 1));
    bool wrap = false;
    switch (g.kind) {
        case GridKind::kReport5x5:
            o << "    // The report's signed-theta grid; atan(y, x) keeps the quadrant, and phi "
                 "outside\n"
              << "    // [-pi/2, pi/2] folds to phi -+ pi with theta negated (the same normal).\n"
              << "    float theta = atan2_f32(sqrt(m.x * m.x + m.y * m.y), m.z);  // acos(m.z)\n"
              << "    float phi = (abs(m.x) + abs(m.y) > 0.0) ? atan2_f32(m.y, m.x) : 0.0;  // "
                 "atan(0,0) is undefined\n"
              << "    if (phi > " << glsl_float(1.57079633f) << ") { phi -= " << glsl_float(3.14159265f)
              << "; theta = -theta; }\n"
              << "    else if (phi < -" << glsl_float(1.57079633f) << ") { phi += " << glsl_float(3.14159265f)
              << "; theta = -theta; }\n"
              << "    float r = clamp(theta * " << glsl_float(1.27323954f) << " + 2.0, 0.0, 4.0);\n"
              << "    float c = clamp(phi * " << glsl_float(1.27323954f) << " + 2.0, 0.0, 4.0);\n";
            break;
        case GridKind::kThetaPhi:
            wrap = true;
            o << "    float theta = atan2_f32(sqrt(m.x * m.x + m.y * m.y), m.z);  // acos(m.z)\n"
              << "    float phi = (abs(m.x) + abs(m.y) > 0.0) ? atan2_f32(m.y, m.x) : 0.0;  // "
                 "atan(0,0) is undefined\n"
              << "    if (phi < 0.0) phi += " << glsl_float(6.28318531f) << ";\n"
              << "    float r = clamp(theta * "
              << glsl_float(static_cast<float>(g.rows - 1) / static_cast<float>(g.theta_max)) << ", 0.0, "
              << last_r << ");\n"
              << "    float c = phi * " << glsl_float(static_cast<float>(g.cols) / 6.28318531f) << ";\n";
            break;
        case GridKind::kOcta:
            o << "    float z = max(m.z, 0.0);\n"
              << "    float d = max(abs(m.x) + abs(m.y) + z, 1e-20);\n"
              << "    float px = m.x / d;\n    float py = m.y / d;\n"
              << "    float u = px + py;\n    float v = px - py;\n"
              << "    float c = clamp((u * 0.5 + 0.5) * " << last_c << ", 0.0, " << last_c << ");\n"
              << "    float r = clamp((v * 0.5 + 0.5) * " << last_r << ", 0.0, " << last_r
              << ");\n";
            break;
        case GridKind::kDisk:
            o << "    float u = m.x;\n    float v = m.y;\n"
              << "    if (m.z < 0.0) {  // below the horizon: the horizon normal of the same "
                 "azimuth\n"
              << "        float q = max(sqrt(m.x * m.x + m.y * m.y), 1e-20);\n"
              << "        u = m.x / q;\n        v = m.y / q;\n    }\n"
              << "    float c = clamp((u * 0.5 + 0.5) * " << last_c << ", 0.0, " << last_c << ");\n"
              << "    float r = clamp((v * 0.5 + 0.5) * " << last_r << ", 0.0, " << last_r
              << ");\n";
            break;
    }
    o << "    float rf = floor(r);\n    float cf = floor(c);\n    int r0 = int(rf);\n";
    if (glsl_version == 100) {
        // GLSL ES 1.00 has neither integer % nor integer min(); cf >= 0 and small, so float
        // mod of an integral value is exact.
        o << "    int r1 = r0 + 1 < BRDF_ROWS ? r0 + 1 : BRDF_ROWS - 1;\n";
        if (wrap) {
            o << "    int c0 = int(mod(cf, float(BRDF_COLS)));  // phi is periodic: the last "
                 "column wraps to 0\n"
              << "    int c1 = c0 + 1 == BRDF_COLS ? 0 : c0 + 1;\n";
        } else {
            o << "    int c0 = int(cf);\n    int c1 = c0 + 1 < BRDF_COLS ? c0 + 1 : BRDF_COLS - 1;\n";
        }
    } else {
        o << "    int r1 = min(r0 + 1, BRDF_ROWS - 1);\n";
        if (wrap) {
            o << "    int c0 = int(cf) % BRDF_COLS;  // phi is periodic: the last column wraps to "
                 "0\n"
              << "    int c1 = (c0 + 1) % BRDF_COLS;\n";
        } else {
            o << "    int c0 = int(cf);\n    int c1 = min(c0 + 1, BRDF_COLS - 1);\n";
        }
    }
    o << "    cell = ivec4(r0, r1, c0, c1);\n    f = vec2(r - rf, c - cf);\n}\n";

    return o.str();
}

std::string glsl_lookup_source(const Table& t) {
    const Grid& g = t.grid;
    std::ostringstream o;
    o << "// brdf-sh-bake lookup, GLSL ES 3.0. Grid " << to_string(g) << ", " << t.sh_bands
      << " SH bands (" << t.coeff_count() << " coefficients), " << t.channels << " channel(s).\n"
      << "// Normals in the device frame (+z toward the viewer). Real SH without Condon-Shortley\n"
      << "// phase, index l*(l+1)+m. Reflected radiance = sum_k L_k * coeffs[k] per channel.\n"
      << "precision highp float;\nprecision highp int;\n\n"
      << "const int BRDF_ROWS = " << g.rows << ";\n"
      << "const int BRDF_COLS = " << g.cols << ";\n"
      << "const int BRDF_NCOEFFS = " << t.coeff_count() << ";\n"
      << "const int BRDF_CHANNELS = " << t.channels << ";\n"
      << "const int BRDF_TEXELS_PER_NODE = " << (t.coeff_count() + 3) / 4 << ";\n\n"
      << "#ifdef BRDF_USE_TEXTURE\n"
      << "// RGBA32F, width BRDF_COLS * BRDF_TEXELS_PER_NODE, height BRDF_CHANNELS * BRDF_ROWS;\n"
      << "// texel (i2 * BRDF_TEXELS_PER_NODE + k / 4, channel * BRDF_ROWS + i1), component k % "
         "4.\n"
      << "uniform highp sampler2D u_brdf_texture;\n"
      << "float brdf_fetch(int ch, int i1, int i2, int k) {\n"
      << "    vec4 t = texelFetch(u_brdf_texture, ivec2(i2 * BRDF_TEXELS_PER_NODE + k / 4,"
         " ch * BRDF_ROWS + i1), 0);\n"
      << "    return t[k % 4];\n}\n"
      << "#else\n"
      << "// index ((channel * BRDF_ROWS + i1) * BRDF_COLS + i2) * BRDF_NCOEFFS + k\n"
      << "uniform float u_brdf_coeffs[BRDF_CHANNELS * BRDF_ROWS * BRDF_COLS * BRDF_NCOEFFS];\n"
      << "float brdf_fetch(int ch, int i1, int i2, int k) {\n"
      << "    return u_brdf_coeffs[((ch * BRDF_ROWS + i1) * BRDF_COLS + i2) * BRDF_NCOEFFS + "
         "k];\n}\n"
      << "#endif\n\n";

    o << glsl_grid_coord_source(g, 300) << "\n";

    o << "// Bilinearly interpolated SH coefficients of the cosine-weighted lobe at normal n.\n"
      << "void brdf_sh_lookup(vec3 n, int ch, out float coeffs[BRDF_NCOEFFS]) {\n"
      << "    ivec4 cell;\n    vec2 f;\n    brdf_grid_coord(n, cell, f);\n"
      << "    for (int k = 0; k < BRDF_NCOEFFS; ++k) {\n"
      << "        coeffs[k] = mix(mix(brdf_fetch(ch, cell.x, cell.z, k), brdf_fetch(ch, cell.x, "
         "cell.w, k), f.y),\n"
      << "                        mix(brdf_fetch(ch, cell.y, cell.z, k), brdf_fetch(ch, cell.y, "
         "cell.w, k), f.y),\n"
      << "                        f.x);\n"
      << "    }\n}\n";
    return o.str();
}

}  // namespace inlight::brdf
