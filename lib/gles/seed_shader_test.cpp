// The seed mode is the inlight report's shader (section 2.6, Snippet 3 and the basis of its
// Figure 6), written out here from the report's text, independently of the exporter and the CPU
// model: the exported seed variant must compute it, slips included, on the driver.
#include "gles/harness.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <iostream>
#include <random>

#include "gles/harness_testing.h"

namespace inlight::gles {
namespace {

using namespace harness_testing;

// ---- The inlight report's shader written out from its text (section 2.6: Snippet 3 and the
// basis of its Figure 6), independently of the exporter and of the CPU model. ----

/// Figure 6's basis as printed, signs included (the Condon-Shortley phase: Y_1,1 = -0.4886 x).
std::array<double, 9> report_figure6_basis(const Eigen::Vector3d& d) {
    const double x = d.x(), y = d.y(), z = d.z();
    return {0.282095,          -0.488603 * y,           0.488603 * z,
            -0.488603 * x,     1.092548 * x * y,        -1.092548 * y * z,
            0.315392 * (3 * z * z - 1), -1.092548 * z * x, 0.546274 * (x * x - y * y)};
}

/// Per coefficient, the report's basis function over inlight's (sh/sh.h): +1 or -1, at a
/// direction where none vanishes. The report projects lighting and BRDF with its own basis, so
/// its L_k and B_k are inlight's times this.
std::array<double, 9> report_phase() {
    const Eigen::Vector3d d = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
    const std::array<double, 9> r = report_figure6_basis(d);
    const std::vector<double> y = sh::eval(3, d);
    std::array<double, 9> phase{};
    for (int k = 0; k < 9; ++k) {
        phase[k] = std::round(r[k] / y[k]);
        EXPECT_NEAR(r[k] / y[k], phase[k], 1e-5) << k;  // Figure 6 prints 6 digits
    }
    return phase;
}

/// Snippet 3's getBRDF on the report's 5 x 5 table (`b225[45 i1 + 9 i2 + k]`, brdfIndex):
/// cart2sph (theta = acos(z / |n|), phi = atan(y / x), not atan2), sph2index (angle x 4 / pi +
/// 2), corners by floor and ceil, mixed as written. The angles in float, as the shader's (its pi
/// = 3.14159265358 rounds to float pi, above pi: in double the horizon's index would be
/// 4 + 4e-12 and its ceil 5, off the grid). NaN where cart2sph divides 0 by 0 or off the grid.
std::array<double, 9> report_get_brdf(const std::vector<double>& b225, const Eigen::Vector3d& n) {
    const float pi = 3.14159265358f;  // as in sph2index
    const Eigen::Vector3f nf = n.cast<float>();
    const float sx = std::acos(nf.z() / nf.norm()), sy = std::atan(nf.y() / nf.x());
    const double ix = sx * (4.0f / pi) + 2.0f, iy = sy * (4.0f / pi) + 2.0f;
    std::array<double, 9> b;
    b.fill(std::numeric_limits<double>::quiet_NaN());
    if (!std::isfinite(ix) || !std::isfinite(iy)) return b;
    const int fx = static_cast<int>(std::floor(ix)), cx = static_cast<int>(std::ceil(ix));
    const int fy = static_cast<int>(std::floor(iy)), cy = static_cast<int>(std::ceil(iy));
    if (fx < 0 || fy < 0 || cx > 4 || cy > 4) return b;
    const double h = ix - std::floor(ix), v = iy - std::floor(iy);
    auto at = [&](int i1, int i2, int k) { return b225[45 * i1 + 9 * i2 + k]; };
    auto mix = [](double a, double c, double t) { return a * (1 - t) + c * t; };
    for (int k = 0; k < 9; ++k) {
        b[k] = mix(mix(at(fx, fy, k), at(cx, fy, k), h), mix(at(fx, cy, k), at(cx, cy, k), h), v);
    }
    return b;
}

/// Snippet 3's main() for one fragment: u_IrradianceMatrix[c] = R&H's matrix (eq. 12) of the
/// coefficients `l` (9 x 3), the texture = `albedo`, `brdf` null = no specular.
Eigen::Vector3d report_shader(const Eigen::Vector3d& n, const Eigen::Vector3d& albedo,
                              const Eigen::MatrixXd& l, const std::array<double, 9>* brdf) {
    const Eigen::Vector4d n4(n.x(), n.y(), n.z(), 1.0);
    Eigen::Vector3d spec = Eigen::Vector3d::Zero(), irr;
    for (int band = 0; band < 3; ++band) {
        const Eigen::VectorXd lc = l.col(band);
        const Eigen::Matrix4d u = sh::irradiance_matrix(lc.data());
        irr[band] = n4.dot(u * n4);
        if (!brdf) continue;
        const std::array<double, 9>& b = *brdf;
        const double c5l20 = (u(2, 2) / 0.743125) * 0.247708;
        const double c4l00 = u(3, 3) + c5l20;
        Eigen::Matrix4d m;
        m << u(0, 0) * b[8], u(0, 1) * b[4], u(0, 2) * b[7], u(0, 3) * b[3],  //
            u(1, 0) * b[4], u(1, 1) * b[8], u(1, 2) * b[5], u(1, 3) * b[1],   //
            u(2, 0) * b[7], u(2, 1) * b[5], u(2, 2) * b[6], u(2, 3) * b[2],   //
            u(3, 0) * b[3], u(3, 1) * b[1], u(3, 2) * b[2], c4l00 * b[0] - c5l20 * b[6];
        spec[band] = n4.dot(m * n4) * 0.05;
    }
    const double mean = irr.sum() / 3.0;
    return albedo * (mean * 0.3) + spec;
}

// The seed variants are the report's shader as written, slips included, and the
// consistent ones are fixed. The report (1) looks its BRDF up at phi = atan(y/x), which loses
// the quadrant, and (2) projects with Figure 6's basis (Condon-Shortley phase) while its
// irradiance matrix (R&H eq. 12) assumes none. On the report's own 5 x 5 grid, normals in all
// four quadrants, the axes and the pole: the driver's seed output equals the report's formula
// above (computed from the report's coefficients, inlight's times the phase), and it differs
// from the slip-free formula exactly where the report's formula does: the specular part (albedo
// 0) only at x < 0, the diffuse part (no table) everywhere but where E(x, y, z) = E(-x, -y, z).
TEST(GlesHarness, SeedIsTheReportShaderWithItsSlips) {
    const brdf::Table t = smooth_table("report5x5", 3, 1, 21);
    const std::array<double, 9> phase = report_phase();
    const Eigen::MatrixXd sh = lighting(3, 22);
    Eigen::MatrixXd sh_report = sh;
    for (int k = 0; k < 9; ++k) sh_report.row(k) *= phase[k];
    const std::vector<Eigen::Vector3d> normals = probe_normals(t.grid, kWidth * kHeight, 23);
    ASSERT_EQ(normals[0], Eigen::Vector3d::UnitZ());
    // At the pole cart2sph divides 0 by 0: the report's shader is undefined there (NaN here).
    // Its limit from every side is the pole's value (row 2 of the grid is five copies of the
    // pole), which the seed shader takes: the reference there is the formula just beside it.
    const Eigen::Vector3d beside_pole = Eigen::Vector3d(1e-9, 0, 1).normalized();

    struct Part {
        const char* what;
        bool table;
        Eigen::Vector3d albedo;
    };
    for (const Part& part : {Part{"whole shader", true, {0.8, 0.6, 0.5}},
                             Part{"specular only (albedo 0)", true, {0, 0, 0}},
                             Part{"diffuse only (no table)", false, {1, 1, 1}}}) {
        for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
            Context& ctx = ver == GlslVersion::kEs300 ? context3() : context2();
            if (!ctx.info().float_color_buffer) GTEST_SKIP() << "no float colour buffer";
            const Variant v{ver, ShaderMode::kSeed, 3, Precision::kHighp};
            const Export e = export_variant(part.table ? &t : nullptr, MaterialInputs{}, v,
                                            ctx.info().limits);
            // The report's table: the table as bound (ES 1.00: RGBA8-dequantised) times the
            // phase, in brdfIndex order.
            const brdf::Table& tb = part.table ? *e.table_as_bound : t;
            std::vector<double> b225(225);
            for (int i1 = 0; i1 < 5; ++i1) {
                for (int i2 = 0; i2 < 5; ++i2) {
                    for (int k = 0; k < 9; ++k) {
                        b225[45 * i1 + 9 * i2 + k] = tb.at(0, i1, i2, k) * phase[k];
                    }
                }
            }
            EXPECT_TRUE(std::isnan(report_get_brdf(b225, normals[0])[0]));
            // The report's formula, and the same formula without the two slips (inlight's
            // phase, brdf::lookup's atan2).
            std::vector<Eigen::Vector3d> report(normals.size()), fixed(normals.size());
            std::vector<double> magnitudes;
            for (size_t i = 0; i < normals.size(); ++i) {
                const Eigen::Vector3d& n = normals[i];
                const std::array<double, 9> b_report = report_get_brdf(b225, i == 0 ? beside_pole : n);
                float bf[9];
                brdf::lookup(tb, n.cast<float>(), 0, bf);
                std::array<double, 9> b_fixed;
                std::copy(bf, bf + 9, b_fixed.begin());
                report[i] = report_shader(n, part.albedo, sh_report, part.table ? &b_report : nullptr);
                fixed[i] = report_shader(n, part.albedo, sh, part.table ? &b_fixed : nullptr);
                for (int c = 0; c < 3; ++c) magnitudes.push_back(std::abs(report[i][c]));
            }
            std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                             magnitudes.end());
            const double floor = kFloorFractionOfMedian * magnitudes[magnitudes.size() / 2];
            auto rel = [floor](const Eigen::Vector3d& got, const Eigen::Vector3d& want) {
                double r = 0;
                for (int c = 0; c < 3; ++c) {
                    r = std::max(r, std::abs(got[c] - want[c]) / std::max(std::abs(want[c]), floor));
                }
                return r;
            };
            Bindings bind;
            bind.sh = sh;
            bind.albedo = part.albedo.cast<float>();
            const Readback gpu = draw(ctx, e, bind, probe_mesh(normals, Eigen::Vector3d::UnitX()),
                                      kWidth, kHeight, TargetFormat::kRgba32f);
            int pass = 0, shown = 0, predicted = 0, agree = 0, decided = 0;
            int quadrant_shown[4] = {0, 0, 0, 0};  // I (x > 0, y >= 0), II, III, IV
            double worst = 0;
            for (int y = 0; y < kHeight; ++y) {
                for (int x = 0; x < kWidth; ++x) {
                    const size_t i = static_cast<size_t>(y) * kWidth + x;
                    const Eigen::Vector3d got(gpu.at(x, y, 0), gpu.at(x, y, 1), gpu.at(x, y, 2));
                    const double r = rel(got, report[i]);
                    worst = std::max(worst, r);
                    if (!(r <= kRelTolerance)) {
                        std::cout << "[gles] off at normal " << normals[i].transpose() << ": "
                                  << got.transpose() << " vs " << report[i].transpose() << "\n";
                    }
                    pass += r <= kRelTolerance ? 1 : 0;
                    // Where the report's formula differs from the slip-free one by > 10x the
                    // tolerance, the driver's must differ by > 5x (it is within 1x of the
                    // report's); where they are equal (< 0.1x), the driver's must be within 2x.
                    const double pr = rel(report[i], fixed[i]), g = rel(got, fixed[i]);
                    if (pr > 10 * kRelTolerance) {
                        ++decided;
                        ++predicted;
                        if (g > 5 * kRelTolerance) {
                            ++agree;
                            ++shown;
                            const Eigen::Vector3d& n = normals[i];
                            ++quadrant_shown[n.x() > 0 ? (n.y() >= 0 ? 0 : 3) : (n.y() > 0 ? 1 : 2)];
                        }
                    } else if (pr < 0.1 * kRelTolerance) {
                        ++decided;
                        agree += g <= 2 * kRelTolerance ? 1 : 0;
                    }
                }
            }
            const std::string what = str(e.name, ", ", part.what, " on ", ctx.info().renderer);
            EXPECT_GE(pass / static_cast<double>(kWidth * kHeight), kMinPassFraction)
                << what << ": against the report's formula, worst relative " << worst;
            EXPECT_EQ(agree, decided) << what;
            EXPECT_GT(predicted, 0) << what;
            if (part.albedo.isZero()) {
                // The quadrant loss alone: the slip shows exactly at x < 0.
                EXPECT_EQ(quadrant_shown[0] + quadrant_shown[3], 0) << what;
                EXPECT_GT(quadrant_shown[1], 0) << what;
                EXPECT_GT(quadrant_shown[2], 0) << what;
            }
            std::cout << "[gles] " << what << ": " << pass * 100.0 / (kWidth * kHeight)
                      << "% within 1e-3 of the report's formula (worst " << worst
                      << "); differs from the slip-free formula at " << shown << " of "
                      << predicted << " predicted pixels (quadrants I-IV: " << quadrant_shown[0]
                      << ", " << quadrant_shown[1] << ", " << quadrant_shown[2] << ", "
                      << quadrant_shown[3] << "), " << agree << " of " << decided
                      << " pixels classified alike\n";
        }
    }
    // The consistent variants at the same normals are the CPU model (no slip).
    for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        Context& ctx = ver == GlslVersion::kEs300 ? context3() : context2();
        const Variant v{ver, ShaderMode::kConsistent, 3, Precision::kHighp};
        const Export e = export_variant(&t, MaterialInputs{}, v, ctx.info().limits);
        const Outcome f = compare(ctx, e, v, Case{"report5x5", 3, 1, false}, sh, TargetFormat::kRgba32f);
        EXPECT_GE(f.pass_fraction, kMinPassFraction) << e.name << ": worst " << f.worst;
    }
}

// The lookup snippet brdf-sh-bake ships (brdf/glsl.h, both its uniform-array and its
// texture path) computes brdf::lookup() on a real driver, at the nodes, cell centres, the
// thetaphi seam and pole and the report grid's folds.
TEST(BrdfGlslSnippet, EqualsLookupAtNodesSeamsAndPoles) {
    for (const Case& s : cases()) {
        if (s.textured) continue;
        const brdf::Table t = smooth_table(s.grid, 3, s.channels, 5);
        const std::vector<Eigen::Vector3d> normals =
            probe_normals(t.grid, kWidth * kHeight, 14);
        const Mesh mesh = probe_mesh(normals, Eigen::Vector3d::UnitX());
        const float range = *std::max_element(t.coeffs.begin(), t.coeffs.end()) -
                            *std::min_element(t.coeffs.begin(), t.coeffs.end());
        // Equal but for float rounding: atan2_f32 and libm differ by ~1e-7 relative, moving
        // the fractions by ~1e-6 of a cell, times at most the table's range per cell.
        const double tolerance = 1e-5 * range;
        for (bool use_texture : {false, true}) {
            for (int ch = 0; ch < t.channels; ++ch) {
                for (int k0 = 0; k0 < t.coeff_count(); k0 += 4) {
                    Export e;
                    e.name = str("lookup snippet ", s.grid, use_texture ? " texture" : " uniform");
                    e.vertex_source =
                        "#version 300 es\nin vec3 a_position;\nin vec3 a_normal;\nout vec3 "
                        "v_normal;\nvoid main() {\n    v_normal = a_normal;\n    gl_Position = "
                        "vec4(a_position, 1.0);\n}\n";
                    std::string out = "vec4(";
                    for (int i = 0; i < 4; ++i) {
                        out += i ? ", " : "";
                        out += k0 + i < t.coeff_count() ? str("c[", k0 + i, "]") : "0.0";
                    }
                    e.fragment_source =
                        str("#version 300 es\n", use_texture ? "#define BRDF_USE_TEXTURE\n" : "",
                            brdf::glsl_lookup_source(t),
                            "in vec3 v_normal;\nout vec4 o_value;\nvoid main() {\n"
                            "    float c[BRDF_NCOEFFS];\n    brdf_sh_lookup(v_normal, ",
                            ch, ", c);\n    o_value = ", out, ");\n}\n");
                    e.manifest["variant"] = {{"glsl_version", "300 es"}, {"sh_bands", 1}};
                    e.manifest["textures"] = nlohmann::json::array();
                    Bindings b;
                    b.sh = Eigen::MatrixXd::Zero(1, 3);
                    if (use_texture) {
                        e.manifest["textures"].push_back({{"uniform", "u_brdf_texture"}, {"unit", 0}});
                        e.table_layout = TableLayout::kFloatTexture;
                        e.table_texels = brdf::texture_texels(t);
                        const Eigen::Vector2i size = brdf::texture_size(t);
                        e.data_width = size.x();
                        e.data_height = size.y();
                    } else {
                        b.float_arrays.emplace_back("u_brdf_coeffs", t.coeffs);
                    }
                    const Readback gpu = draw(context3(), e, b, mesh, kWidth, kHeight,
                                              TargetFormat::kRgba32f);
                    double worst = 0;
                    for (int y = 0; y < kHeight; ++y) {
                        for (int x = 0; x < kWidth; ++x) {
                            float want[16];
                            brdf::lookup(t, normals[y * kWidth + x].cast<float>(), ch, want);
                            for (int i = 0; i < 4 && k0 + i < t.coeff_count(); ++i) {
                                const double d = std::abs(gpu.at(x, y, i) - want[k0 + i]);
                                worst = std::max(worst, d);
                                ASSERT_LE(d, tolerance)
                                    << e.name << " channel " << ch << " k " << k0 + i
                                    << " at normal " << normals[y * kWidth + x].transpose();
                            }
                        }
                    }
                    std::cout << "[gles] " << e.name << " ch " << ch << " k " << k0
                              << "..: worst |GLSL - lookup()| " << worst << "\n";
                }
            }
        }
    }
}

}  // namespace
}  // namespace inlight::gles
