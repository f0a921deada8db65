// Tests of the GLES exporter without a GPU: every variant passes the Khronos reference compiler
// (glslangValidator) for its GLSL ES version, declares nothing it does not use, picks its data
// layout from the limits given and refuses what does not fit.
#include "gles/export.h"
#include "image/image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <random>
#include <regex>
#include <set>

#include "core/conventions.h"
#include "core/error.h"
#include "image/color.h"
#include "render/mip.h"
#include "sh/sh.h"
#include "gles/gles_testing.h"
#include "testing/testing.h"

namespace inlight::gles {
namespace {

using testing::all_variants;
using testing::random_table;
using testing::roomy_limits;
using testing::GlslangBatch;

struct Case {
    std::string grid;
    int bands;
    int channels;
    MaterialInputs mat;
};

std::vector<Case> cases() {
    MaterialInputs plain;
    plain.name = "plain";
    MaterialInputs textured;
    textured.name = "textured";
    textured.albedo_texture_px = {16, 8};
    textured.normal_texture_px = {8, 8};
    textured.brdf.specular = brdf::Model::kCharlie;  // the lights' lobe of each model
    MaterialInputs albedo_only;
    albedo_only.name = "albedo";
    albedo_only.albedo_texture_px = {5, 3};
    albedo_only.brdf.specular = brdf::Model::kCookTorranceReport;
    return {{"thetaphi:5x8", 4, 1, plain},
            {"octa:5", 4, 3, textured},
            {"report5x5", 3, 1, albedo_only},
            {"disk:4", 5, 1, textured},
            {"octa:4", 6, 1, plain}};  // ES 1.00 above 5 bands
}

/// The limits each test exports against: the driver-sized ones (everything in uniforms where
/// it may be) and two at 16 vectors, which move the lighting and the ES 1.00 table's
/// scale/offset into textures, with 64 and 24 texels per side (24 wraps the wider tables on both
/// versions). A variant these cannot hold is refused (Error) and skipped.
std::vector<Limits> test_limits() {
    Limits tight = roomy_limits();
    tight.max_fragment_uniform_vectors = 16;
    tight.max_texture_size = 64;
    Limits tighter = tight;
    tighter.max_texture_size = 24;
    return {roomy_limits(), tight, tighter};
}

/// all_variants plus consistent variants with 1 and 3 dominant lights (both versions and
/// precisions, 3 bands) and, for a textured material, trilinear variants of both modes.
std::vector<Variant> variants_with_lights(int bands, const MaterialInputs& mat) {
    const bool textured = mat.has_albedo_texture() || mat.has_normal_texture();
    std::vector<Variant> out = all_variants(bands);
    for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        for (Precision prec : {Precision::kHighp, Precision::kMediump}) {
            for (int lights : {1, 3}) out.push_back({ver, ShaderMode::kConsistent, 3, prec, lights});
            // The trilinear texture filter (the same code as bilinear without textures).
            for (ShaderMode mode : {ShaderMode::kConsistent, ShaderMode::kSeed}) {
                if (!textured) break;
                out.push_back({ver, mode, 3, prec, mode == ShaderMode::kSeed ? 0 : 1,
                               envmap::LightShading::kCap, TextureFilter::kTrilinear});
            }
        }
    }
    return out;
}

TEST(ExportVariant, EveryVariantPassesGlslangValidator) {
    ASSERT_EQ(std::system("glslangValidator --version > /dev/null 2>&1"), 0)
        << "glslangValidator (Debian glslang-tools, in make deps) is required";
    const std::string dir = inlight::testing::temp_dir("gles_glslang");
    GlslangBatch batch(dir);
    int checked = 0, wrapped = 0, scale_in_texture = 0;
    const std::vector<Case> all = cases();
    for (const Case& c : all) {
        const brdf::Table table = random_table(c.grid, c.bands, c.channels, 1);
        for (const Variant& v : variants_with_lights(c.bands, c.mat)) {
            // Lambert (no table) for the first case only: its code is a subset of the others'.
            std::vector<const brdf::Table*> tables = {&table};
            if (&c == &all.front()) tables.push_back(nullptr);
            for (const brdf::Table* t : tables) {
              for (size_t li = 0; li < test_limits().size(); ++li) {
                Export e;
                try {
                    e = export_variant(t, c.mat, v, test_limits()[li]);
                } catch (const Error&) {
                    continue;  // refused at these limits (RefusesWhatDoesNotFitNamingTheNeed)
                }
                for (const auto& [name, bytes] : export_files(e)) {
                    if (name.find(".vert") == std::string::npos &&
                        name.find(".frag") == std::string::npos) {
                        continue;
                    }
                    batch.add((t ? "" : "lambert-") + str("l", li, "-") + name, bytes);
                    ++checked;
                    if (name.find(".frag") == std::string::npos) continue;
                    wrapped += e.table_wrapped ? 1 : 0;
                    scale_in_texture += e.table_scale_in_texture ? 1 : 0;
                }
              }
            }
        }
    }
    for (const auto& [path, log, bytes] : batch.failures()) ADD_FAILURE() << path << "\n" << log << "\n" << bytes;
    EXPECT_GE(checked, 300);
    EXPECT_GE(batch.unique_sources(), 200u);  // distinct sources compiled (260 on 2026-11-29)
    EXPECT_GT(wrapped, 0);  // the new layouts were among them
    EXPECT_GT(scale_in_texture, 0);
}

// Every uniform, varying, constant and function the fragment shader declares is used.
TEST(ExportVariant, NoDeadDeclarations) {
    const std::regex decl(
        R"(\n(?:uniform|in|varying|attribute|const)\s+(?:highp\s+|mediump\s+)?\w+\s+(\w+)|\n\w+\s+(\w+)\()");
    for (const Case& c : cases()) {
        const brdf::Table table = random_table(c.grid, c.bands, c.channels, 2);
        for (const Variant& v : variants_with_lights(c.bands, c.mat)) {
          for (const Limits& lim : test_limits()) {
            Export e;
            try {
                e = export_variant(&table, c.mat, v, lim);
            } catch (const Error&) {
                continue;  // refused at these limits
            }
            for (const std::string* src : {&e.vertex_source, &e.fragment_source}) {
                for (auto it = std::sregex_iterator(src->begin(), src->end(), decl);
                     it != std::sregex_iterator(); ++it) {
                    const std::string name = (*it)[1].matched ? (*it)[1] : (*it)[2];
                    if (name == "main") continue;
                    const std::regex use("\\b" + name + "\\b");
                    const auto uses = std::distance(
                        std::sregex_iterator(src->begin(), src->end(), use), std::sregex_iterator());
                    EXPECT_GE(uses, 2) << e.name << ": '" << name << "' declared, never used\n"
                                       << *src;
                }
            }
          }
        }
    }
}

TEST(ExportVariant, LayoutFollowsTheLimits) {
    const brdf::Table table = random_table("octa:9", 3, 1, 3);  // 81 nodes x 3 texels
    MaterialInputs mat;
    Variant es3;
    // ES 3.0's minimum 224 vectors cannot hold 243 texels: a float texture.
    const Export small = export_variant(&table, mat, es3, Limits::minimum(GlslVersion::kEs300));
    EXPECT_EQ(small.table_layout, TableLayout::kFloatTexture);
    EXPECT_EQ(small.fragment_uniform_vectors, 10);  // u_sh[9], u_albedo
    const Export big = export_variant(&table, mat, es3, roomy_limits());
    EXPECT_EQ(big.table_layout, TableLayout::kUniformArray);
    EXPECT_EQ(big.fragment_uniform_vectors, 10 + 243);
    EXPECT_EQ(big.manifest["gl_limits_needed"]["max_fragment_uniform_vectors"], 253);
    // ES 1.00: always RGBA8, and the 3-band variants fit the ES 2.0 minimum of 16 vectors:
    // u_sh[9] + u_albedo + 3 scales + 3 offsets.
    Variant es1;
    es1.version = GlslVersion::kEs100;
    for (ShaderMode mode : {ShaderMode::kConsistent, ShaderMode::kSeed}) {
        es1.mode = mode;
        const Export e = export_variant(&table, mat, es1, Limits::minimum(GlslVersion::kEs100));
        EXPECT_EQ(e.table_layout, TableLayout::kRgba8Texture);
        EXPECT_EQ(e.fragment_uniform_vectors, 16);
    }
}

// Above 3 bands the ES 1.00 lighting moves into an RGBA8 texture at the ES 2.0 minimum (instead
// of the export being refused): u_albedo + the table's scale and offset, + 2 per light.
TEST(ExportVariant, LightingTextureWhenUniformsDoNotFit) {
    const brdf::Table table = random_table("octa:5", 5, 1, 9);
    MaterialInputs mat;
    for (int bands : {4, 5}) {
        Variant v{GlslVersion::kEs100, ShaderMode::kConsistent, bands, Precision::kHighp};
        const Export e = export_variant(&table, mat, v, Limits::minimum(GlslVersion::kEs100));
        EXPECT_EQ(e.lighting_layout, LightingLayout::kRgba8Texture);
        EXPECT_EQ(e.fragment_uniform_vectors, 1 + 2 * ((sh::count(bands) + 3) / 4));
        EXPECT_EQ(e.manifest["lighting_layout"], "rgba8_texture_16bit");
        EXPECT_EQ(e.fragment_source.find("u_sh["), std::string::npos);
    }
    Variant lit{GlslVersion::kEs100, ShaderMode::kConsistent, 4, Precision::kHighp, 3};
    EXPECT_EQ(export_variant(&table, mat, lit, Limits::minimum(GlslVersion::kEs100))
                  .fragment_uniform_vectors, 9 + 6);
    // 3 bands stay in uniforms (exactly 16 vectors).
    const Export b3 = export_variant(&table, mat, Variant{GlslVersion::kEs100}, Limits::minimum(GlslVersion::kEs100));
    EXPECT_EQ(b3.lighting_layout, LightingLayout::kUniformArray);
}

// The RGBA8 lighting: 16 bits per value between a per-coefficient offset and scale stored as
// float32 bytes: every value within scale_k / 131070 (half a 16-bit step) plus float rounding
// of offset + scale * q (2 ulp of the coefficient's magnitude), and the bound states it.
TEST(ExportVariant, LightingQuantisationWithinHalfAStep) {
    const brdf::Table table = random_table("octa:5", 5, 1, 10);
    const Export e = export_variant(&table, MaterialInputs{}, {GlslVersion::kEs100, ShaderMode::kConsistent, 5},
                                    Limits::minimum(GlslVersion::kEs100));
    Eigen::MatrixXd sh = Eigen::MatrixXd::Random(25, 3) * 3.0;
    sh.row(3).setConstant(-0.25);  // no spread: scale 0, exact
    sh(5, 1) = 1e-30;
    const BoundLighting b = bind_lighting(e, sh);
    ASSERT_EQ(b.bytes.size(), 25u * 4 * 4);
    double worst = 0;
    for (int k = 0; k < 25; ++k) {
        const double spread = sh.row(k).maxCoeff() - sh.row(k).minCoeff();
        for (int c = 0; c < 3; ++c) {
            const double err = std::abs(b.as_bound(k, c) - sh(k, c));
            EXPECT_LE(err, spread / 131070 + 2.4e-7 * std::abs(sh(k, c))) << k << " " << c;
            worst = std::max(worst, err);
        }
    }
    EXPECT_EQ(b.as_bound(3, 0), -0.25);
    EXPECT_LE(worst, b.max_abs_error + 1e-6);
    EXPECT_THROW(bind_lighting(e, Eigen::MatrixXd::Constant(25, 3, NAN)), Error);
}

TEST(ExportVariant, RefusesWhatDoesNotFitNamingTheNeed) {
    const brdf::Table table = random_table("octa:9", 4, 1, 4);
    MaterialInputs mat;
    Variant v;
    v.version = GlslVersion::kEs100;
    v.sh_bands = 3;
    // 8 lights at the ES 2.0 minimum: 1 + 2 x 8 = 17 vectors even with the lighting and the
    // table's scale and offset in textures.
    v.lights = 8;
    const std::string msg = inlight::testing::error_of(
        [&] { export_variant(&table, mat, v, Limits::minimum(GlslVersion::kEs100)); });
    EXPECT_NE(msg.find("material-es100-consistent-b3-l8-highp"), std::string::npos) << msg;
    EXPECT_NE(msg.find("needs 17 fragment uniform vectors (lighting in a texture, u_albedo, 16 for 8 lights)"),
              std::string::npos) << msg;
    EXPECT_NE(msg.find("GL_MAX_FRAGMENT_UNIFORM_VECTORS is 16"), std::string::npos) << msg;
    v.lights = 0;
    // ES 1.00 wraps a table wider than GL_MAX_TEXTURE_SIZE into rows of that width; one with
    // more texels than 64 x 64 is refused at the ES 2.0 minimum, naming its size and the limit.
    const brdf::Table wide = random_table("thetaphi:5x40", 3, 1, 5);  // 120 x 5 = 600 texels
    const Export wrapped = export_variant(&wide, mat, v, Limits::minimum(GlslVersion::kEs100));
    EXPECT_EQ(wrapped.data_width, 64);
    EXPECT_EQ(wrapped.data_height, 10);
    EXPECT_EQ(wrapped.table_bytes.size(), 64u * 10 * 4);
    const brdf::Table huge = random_table("thetaphi:33x64", 3, 1, 5);  // 6336 texels
    const std::string msg2 = inlight::testing::error_of(
        [&] { export_variant(&huge, mat, v, Limits::minimum(GlslVersion::kEs100)); });
    EXPECT_NE(msg2.find("needs 6336 texels (6336 of the table, 192x33), more than "
                        "GL_MAX_TEXTURE_SIZE^2 = 64x64 holds; give the device's limit"),
              std::string::npos) << msg2;
    // Impossible variants are usage errors.
    v.sh_bands = 4;
    v.mode = ShaderMode::kSeed;
    v.sh_bands = 4;
    EXPECT_THROW(export_variant(&table, mat, v, roomy_limits()), UsageError);
    v.mode = ShaderMode::kConsistent;
    v.sh_bands = 5;
    EXPECT_THROW(export_variant(&table, mat, v, roomy_limits()), UsageError);
    mat.name = "bad name";
    v.sh_bands = 3;
    EXPECT_THROW(export_variant(&table, mat, v, roomy_limits()), UsageError);
    // Lights: none in the seed mode (the report's shader has none), none on a Lambert lobe
    // with a table; two uniform vectors each, counted against the limit.
    mat.name = "material";
    v.lights = 1;
    v.mode = ShaderMode::kSeed;
    EXPECT_THROW(export_variant(&table, mat, v, roomy_limits()), UsageError);
    v.mode = ShaderMode::kConsistent;
    mat.brdf.specular = brdf::Model::kLambert;
    EXPECT_THROW(export_variant(&table, mat, v, roomy_limits()), UsageError);
    mat.brdf.specular = brdf::Model::kGgx;
    v.version = GlslVersion::kEs300;
    v.lights = 7;  // 9 + 1 + 14 > 16 vectors: the lighting moves to a texture (1 + 14)
    Limits l16 = roomy_limits();
    l16.max_fragment_uniform_vectors = 16;
    EXPECT_EQ(export_variant(&table, mat, v, l16).lighting_layout, LightingLayout::kFloatTexture);
    v.lights = 3;
    EXPECT_EQ(export_variant(&table, mat, v, Limits::minimum(GlslVersion::kEs300))
                  .fragment_uniform_vectors,
              9 + 1 + 6);
}

// ES 1.00 up to the table's bands at the ES 2.0 minimum. The cheapest arrangement that
// fits the 16 vectors is taken: 3 bands all in uniforms (9 + 1 + 6); 3 bands + 3 lights (22)
// the table's scale/offset in its texture (16); 4 and 5 bands the lighting in its texture
// (1 + 8, 1 + 14); 6 and 8 bands both (1). The scale/offset texels follow the table's texels,
// each the float32 of the manifest's value; and a GL_MAX_TEXTURE_SIZE given above the minimum
// lays out what the minimum refuses (both versions), in rows of that size.
TEST(ExportVariant, Es100UpToTheTablesBandsAndLargeTablesWithinTheGivenLimit) {
    const brdf::Table table = random_table("octa:5", 8, 3, 7);
    MaterialInputs mat;
    const Limits es2 = Limits::minimum(GlslVersion::kEs100);
    struct Expect {
        int bands, lights;
        bool lighting_texture, scale_texture;
        int vectors;
    };
    for (const Expect& x : {Expect{3, 0, false, false, 16}, Expect{3, 3, false, true, 16},
                            Expect{4, 0, true, false, 9}, Expect{5, 0, true, false, 15},
                            Expect{6, 0, true, true, 1}, Expect{8, 0, true, true, 1},
                            Expect{8, 7, true, true, 15}}) {
        Variant v;
        v.version = GlslVersion::kEs100;
        v.sh_bands = x.bands;
        v.lights = x.lights;
        mat.brdf.specular = brdf::Model::kGgx;
        const Export e = export_variant(&table, mat, v, es2);
        EXPECT_EQ(e.lighting_layout != LightingLayout::kUniformArray, x.lighting_texture) << e.name;
        EXPECT_EQ(e.table_scale_in_texture, x.scale_texture) << e.name;
        EXPECT_EQ(e.fragment_uniform_vectors, x.vectors) << e.name;
        EXPECT_EQ(e.manifest["gl_limits_needed"]["max_fragment_uniform_vectors"], x.vectors) << e.name;
        EXPECT_LE(std::max(e.data_width, e.data_height), 64) << e.name;
        const int k = x.bands * x.bands, tn = (k + 3) / 4;
        const bool has_uniforms = e.fragment_source.find("u_brdf_scale") != std::string::npos;
        EXPECT_NE(has_uniforms, x.scale_texture) << e.name;
        if (!x.scale_texture) continue;
        EXPECT_EQ(e.table_scale_texel, 3 * 25 * tn) << e.name;
        EXPECT_EQ(e.manifest["brdf_table"]["scale_offset"]["scale_texel"], 3 * 25 * tn) << e.name;
        const int texels = 3 * 25 * tn + 2 * k;  // the table's and 2 k more; the last row padded
        EXPECT_GE(e.data_width * e.data_height, texels) << e.name;
        EXPECT_LT(e.data_width * e.data_height - texels, e.data_width) << e.name;
        for (int c = 0; c < k; ++c) {
            for (int which = 0; which < 2; ++which) {
                const uint8_t* b = &e.table_bytes[(e.table_scale_texel + which * k + c) * 4];
                const float want = which == 0 ? e.table_scale[c] : e.table_offset[c];
                // The shader's unpack_f32, in double: exact for every float32 it packs.
                const double m = (((b[1] & 0x7f) | 0x80) * 65536.0 + b[2] * 256.0 + b[3]) / 16777216.0;
                const double got = b[0] == 0 ? 0.0 : (b[1] & 0x80 ? -1 : 1) * std::ldexp(m, b[0] - 127);
                EXPECT_EQ(got, static_cast<double>(want)) << e.name << " k " << c;
            }
        }
    }
    // Larger than 64 x 64 texels: refused at the minimum (RefusesWhatDoesNotFitNamingTheNeed),
    // laid out within a larger GL_MAX_TEXTURE_SIZE: ES 1.00 RGBA8 and ES 3.00 RGBA32F alike.
    const brdf::Table huge = random_table("thetaphi:33x64", 3, 1, 5);  // 6336 texels, 192 x 33
    for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        Limits l = Limits::minimum(ver);
        l.max_texture_size = 128;
        Variant v;
        v.version = ver;
        const Export e = export_variant(&huge, mat, v, l);
        EXPECT_EQ(e.data_width, 128) << e.name;
        EXPECT_EQ(e.data_height, 50) << e.name;  // ceil(6336 / 128)
        EXPECT_TRUE(e.table_wrapped) << e.name;
        EXPECT_EQ(e.manifest["gl_limits_needed"]["max_texture_size"], 128) << e.name;
        l.max_texture_size = 79;  // 79 x 79 = 6241 < 6336: refused with the reason
        EXPECT_NE(inlight::testing::error_of([&] { export_variant(&huge, mat, v, l); })
                      .find("more than GL_MAX_TEXTURE_SIZE^2 = 79x79 holds"),
                  std::string::npos) << e.name;
    }
    // The export set takes the device's limit; below a version's minimum it is a usage error.
    ExportSet set;
    set.max_texture_size = 128;
    EXPECT_EQ(export_limits(set, GlslVersion::kEs100).max_texture_size, 128);
    EXPECT_THROW(export_limits(set, GlslVersion::kEs300), UsageError);
    set.max_texture_size = 0;
    EXPECT_EQ(export_limits(set, GlslVersion::kEs300).max_texture_size, 2048);
}

// RGBA8: every coefficient is offset + scale x byte / 255 within half a step of the float
// table, and table_as_bound is exactly what those bytes decode to.
TEST(ExportVariant, Rgba8QuantisationWithinHalfAStep) {
    const brdf::Table table = random_table("thetaphi:5x8", 3, 3, 6);
    MaterialInputs mat;
    Variant v;
    v.version = GlslVersion::kEs100;
    const Export e = export_variant(&table, mat, v, Limits::minimum(GlslVersion::kEs100));
    ASSERT_TRUE(e.table_as_bound);
    double worst = 0;
    for (int ch = 0; ch < 3; ++ch) {
        for (int i1 = 0; i1 < 5; ++i1) {
            for (int i2 = 0; i2 < 8; ++i2) {
                for (int k = 0; k < 9; ++k) {
                    const double step = e.table_scale[k] / 255.0;
                    const double err =
                        std::abs(e.table_as_bound->at(ch, i1, i2, k) - table.at(ch, i1, i2, k));
                    // Half a step, plus float rounding of offset + scale * b (~1e-7 relative).
                    EXPECT_LE(err, 0.5 * step + 1e-6) << ch << " " << i1 << " " << i2 << " " << k;
                    worst = std::max(worst, err);
                }
            }
        }
    }
    EXPECT_LE(worst, e.manifest["brdf_table"]["quantization_max_abs_error"].get<double>() + 1e-6);
}

TEST(ExportVariant, ManifestListsEveryBinding) {
    const brdf::Table table = random_table("octa:5", 3, 1, 7);
    MaterialInputs mat;
    mat.name = "velvet";
    mat.albedo_texture_px = {4, 4};
    mat.normal_texture_px = {4, 4};
    const Export e = export_variant(&table, mat, Variant{}, Limits::minimum(GlslVersion::kEs300));
    std::set<std::string> names;
    for (const auto& u : e.manifest["uniforms"]) names.insert(u["name"]);
    for (const auto& t : e.manifest["textures"]) names.insert(t["uniform"]);
    for (const auto& a : e.manifest["attributes"]) names.insert(a["name"]);
    const std::regex decl(R"(\n(?:uniform|in)\s+(?:highp\s+)?\w+\s+(\w+))");
    for (const std::string* src : {&e.vertex_source, &e.fragment_source}) {
        for (auto it = std::sregex_iterator(src->begin(), src->end(), decl);
             it != std::sregex_iterator(); ++it) {
            const std::string n = (*it)[1];
            if (n.rfind("v_", 0) == 0) continue;  // varyings are internal
            EXPECT_TRUE(names.count(n)) << n << " is not in the manifest";
        }
    }
    EXPECT_EQ(e.manifest["textures"][0]["color_space"], "srgb");
    EXPECT_EQ(e.manifest["precision"]["safe"], "highp");
}

// The manifest suffices to bind (docs/gles.md, "What the app binds"): every uniform has a value
// (the material's, the table's) or a source, every material texture a file whose bytes the export
// carries, and the values are the ones the harness binds.
TEST(ExportVariant, ManifestGivesEveryUniformAValueOrASource) {
    const brdf::Table table = random_table("octa:5", 3, 1, 9);
    MaterialInputs mat;
    mat.name = "velvet";
    mat.brdf.albedo = {0.25, 0.5, 0.75};
    mat.uv_scale = {2, 3};
    mat.albedo_texture_px = {2, 1};
    mat.albedo_rgba8 = {1, 2, 3, 255, 4, 5, 6, 255};
    for (GlslVersion version : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        const Export e = export_variant(&table, mat, {version}, Limits::minimum(version));
        const nlohmann::json& m = e.manifest;
        for (const auto& u : m["uniforms"]) {
            EXPECT_TRUE(u.contains("value") || u.contains("source")) << e.name << " " << u["name"];
            if (u["name"] == "u_albedo") {
                EXPECT_EQ(u["value"], nlohmann::json({0.25, 0.5, 0.75}));
            }
            if (u["name"] == "u_uv_scale") {
                EXPECT_EQ(u["value"], nlohmann::json({2.0, 3.0}));
            }
            if (u["name"] == "u_sh") {
                EXPECT_EQ(u["source"]["count"], 9);
            }
            if (u["name"] == "u_brdf_scale") {
                EXPECT_EQ(u["value"].get<std::vector<float>>(), e.table_scale);
            }
            if (u["name"] == "u_brdf_offset") {
                EXPECT_EQ(u["value"].get<std::vector<float>>(), e.table_offset);
            }
            if (u["name"] == "u_brdf") {  // one vector per texel: no width to refer to
                EXPECT_EQ(u["value"]["file"], e.name + ".brdf.bin");
                EXPECT_EQ(m["brdf_table"]["texel_of"].get<std::string>().find("width"), std::string::npos);
            }
        }
        for (const auto& t : m["textures"]) {
            ASSERT_TRUE(t.contains("file")) << e.name << " " << t["uniform"];
            EXPECT_TRUE(t.contains("padding"));
        }
        ASSERT_EQ(m["textures"][0]["file"], "velvet.albedo.png");
        const auto files = export_files(e);
        const auto albedo = std::find_if(files.begin(), files.end(),
                                         [](const auto& f) { return f.first == "velvet.albedo.png"; });
        ASSERT_NE(albedo, files.end());
        // The PNG's samples, decoded without any colour step, are the texel bytes.
        image::ReadOptions raw;
        raw.decode_srgb = false;
        const image::Image png = image::read_image_memory(albedo->second.data(), albedo->second.size(),
                                                          albedo->first, raw);
        ASSERT_EQ(png.width, 2);
        ASSERT_EQ(png.height, 1);
        ASSERT_EQ(png.channels, 4);
        std::string codes;
        for (float v : png.pixels) codes.push_back(static_cast<char>(std::lround(v * 255.0f)));
        EXPECT_EQ(codes, std::string("\x01\x02\x03\xff\x04\x05\x06\xff", 8));
        EXPECT_EQ(m["output"]["encoding_8bit"]["steps"].size(), 4u);
    }
    mat.albedo_rgba8.pop_back();  // 7 bytes for 2 x 1 texels: refused, naming both
    EXPECT_THROW(export_variant(&table, mat, {}, Limits::minimum(GlslVersion::kEs300)), UsageError);
}

// A lighting file's lights: the consistent variants shade them, the seed variants do not, and
// the manifest carries the values the app binds, as light_uniforms() computes them.
TEST(ExportVariant, LightsInTheManifest) {
    const brdf::Table table = random_table("octa:5", 3, 1, 8);
    MaterialInputs mat;
    mat.name = "satin";
    ExportSet set;
    set.versions = {GlslVersion::kEs300};
    set.precisions = {Precision::kHighp};
    envmap::DirectionalLight sun, lamp;
    sun.direction = {0, 0.6, 0.8};
    sun.flux = {100, 90, 80};
    sun.angular_radius = 0.5 * kPi / 180;
    lamp.direction = {1, 0, 0};
    lamp.flux = {1, 1, 1};
    lamp.angular_radius = 5e-5;  // below 1e-4 rad: a point (sin alpha bound as 0)
    set.lights = {sun, lamp};
    const std::vector<Export> exports = export_material(&table, mat, set);
    ASSERT_EQ(exports.size(), 2u);
    EXPECT_EQ(exports[0].name, "satin-es300-consistent-b3-l2-highp");
    EXPECT_EQ(exports[1].name, "satin-es300-seed-b3-highp");
    EXPECT_FALSE(exports[1].manifest.contains("lights"));
    const nlohmann::json& m = exports[0].manifest;
    EXPECT_EQ(m["lights"]["count"], 2);
    EXPECT_EQ(m["lights"]["lobe"]["model"], "ggx");
    for (const auto& u : m["uniforms"]) {
        if (u["name"] == "u_light_direction") {
            const std::vector<float> want = {0.0f, 0.6f, 0.8f,
                                             static_cast<float>(std::sin(0.5 * kPi / 180)),
                                             1.0f, 0.0f, 0.0f, 0.0f};
            const auto got = u["value"].get<std::vector<float>>();
            ASSERT_EQ(got.size(), want.size());
            for (size_t i = 0; i < want.size(); ++i) EXPECT_FLOAT_EQ(got[i], want[i]) << i;
        }
        if (u["name"] == "u_light_irradiance") {
            const double half = 0.5 * (1 + std::cos(0.5 * kPi / 180));
            const auto got = u["value"].get<std::vector<float>>();
            ASSERT_EQ(got.size(), 6u);
            EXPECT_FLOAT_EQ(got[0], static_cast<float>(100 * half));
            EXPECT_FLOAT_EQ(got[5], static_cast<float>(0.5 * (1 + std::cos(5e-5))));
        }
    }
    EXPECT_EQ(m["gl_limits_needed"]["max_fragment_uniform_vectors"],
              exports[0].fragment_uniform_vectors);
}

// mediump variants are exported only on request: they are not validated on a half-float driver.
TEST(ExportSet, HighpOnlyByDefault) {
    const brdf::Table table = random_table("octa:5", 3, 1, 8);
    MaterialInputs mat;
    for (const Export& e : export_material(&table, mat, ExportSet{})) {
        EXPECT_EQ(e.variant.precision, Precision::kHighp) << e.name;
    }
}

// index.json's "load": per capability the consistent variant at the most bands, highp where the
// context has it, and for ES 2.0 without highp a mediump variant (marked not validated) only when
// one was asked for, else null with the reason.
TEST(LoadChoices, NamesTheVariantPerCapability) {
    const brdf::Table table = random_table("octa:5", 4, 1, 8);
    MaterialInputs mat;
    mat.name = "satin";
    ExportSet set;
    set.max_sh_bands = 4;
    set.max_texture_size = 2048;  // the 4-band table fits ES 2.0 only above 64 texels
    nlohmann::json load = load_choices(export_material(&table, mat, set));
    ASSERT_EQ(load["satin"].size(), 3u);
    EXPECT_EQ(load["satin"][0]["variant"], "satin-es300-consistent-b4-highp");
    EXPECT_EQ(load["satin"][1]["variant"], "satin-es100-consistent-b4-highp");
    EXPECT_TRUE(load["satin"][2]["variant"].is_null());
    EXPECT_NE(load["satin"][2]["why"].get<std::string>().find("GL_FRAGMENT_PRECISION_HIGH"),
              std::string::npos);
    set.precisions = {Precision::kMediump, Precision::kHighp};
    set.modes = {ShaderMode::kSeed, ShaderMode::kConsistent};
    load = load_choices(export_material(&table, mat, set));
    EXPECT_EQ(load["satin"][0]["variant"], "satin-es300-consistent-b4-highp");
    EXPECT_EQ(load["satin"][1]["variant"], "satin-es100-consistent-b4-highp");
    EXPECT_EQ(load["satin"][2]["variant"], "satin-es100-consistent-b4-mediump");
    EXPECT_EQ(load["satin"][2]["validated"], false);
    set.versions = {GlslVersion::kEs100};  // an ES 3 context runs GLSL ES 1.00 too
    load = load_choices(export_material(&table, mat, set));
    EXPECT_EQ(load["satin"][0]["variant"], "satin-es100-consistent-b4-highp");
}

// mediump's guaranteed range is |x| in [2^-14, 2^14] (half floats: up to 65504); a literal
// outside it (other than 0) flushes or overflows on a half-float driver, e.g. the float32
// unpack's 65536.0 x 5.96e-8 (inf x 0 = NaN) or the lobe's 1e-9 guard (0: a division by zero at
// the horizon). llvmpipe computes mediump at 32 bits (GlesHarness.LlvmpipeComputesMediumpAt32
// Bits), so it cannot show these; this test reads every mediump source, the variants with the
// data in textures (unpacks) and lights (lobes) of all four lobes included.
TEST(ExportVariant, MediumpLiteralsFitHalfFloats) {
    const std::regex literal(R"((?:^|[^\w.])(\d+\.\d*(?:e[-+]?\d+)?|\d+e[-+]?\d+))");
    const double kHalfMin = std::ldexp(1.0, -14), kHalfMax = 65504;
    int sources = 0;
    for (brdf::Model model : {brdf::Model::kGgx, brdf::Model::kCookTorranceReport,
                              brdf::Model::kCharlie, brdf::Model::kLambert}) {
        const brdf::Table table = random_table("octa:5", 6, 1, 8);
        MaterialInputs mat;
        mat.brdf.specular = model;
        mat.albedo_texture_px = {4, 4};
        mat.normal_texture_px = {4, 4};
        for (const Variant& base : variants_with_lights(6, mat)) {
            if (base.precision != Precision::kMediump) continue;
            for (int bands : {3, 6}) {
                Variant v = base;
                if (v.mode == ShaderMode::kConsistent) v.sh_bands = bands;
                Limits limits = Limits::minimum(v.version);
                limits.max_texture_size = 4096;
                const bool lambert = model == brdf::Model::kLambert;  // no table: no lobe
                const Export e = export_variant(lambert ? nullptr : &table, mat, v, limits);
                ++sources;
                const std::string& src = e.fragment_source;
                for (auto it = std::sregex_iterator(src.begin(), src.end(), literal);
                     it != std::sregex_iterator(); ++it) {
                    const double x = std::stod((*it)[1]);
                    if (x == 0) continue;
                    EXPECT_TRUE(x >= kHalfMin && x <= kHalfMax)
                        << e.name << ": literal " << (*it)[1] << " is not a normal half float";
                }
            }
        }
    }
    EXPECT_GT(sources, 40);
}

}  // namespace
}  // namespace inlight::gles

namespace inlight::gles {
namespace {

std::vector<uint8_t> random_bytes(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> byte(0, 255);
    std::vector<uint8_t> out(static_cast<size_t>(w) * h * 4, 255);
    for (size_t i = 0; i < out.size(); ++i) {
        if (i % 4 != 3) out[i] = static_cast<uint8_t>(byte(rng));
    }
    return out;
}

// The atlas file holds the CPU model's atlas exactly: level 0 the bytes themselves, levels >= 1
// the 8-bit codes render::build_mip_atlas quantised to (decoded: the same floats, bit for bit).
TEST(ExportTrilinear, AtlasFileIsTheCpuModelsAtlas) {
    for (const bool srgb : {true, false}) {
        const Eigen::Vector2i size(37, 23);
        const std::vector<uint8_t> bytes = random_bytes(size.x(), size.y(), srgb ? 1 : 2);
        const MipAtlas8 a = mip_atlas_rgba8(bytes, size, srgb);
        image::Image level0(size.x(), size.y(), 3);
        for (int y = 0; y < size.y(); ++y)
            for (int x = 0; x < size.x(); ++x)
                for (int c = 0; c < 3; ++c) {
                    const float v = bytes[(static_cast<size_t>(y) * size.x() + x) * 4 + c] / 255.0f;
                    level0.at(x, y, c) = srgb ? image::srgb_decode(v) : v;
                }
        const render::MipAtlas cpu = render::build_mip_atlas(
            level0, srgb ? render::TextureKind::kColor : render::TextureKind::kNormalMap, true);
        ASSERT_EQ(a.width, cpu.atlas.width);
        ASSERT_EQ(a.height, cpu.atlas.height);
        EXPECT_EQ(a.width, 37 + 18);
        ASSERT_EQ(a.levels.size(), cpu.levels.size());
        int compared = 0;
        for (const render::MipRect& r : cpu.levels) {
            for (int y = r.y; y < r.y + r.height; ++y)
                for (int x = r.x; x < r.x + r.width; ++x)
                    for (int c = 0; c < 3; ++c) {
                        const float v = a.rgba[(static_cast<size_t>(y) * a.width + x) * 4 + c] / 255.0f;
                        EXPECT_EQ(srgb ? image::srgb_decode(v) : v, cpu.atlas.at(x, y, c)) << x << "," << y;
                        ++compared;
                    }
        }
        EXPECT_EQ(compared, 3 * (37 * 23 + 18 * 11 + 9 * 5 + 4 * 2 + 2 * 1 + 1));
    }
}

TEST(ExportTrilinear, ManifestNamesTheAtlasItsLevelsTheLodAndTheExtension) {
    MaterialInputs mat;
    mat.name = "cloth";
    mat.albedo_texture_px = {16, 8};
    mat.normal_texture_px = {5, 3};
    mat.albedo_rgba8 = random_bytes(16, 8, 3);
    mat.normal_rgba8 = random_bytes(5, 3, 4);
    for (GlslVersion version : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        Variant v;
        v.version = version;
        v.texture_filter = TextureFilter::kTrilinear;
        const Export e = export_variant(nullptr, mat, v, roomy_limits());
        EXPECT_EQ(e.name, str("cloth-es", to_string(version), "-consistent-b3-highp-trilinear"));
        EXPECT_EQ(e.manifest["texture_filter"], "trilinear");
        EXPECT_EQ(e.manifest["files"]["albedo_texture"], "cloth.albedo.mip.png");
        const nlohmann::json& t = e.manifest["textures"][0];
        EXPECT_EQ(t["width"], 24);
        EXPECT_EQ(t["height"], 8);
        const auto levels = render::mip_atlas_levels(16, 8);
        ASSERT_EQ(t["mip"]["levels"].size(), levels.size());
        for (size_t k = 0; k < levels.size(); ++k) {
            EXPECT_EQ(t["mip"]["levels"][k]["x"], levels[k].x);
            EXPECT_EQ(t["mip"]["levels"][k]["y"], levels[k].y);
            EXPECT_EQ(t["mip"]["levels"][k]["width"], levels[k].width);
            EXPECT_EQ(t["mip"]["levels"][k]["height"], levels[k].height);
        }
        EXPECT_EQ(e.manifest["textures"][1]["width"], 7);  // 5 + 2
        const std::string lod = t["mip"]["level_of_detail"];
        EXPECT_NE(lod.find("0.5 * log2(max(dot(dx, dx), dot(dy, dy)) / 3 + 2 / 3)"), std::string::npos);
        EXPECT_EQ(e.manifest["gl_limits_needed"]["max_texture_size"], 24);
        // The files: the atlases' PNGs, whose samples are mip_atlas_rgba8()'s bytes.
        ASSERT_EQ(e.texture_files.size(), 2u);
        EXPECT_EQ(e.texture_files[0].first, "cloth.albedo.mip.png");
        EXPECT_EQ(e.texture_files[1].first, "cloth.normal.mip.png");
        for (int i = 0; i < 2; ++i) {
            const auto& [file, bytes] = e.texture_files[i];
            image::ReadOptions raw;
            raw.decode_srgb = false;
            const image::Image png = image::read_image_memory(bytes.data(), bytes.size(), file, raw);
            const MipAtlas8 want = i == 0 ? mip_atlas_rgba8(mat.albedo_rgba8, mat.albedo_texture_px, true)
                                          : mip_atlas_rgba8(mat.normal_rgba8, mat.normal_texture_px, false);
            ASSERT_EQ(png.width, want.width) << file;
            ASSERT_EQ(png.height, want.height) << file;
            ASSERT_EQ(png.channels, 4) << file;
            for (size_t k = 0; k < want.rgba.size(); ++k)
                ASSERT_EQ(std::lround(png.pixels[k] * 255.0f), want.rgba[k]) << file << " byte " << k;
        }
        EXPECT_EQ(e.manifest["textures"][1]["height"], 3);
        // ES 1.00 needs the derivatives extension, declared in the shader and the manifest.
        const bool es1 = version == GlslVersion::kEs100;
        const bool declared = e.fragment_source.find("#extension GL_OES_standard_derivatives : require") !=
                              std::string::npos;
        EXPECT_EQ(declared, es1);
        bool listed = false;
        for (const auto& r : e.manifest["gl_limits_needed"]["requires"])
            listed = listed || r.get<std::string>().rfind("GL_OES_standard_derivatives", 0) == 0;
        EXPECT_EQ(listed, es1);
        // The bilinear variant of the same material is today's: no lod, the textures themselves.
        v.texture_filter = TextureFilter::kBilinear;
        const Export b = export_variant(nullptr, mat, v, roomy_limits());
        EXPECT_EQ(b.fragment_source.find("texture_lod"), std::string::npos);
        EXPECT_EQ(b.texture_files[0].first, "cloth.albedo.png");
        EXPECT_FALSE(b.manifest["textures"][0].contains("mip"));
    }
}

TEST(ExportTrilinear, RefusesAnAtlasWiderThanTheLimitNamingIt) {
    MaterialInputs mat;
    mat.albedo_texture_px = {48, 48};  // atlas 72 x 48: above ES 2.0's minimum of 64
    Variant v;
    v.version = GlslVersion::kEs100;
    v.texture_filter = TextureFilter::kTrilinear;
    try {
        export_variant(nullptr, mat, v, Limits::minimum(GlslVersion::kEs100));
        FAIL() << "a 72 x 48 atlas at GL_MAX_TEXTURE_SIZE 64 must be refused";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("mip atlas is 72x48"), std::string::npos) << what;
        EXPECT_NE(what.find("GL_MAX_TEXTURE_SIZE = 64"), std::string::npos) << what;
    }
    // The bilinear variant binds the 48 x 48 texture itself, the app's to size (not checked).
    v.texture_filter = TextureFilter::kBilinear;
    EXPECT_NO_THROW(export_variant(nullptr, mat, v, Limits::minimum(GlslVersion::kEs100)));
    v.texture_filter = TextureFilter::kTrilinear;
    // A material without textures gets the bilinear variant whatever is asked (the same code).
    MaterialInputs plain;
    const Export e = export_variant(nullptr, plain, v, Limits::minimum(GlslVersion::kEs100));
    EXPECT_EQ(e.name, "material-es100-consistent-b3-highp");
    EXPECT_EQ(e.variant.texture_filter, TextureFilter::kBilinear);
    EXPECT_EQ(e.manifest["texture_filter"], "bilinear");
    // A device limit of 72 holds it.
    Limits limits = Limits::minimum(GlslVersion::kEs100);
    limits.max_texture_size = 72;
    EXPECT_NO_THROW(export_variant(nullptr, mat, v, limits));
}

}  // namespace
}  // namespace inlight::gles
