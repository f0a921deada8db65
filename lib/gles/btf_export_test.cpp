// The BTF export (gles/btf_export.h) drawn through EGL against the CPU decoder
// (CompressedBtf::combine_streamed of the light weights W = A c: no folding shared with the
// shader), and its files' layout. Skips where EGL cannot give a context.
#include "gles/btf_export.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>

#include "btf/compressed.h"
#include "btf/pca_run.h"
#include "btf/sh_lighting.h"
#include "btf/synthetic.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "gles/btf_draw.h"
#include "gles/gles_testing.h"
#include "gles/harness_testing.h"
#include "render/btf_shade.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::gles {
namespace {

using harness_testing::context2;
using harness_testing::context3;

constexpr int kWidth = 16, kHeight = 12;

/// A btf-pca folder of a synthetic BTF on the Bonn dome (81 lights, 81 views), groups of 3
/// views, `components` per group, 8-bit PNG.
std::string make_folder(const std::string& name, int components, btf::FitSpace space = btf::FitSpace::kLinear,
                        btf::ComponentEncoding enc = btf::ComponentEncoding::kPng8) {
    btf::AnalyticBtfOptions ao;
    ao.width = kWidth;
    ao.height = kHeight;
    ao.rank = 4;
    const btf::AnalyticBtf raw(ao);
    btf::PcaRunOptions po;
    po.output = inlight::testing::temp_dir(name);
    po.pca.view_group_size = 3;
    po.pca.components = components;
    po.encoding = enc;
    po.fit_space = space;
    btf::compress_to_folder(raw, po, 0);
    return po.output;
}

const std::string& folder6() {
    static const std::string d = make_folder("btf_gles_c6", 6);
    return d;
}
const std::string& folder3() {
    static const std::string d = make_folder("btf_gles_c3", 3);
    return d;
}
/// folder3 with every component's scale and offset 0: components all zero.
const std::string& folder_zero() {
    static const std::string d = [] {
        const std::string out = inlight::testing::temp_dir("btf_gles_zero");
        std::filesystem::copy(folder3(), out, std::filesystem::copy_options::overwrite_existing | std::filesystem::copy_options::recursive);
        nlohmann::json m = nlohmann::json::parse(fs::read_file(out + "/btf-pca.json"));
        for (auto& g : m["groups"]) {
            for (auto& c : g["components"]) {
                c["scale"] = 0.0;
                c["offset"] = 0.0;
            }
        }
        fs::write_text_atomic(out + "/btf-pca.json", m.dump(2));
        return out;
    }();
    return d;
}

/// A lighting of `bands`: a warm sky plus seeded higher bands of a tenth its size.
Eigen::MatrixXd lighting(int bands, unsigned seed) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(sh::count(bands), 3);
    c.row(0) << 2.0, 1.8, 1.5;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.25, 0.25);
    for (Eigen::Index j = 1; j < c.rows(); ++j) {
        for (int ch = 0; ch < 3; ++ch) c(j, ch) = u(rng) * (j < 4 ? 3.0 : 1.0);
    }
    return c;
}

/// 255 x the sRGB encoding of v clamped to [0, 1] (the manifest's output steps before rounding).
double srgb_255(double v) {
    v = std::clamp(v, 0.0, 1.0);
    return 255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055);
}
int srgb_code(double v) { return static_cast<int>(std::lround(srgb_255(v))); }

struct Result {
    int max_code_diff = 0;
    double max_diff_in_codes = 0;  ///< before rounding to codes
    double largest = 0;
};

/// Draws `variant` of `e` (exported from `dir`) and compares with the CPU decoder.
/// With `lights`, the reference adds each light's directional_light_weights to W.
Result compare(Context& ctx, const btf::CompressedBtf* btf, const Eigen::MatrixXd& a, const BtfGlesExport& e,
               const BtfGlesVariant& variant, const btf::Direction& view, int bands, int64_t sent,
               const std::vector<BtfLight>& lights = {}) {
    const Eigen::MatrixXd c = lighting(bands, 7);
    // Reference: light weights W = A c, the blend's views as terms (sh_lighting_test's path).
    btf::DomeLighting w;
    for (Eigen::Index k = 0; k < a.rows(); ++k)
        w.weight.emplace_back(a.row(k).dot(c.col(0)), a.row(k).dot(c.col(1)), a.row(k).dot(c.col(2)));
    for (const BtfLight& l : lights) {
        const btf::DomeLighting d =
            btf::directional_light_weights(btf->shape().lights, l.direction, l.irradiance_w_m2, e.lighting);
        for (size_t k = 0; k < w.weight.size(); ++k) w.weight[k] += d.weight[k];
    }
    const render::ViewBlend blend = render::select_views(btf->shape().views, view, 3);
    const image::Image ref = btf->combine_streamed(btf::shading_terms(w, blend.views, blend.weights, 1.0), sent);

    const BtfFrame frame = btf_frame_weights(e, variant, view, c, sent, lights);
    const Bindings b = btf_bindings(e, frame);
    const Readback out = draw(ctx, variant.as_export, b, btf_sample_quad(), kWidth, kHeight, TargetFormat::kRgba32f);

    double y_sum = 0;
    Result r;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            y_sum += 0.2126 * ref.at(x, y, 0) + 0.7152 * ref.at(x, y, 1) + 0.0722 * ref.at(x, y, 2);
            for (int ch = 0; ch < 3; ++ch) r.largest = std::max(r.largest, double(std::abs(ref.at(x, y, ch))));
        }
    }
    const double y_mean = y_sum / (kWidth * kHeight);
    const double exposure = y_mean > 0 ? 0.18 / y_mean : 1.0;  // the manifest's auto exposure
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            for (int ch = 0; ch < 3; ++ch) {
                const int d = std::abs(srgb_code(exposure * out.at(x, y, ch)) - srgb_code(exposure * ref.at(x, y, ch)));
                r.max_code_diff = std::max(r.max_code_diff, d);
                r.max_diff_in_codes = std::max(r.max_diff_in_codes, std::abs(srgb_255(exposure * out.at(x, y, ch)) -
                                                                            srgb_255(exposure * ref.at(x, y, ch))));
            }
        }
    }
    return r;
}

bool have_context(int major) {
    try {
        (major == 3 ? context3() : context2());
        return true;
    } catch (const Error&) {
        return false;
    }
}

// The views: the pole (a measured view alone), 45 degrees between measured azimuths, 75 degrees
// (the last ring) between azimuths.
const btf::Direction kViews[] = {{0, 0}, {45, 10}, {75, 7}};

void check_version(GlslVersion ver, const std::string& dir, const char* what) {
    BtfGlesOptions o;
    o.versions = {ver};
    const auto btf = btf::CompressedBtf::open(dir);
    for (int bands : {2, 9}) {
        o.sh_bands = bands;
        const BtfGlesExport e = export_btf_gles(dir, o);
        const Eigen::MatrixXd a = btf::sh_light_weight_matrix(btf->shape().lights, bands, o.lighting, o.map_height);
        const int64_t all = static_cast<int64_t>(e.stream.size());
        for (const btf::Direction& view : kViews) {
            for (int64_t sent : {int64_t(0), all / 2, all}) {
                const Result r = compare(ver == GlslVersion::kEs300 ? context3() : context2(), btf.get(), a, e,
                                         e.variants[0], view, bands, sent);
                // One 8-bit code (after the manifest's exposure and sRGB encode): float32 sums in
                // another order differ by ~1e-6 relative, far below a code except at a rounding
                // boundary, where they can land one code apart.
                EXPECT_LE(r.max_code_diff, 1) << what << " bands " << bands << " view " << view.theta_deg << " "
                                              << view.phi_deg << " sent " << sent;
                EXPECT_GT(r.largest, 0.05) << "a lit image, not zeros on both sides";
                std::printf("[btf-gles] %s bands %d view (%g, %g) sent %lld/%lld: max code diff %d (%.4f codes before rounding)\n", what, bands,
                            view.theta_deg, view.phi_deg, static_cast<long long>(sent), static_cast<long long>(all),
                            r.max_code_diff, r.max_diff_in_codes);
            }
        }
    }
}

TEST(BtfGles, Es300DrawEqualsTheCpuDecoder) {
    if (!have_context(3)) GTEST_SKIP() << "no EGL OpenGL ES 3 context";
    if (!context3().info().float_color_buffer) GTEST_SKIP() << "no RGBA32F target";
    std::printf("[btf-gles] %s\n", context3().info().summary().c_str());
    check_version(GlslVersion::kEs300, folder6(), "es300 C=6");
    check_version(GlslVersion::kEs300, folder_zero(), "es300 zero components");
}

TEST(BtfGles, Es100DrawEqualsTheCpuDecoder) {
    if (!have_context(2)) GTEST_SKIP() << "no EGL OpenGL ES 2 context";
    if (!context2().info().float_color_buffer) GTEST_SKIP() << "no RGBA32F target";
    // C = 6: two slabs, 19 fragment uniform vectors (above ES 2.0's guaranteed 16; llvmpipe has
    // more), every prefix. C = 3 (one slab) is drawn in DominantLightsFoldIntoTheFrameWeights.
    check_version(GlslVersion::kEs100, folder6(), "es100 C=6");
    check_version(GlslVersion::kEs100, folder_zero(), "es100 zero components");
}

// Dominant lights folded into the frame's weights on the CPU (the shader unchanged): the hard
// cases of a sun exactly on a light direction, between three, at theta 87 deg (beyond the last
// ring, 75 deg) and below the sample's plane, each 20 times the sky's irradiance, beside 3-band SH.
std::vector<BtfLight> hard_lights(const std::vector<btf::Direction>& dome) {
    auto at = [](double theta_deg, double phi_deg) {
        return btf::Direction{theta_deg, phi_deg}.vector();
    };
    const Eigen::Vector3d between = (dome[1].vector() + dome[2].vector() + dome[7].vector()).normalized();
    return {{dome[10].vector(), {40, 36, 30}}, {between, {30, 40, 20}}, {at(87, 200), {60, 50, 40}},
            {at(95, 30), {1e3, 1e3, 1e3}}};
}

void check_lights(GlslVersion ver, const std::string& dir, const char* what, btf::CellRule rule) {
    BtfGlesOptions o;
    o.versions = {ver};
    o.sh_bands = 3;
    o.lighting.rule = rule;
    const auto btf = btf::CompressedBtf::open(dir);
    const BtfGlesExport e = export_btf_gles(dir, o);
    const Eigen::MatrixXd a = btf::sh_light_weight_matrix(btf->shape().lights, 3, o.lighting, o.map_height);
    const std::vector<BtfLight> lights = hard_lights(btf->shape().lights);
    const int64_t all = static_cast<int64_t>(e.stream.size());
    for (const btf::Direction& view : kViews) {
        for (size_t i = 0; i < lights.size(); ++i) {
            for (int64_t sent : {int64_t(0), all}) {
                const Result r = compare(ver == GlslVersion::kEs300 ? context3() : context2(), btf.get(), a, e,
                                         e.variants[0], view, 3, sent, {lights[i]});
                // One 8-bit code, as without lights (float32 sums in another order).
                EXPECT_LE(r.max_code_diff, 1) << what << " light " << i << " view " << view.theta_deg << " sent " << sent;
                std::printf("[btf-gles] %s light %zu view (%g, %g) sent %lld: max code diff %d (%.4f codes)\n", what, i,
                            view.theta_deg, view.phi_deg, static_cast<long long>(sent), r.max_code_diff,
                            r.max_diff_in_codes);
            }
        }
    }
}

TEST(BtfGles, DominantLightsFoldIntoTheFrameWeights) {
    if (!have_context(3) || !have_context(2)) GTEST_SKIP() << "no EGL OpenGL ES 2 and 3 contexts";
    if (!context3().info().float_color_buffer) GTEST_SKIP() << "no RGBA32F target";
    // The default rule (cosine-barycentric: a light between directions spread over three) and
    // the cosine rule (moved to the nearest).
    for (const btf::CellRule rule : {BtfGlesOptions().lighting.rule, btf::CellRule::kCosine}) {
        check_lights(GlslVersion::kEs300, folder6(), "es300 C=6", rule);
        check_lights(GlslVersion::kEs100, folder3(), "es100 C=3", rule);
    }
}

TEST(BtfGlesFiles, LightsChangeTheWeightsOnlyAboveTheSamplesPlane) {
    BtfGlesOptions o;
    o.versions = {GlslVersion::kEs300};
    const BtfGlesExport e = export_btf_gles(folder6(), o);
    const Eigen::MatrixXd c = lighting(3, 7);
    const std::vector<BtfLight> lights = hard_lights(e.lights);
    const int64_t all = static_cast<int64_t>(e.stream.size());
    const BtfFrame none = btf_frame_weights(e, e.variants[0], {45, 10}, c, all);
    // Below the plane: no light direction sees it, so exactly nothing is added.
    EXPECT_EQ(btf_frame_weights(e, e.variants[0], {45, 10}, c, all, {lights[3]}).weight, none.weight);
    // Above it, every light changes the weights; the weights are linear in the light.
    for (size_t i = 0; i < 3; ++i) {
        const BtfFrame one = btf_frame_weights(e, e.variants[0], {45, 10}, c, all, {lights[i]});
        BtfLight twice = lights[i];
        twice.irradiance_w_m2 *= 2;
        const BtfFrame two = btf_frame_weights(e, e.variants[0], {45, 10}, c, all, {twice});
        double changed = 0;
        for (size_t j = 0; j < none.weight.size(); ++j) {
            changed = std::max(changed, double(std::abs(one.weight[j] - none.weight[j])));
            // two - none = 2 (one - none) to float32 rounding of weights of size <= ~1e3.
            EXPECT_NEAR(two.weight[j] - none.weight[j], 2 * (one.weight[j] - none.weight[j]),
                        1e-4 * (1 + std::abs(two.weight[j])))
                << "light " << i << " weight " << j;
        }
        EXPECT_GT(changed, 1e-3) << "light " << i;
    }
    BtfLight bad = lights[0];
    bad.irradiance_w_m2.x() = std::nan("");
    EXPECT_THROW(btf_frame_weights(e, e.variants[0], {45, 10}, c, all, {bad}), Error);
    bad = lights[0];
    bad.direction *= 2;
    EXPECT_THROW(btf_frame_weights(e, e.variants[0], {45, 10}, c, all, {bad}), Error);
}

// An app spreads its dominant lights by the manifest's words and data alone: here the rule as
// btf-gles.json states it (lights.cell_rule, lights.triangulation), implemented apart from
// btf::PointLightWeights, gives the same weights for the hard lights (on a direction, between
// three, at 87 deg, below the plane) and a light at 89.8 deg (between the last ring and the
// horizon points, which pass their share to their owners). Sums of three doubles: 1e-12.
TEST(BtfGlesFiles, TheManifestsTriangulationSpreadsALightAsTheExport) {
    BtfGlesOptions o;
    o.versions = {GlslVersion::kEs300};
    const BtfGlesExport e = export_btf_gles(folder3(), o);
    const nlohmann::json m = nlohmann::json::parse(e.manifest.dump());
    const auto& t = m.at("lights").at("triangulation");
    ASSERT_NE(m.at("lights").at("cell_rule").get<std::string>().find("cosine-barycentric"), std::string::npos);
    std::vector<Eigen::Vector3d> vert;
    for (const auto& v : t.at("vertices")) vert.emplace_back(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    const std::vector<int> owner = t.at("owner").get<std::vector<int>>();
    ASSERT_EQ(owner.size(), vert.size());
    std::vector<BtfLight> lights = hard_lights(e.lights);
    lights.push_back({btf::Direction{89.8, 123}.vector(), {5, 4, 3}});
    for (const BtfLight& l : lights) {
        std::vector<Eigen::Vector3d> mine(e.lights.size(), Eigen::Vector3d::Zero());
        const Eigen::Vector3d d = l.direction;
        for (const auto& tri : t.at("triangles")) {
            if (d.z() <= 0) break;
            const Eigen::Vector3d &a = vert[tri[0].get<size_t>()], &b = vert[tri[1].get<size_t>()],
                                  &c = vert[tri[2].get<size_t>()];
            const double w[3] = {d.dot(b.cross(c)), a.dot(d.cross(c)), a.dot(b.cross(d))};
            if (w[0] < -1e-12 || w[1] < -1e-12 || w[2] < -1e-12) continue;
            const double sum = std::max(0.0, w[0]) + std::max(0.0, w[1]) + std::max(0.0, w[2]);
            for (int i = 0; i < 3; ++i) {
                const int k = owner[tri[size_t(i)].get<size_t>()];
                if (k >= 0) mine[size_t(k)] += l.irradiance_w_m2 * (std::max(0.0, w[i]) / sum * d.z() / vert[size_t(k)].z());
            }
            break;
        }
        const std::vector<Eigen::Vector3d> theirs = btf_light_weights(e, {l});
        double lit = 0;
        for (size_t k = 0; k < mine.size(); ++k) {
            EXPECT_NEAR((mine[k] - theirs[k]).norm(), 0.0, 1e-12 * (1 + theirs[k].norm())) << "light direction " << k;
            lit += theirs[k].norm();
        }
        EXPECT_EQ(lit > 0, d.z() > 0) << "a light above the plane lights something, one below nothing";
    }
}

// A light of 12 degrees' radius spread as kBtfCapSamples (256) point lights against the exact
// cell weights of its disc drawn into a 1024 x 512 map (btf::integrate_dome_cells: each pixel's
// share by the export's rule, the cosine divided out, no sampling shared with the spread), at a
// mid-dome light, near the last ring and at the pole. The difference is the points' quadrature
// of the disc, falling with their number (measured L1 share under the cosine rule, whose
// weights jump at cell borders: 6-12% at 32 points, <= 6% at 128, <= 2.2% at 256, <= 1.4% at
// 512; under the default cosine-barycentric rule, whose weights are continuous, <= 0.8% at 256),
// plus the map's pixelisation of the disc (<= 0.8% of its area): 3% at 256 points.
TEST(BtfGlesFiles, ACapLightSpreadsLikeTheCellIntegralOfItsDisc) {
    BtfGlesOptions o;
    o.versions = {GlslVersion::kEs300};
    const BtfGlesExport e = export_btf_gles(folder3(), o);
    for (const btf::Direction centre : {btf::Direction{40, 100}, btf::Direction{70, 8}, btf::Direction{0, 0}}) {
        const double alpha = 12 * kPi / 180;
        const Eigen::Vector3d c = centre.vector(), radiance(3, 2, 1);
        image::Image map(1024, 512, 3);
        double solid_angle = 0;
        for (int y = 0; y < map.height; ++y) {
            for (int x = 0; x < map.width; ++x) {
                const Eigen::Vector3d d = latlong_direction((x + 0.5) / map.width, (y + 0.5) / map.height);
                if (d.dot(c) < std::cos(alpha)) continue;
                for (int ch = 0; ch < 3; ++ch) map.pixels[(static_cast<size_t>(y) * map.width + x) * 3 + ch] = float(radiance[ch]);
                solid_angle += latlong_pixel_solid_angle(y, map.width, map.height);
            }
        }
        const btf::DomeLighting exact = btf::integrate_dome_cells(map, e.lights, e.lighting);
        // The light as envmap's extraction gives it: the disc's radiance x solid angle.
        const std::vector<Eigen::Vector3d> spread =
            btf_light_weights(e, {{c, radiance * 2 * kPi * (1 - std::cos(alpha)), alpha}});
        double diff = 0, total = 0;
        for (size_t k = 0; k < spread.size(); ++k) {
            diff += std::abs(spread[k].x() - exact.weight[k].x());
            total += exact.weight[k].x();
        }
        std::printf("[btf-gles] cap at (%g, %g): weights' L1 difference %.4f of their sum (disc %.5f sr, cap %.5f sr)\n",
                    centre.theta_deg, centre.phi_deg, diff / total, solid_angle, 2 * kPi * (1 - std::cos(alpha)));
        EXPECT_GT(total, 0);
        EXPECT_LT(diff / total, 0.03) << "cap at " << centre.theta_deg << " " << centre.phi_deg;
    }
}

TEST(BtfGles, ShaderDecodeEqualsTheCpuDecoder) {
    // Weight 1 on one column of one slot, 0 elsewhere: the output is that column's decoded value,
    // which must equal CompressedBtf's (offset + scale x code / 255 in float) to float rounding.
    if (!have_context(3)) GTEST_SKIP() << "no EGL OpenGL ES 3 context";
    if (!context3().info().float_color_buffer) GTEST_SKIP() << "no RGBA32F target";
    BtfGlesOptions o;
    o.versions = {GlslVersion::kEs300};
    const BtfGlesExport e = export_btf_gles(folder6(), o);
    const auto btf = btf::CompressedBtf::open(folder6());
    const BtfGlesVariant& var = e.variants[0];
    const int s_used = var.slabs_used;
    double worst = 0;
    for (int g : {0, 13}) {
        for (int k = 0; k <= e.components[size_t(g)]; ++k) {
            BtfFrame f = btf_frame_weights(e, var, btf::Direction{0, 0}, Eigen::MatrixXd::Zero(sh::count(3), 3), 0);
            f.slot_group = {g, g, g};
            std::fill(f.weight.begin(), f.weight.end(), 0.f);
            // Weight 1 on column k, folded as btf_frame_weights folds it: u_weight = scale,
            // u_bias = offset (slot 0, red).
            f.weight[size_t((0 * s_used) * 4 + k)] = e.scale[size_t(g)][size_t(k)];
            f.bias = {e.offset[size_t(g)][size_t(k)], 0.f, 0.f, 0.f};
            const Readback out = draw(context3(), var.as_export, btf_bindings(e, f), btf_sample_quad(), kWidth, kHeight,
                                      TargetFormat::kRgba32f);
            const Eigen::VectorXf col = k == 0 ? btf->group_mean(g) : Eigen::VectorXf(btf->group_basis(g).col(k - 1));
            for (int y = 0; y < kHeight; ++y) {
                for (int x = 0; x < kWidth; ++x) {
                    const double want = col[y * kWidth + x];
                    worst = std::max(worst, std::abs(out.at(x, y, 0) - want) / (std::abs(e.offset[size_t(g)][size_t(k)]) +
                                                                                 std::abs(e.scale[size_t(g)][size_t(k)])));
                    EXPECT_EQ(out.at(x, y, 1), 0.f);
                }
            }
        }
    }
    // Relative to |offset| + |scale|: the GPU's code / 255 and a possibly fused multiply-add
    // differ from the CPU's float ops by a few ulps (2^-23 = 1.2e-7 each): 1e-6.
    EXPECT_LE(worst, 1e-6);
    std::printf("[btf-gles] decode: worst difference %.3g of |offset| + |scale|\n", worst);
}

TEST(BtfGlesFiles, MatricesFileHoldsEveryViewsLightingMatrix) {
    BtfGlesOptions o;
    o.sh_bands = 3;
    const BtfGlesExport e = export_btf_gles(folder3(), o);
    const auto btf = btf::CompressedBtf::open(folder3());
    std::string bin;
    for (const auto& [name, bytes] : e.files()) {
        if (name == e.manifest["matrices"]["file"]) bin = bytes;
    }
    ASSERT_EQ(static_cast<int64_t>(bin.size()), e.manifest["matrices"]["bytes"].get<int64_t>());
    const Eigen::MatrixXd a = btf::sh_light_weight_matrix(btf->shape().lights, 3, o.lighting, o.map_height);
    const int cols = e.manifest["matrices"]["columns"];
    for (int v : {0, 40, 80}) {
        const auto& vj = e.manifest["views"][size_t(v)];
        const int rows = vj["rows"];
        const int64_t off = vj["offset_bytes"];
        for (int ch = 0; ch < 3; ++ch) {
            const Eigen::MatrixXd m = btf->lighting_matrix(v, ch, a, 1.0);
            for (int r = 0; r < rows; ++r) {
                for (int j = 0; j < cols; ++j) {
                    float f;
                    std::memcpy(&f, bin.data() + off + 4 * ((ch * rows + r) * cols + j), 4);  // little-endian host
                    EXPECT_EQ(f, static_cast<float>(m(r, j))) << v << " " << ch << " " << r << " " << j;
                }
            }
        }
    }
    // Same inputs, same bytes.
    const auto again = export_btf_gles(folder3(), o).files();
    const auto first = e.files();
    ASSERT_EQ(again.size(), first.size());
    for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(again[i], first[i]) << first[i].first;
    // Atlas layout: slab 0 channel k of group 2 is column k's code.
    const auto& t = e.atlases[2];
    EXPECT_EQ(t.width, kWidth);
    EXPECT_EQ(t.height, kHeight * e.slabs);
    for (int k = 0; k <= e.components[2]; ++k) {
        const Eigen::VectorXf col = k == 0 ? btf->group_mean(2) : Eigen::VectorXf(btf->group_basis(2).col(k - 1));
        for (int p = 0; p < kWidth * kHeight; p += 7) {
            const float dec = e.offset[2][size_t(k)] + e.scale[2][size_t(k)] * (t.rgba[size_t(p * 4 + k)] / 255.0f);
            // The folder's reader gets code / 255 from OpenImageIO (code x (1 / 255) in float): an ulp
            // from code / 255.0f, so the decoded values agree to 2 ulps of |offset| + |scale|.
            const double ulp = (std::abs(e.offset[2][size_t(k)]) + std::abs(e.scale[2][size_t(k)])) * 1.2e-7;
            EXPECT_NEAR(dec, col[p], 2 * ulp) << "column " << k << " pixel " << p;
        }
    }
}

/// The files of an export by name.
std::map<std::string, std::string> files_of(const BtfGlesExport& e) {
    std::map<std::string, std::string> out;
    for (auto& [name, bytes] : e.files()) out[name] = bytes;
    return out;
}

TEST(BtfGlesFiles, AtlasesAssembleFromTheFoldersPngsByTheManifestAlone) {
    // The app's assembly (textures.assembly) from btf-gles.json and the folder's PNGs, decoded
    // here without the export's reader: every atlas byte equals the export's, for both slabs.
    const std::string dir = folder6();
    BtfGlesOptions o;
    const BtfGlesExport written = export_btf_gles(dir, o);
    o.write_atlases = false;
    const BtfGlesExport none = export_btf_gles(dir, o);
    const auto wf = files_of(written), nf = files_of(none);
    const nlohmann::json m = nlohmann::json::parse(nf.at("btf-gles.json"));
    EXPECT_EQ(m["textures"]["atlas_files"], false);
    EXPECT_EQ(nlohmann::json::parse(wf.at("btf-gles.json"))["textures"]["atlas_files"], true);
    // No atlas PNG without them; every other file the same bytes.
    EXPECT_EQ(wf.size(), nf.size() + written.atlases.size());
    for (const auto& [name, bytes] : nf) {
        if (name != "btf-gles.json") {
            EXPECT_EQ(bytes, wf.at(name)) << name;
        }
    }
    const int w = m["image"]["width"], h = m["image"]["height"];
    const auto& groups = m["textures"]["groups"];
    ASSERT_EQ(groups.size(), written.atlases.size());
    image::ReadOptions raw;
    raw.decode_srgb = false;
    int files_used = 0, unused = 0;
    for (size_t g = 0; g < groups.size(); ++g) {
        EXPECT_TRUE(groups[g]["file"].is_null());
        const auto& channels = groups[g]["channels"];
        const size_t slabs = channels.size() / 4;
        ASSERT_EQ(channels.size() % 4, 0u);
        std::vector<uint8_t> atlas(size_t(w) * h * slabs * 4, 0);
        for (size_t k = 0; k < channels.size(); ++k) {
            if (channels[k]["file"].is_null()) {
                ++unused;
                continue;
            }
            const image::Image png = image::read_image(dir + "/" + channels[k]["file"].get<std::string>(), raw);
            ASSERT_EQ(png.width, w);
            ASSERT_EQ(png.height, h);
            ++files_used;
            for (int y = 0; y < h; ++y) {
                for (int x = 0; x < w; ++x) {
                    const size_t texel = (k / 4) * size_t(w) * h + size_t(y) * w + size_t(x);
                    atlas[texel * 4 + k % 4] = static_cast<uint8_t>(std::lround(png.at(x, y, 0) * 255.0f));
                }
            }
        }
        EXPECT_EQ(atlas, written.atlases[g].rgba) << "group " << g;
        // And the written atlas PNG decodes to those bytes.
        const std::string path = inlight::testing::temp_dir("btf_gles_atlas") + "/a.png";
        fs::write_text_atomic(path, wf.at(str("g", g < 10 ? "00" : "0", g, "-atlas.png")));
        const image::Image png = image::read_image(path, raw);
        ASSERT_EQ(png.pixels.size(), atlas.size());
        for (size_t i = 0; i < atlas.size(); ++i) {
            ASSERT_EQ(std::lround(png.pixels[i] * 255.0f), atlas[i]) << "group " << g << " byte " << i;
        }
    }
    // 27 groups x (mean + 6 components), one unused channel each (2 slabs: 8 channels).
    EXPECT_EQ(files_used, 27 * 7);
    EXPECT_EQ(unused, 27);
}

TEST(BtfGlesFiles, LoadTableNamesOnlyExportedVariantsThatDrawTheWholeStream) {
    const auto check_names = [](const BtfGlesExport& e) {
        const auto f = files_of(e);
        for (const auto& c : e.manifest["load"]) {
            if (c["variant"].is_null()) continue;
            const std::string n = c["variant"];
            EXPECT_TRUE(f.count(n + ".frag") && f.count(n + ".vert")) << n << " named but not exported";
            EXPECT_EQ(c["manifest"], "btf-gles.json");
            EXPECT_EQ(c["validated"], true);
        }
    };
    BtfGlesOptions o;
    const BtfGlesExport c3 = export_btf_gles(folder3(), o);
    const nlohmann::json& l3 = c3.manifest["load"];
    ASSERT_EQ(l3.size(), 3u);
    EXPECT_EQ(l3[0]["capability"], "OpenGL ES 3.0 or later");
    EXPECT_EQ(l3[0]["variant"], "btf-es300-highp");
    EXPECT_EQ(l3[1]["capability"], "OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH");
    EXPECT_EQ(l3[1]["variant"], "btf-es100-highp");  // 3 components: one slab holds them
    EXPECT_EQ(l3[2]["capability"], "OpenGL ES 2.0 without GL_FRAGMENT_PRECISION_HIGH");
    EXPECT_TRUE(l3[2]["variant"].is_null());
    EXPECT_NE(l3[2]["why"].get<std::string>().find("mediump is refused"), std::string::npos);
    check_names(c3);
    // 6 components: ES 1.00 reads both slabs, 19 vectors (9 x 2 + 1), above ES 2.0's guaranteed 16: its entry
    // says so, and a fourth names no variant for a device that reports fewer.
    const BtfGlesExport c6 = export_btf_gles(folder6(), o);
    const nlohmann::json& l6 = c6.manifest["load"];
    ASSERT_EQ(l6.size(), 4u);
    EXPECT_EQ(l6[0]["variant"], "btf-es300-highp");
    EXPECT_EQ(l6[1]["capability"], "OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH");
    EXPECT_EQ(l6[1]["variant"], "btf-es100-highp");
    EXPECT_EQ(l6[1]["requires"]["max_fragment_uniform_vectors"], 19);
    EXPECT_NE(l6[1]["why"].get<std::string>().find("GL_MAX_FRAGMENT_UNIFORM_VECTORS >= 19"), std::string::npos);
    EXPECT_TRUE(l6[2]["variant"].is_null());
    EXPECT_EQ(l6[3]["capability"],
              "OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH and GL_MAX_FRAGMENT_UNIFORM_VECTORS < 19");
    EXPECT_TRUE(l6[3]["variant"].is_null());
    EXPECT_FALSE(l3[1].contains("requires"));  // one slab: 10 vectors, within every ES 2.0 device
    check_names(c6);
    for (const auto& v : c6.manifest["variants"]) {
        EXPECT_EQ(v["slabs_read"], 2) << v["name"];
        EXPECT_EQ(v["max_components_per_group"], 7) << v["name"];
    }
    nlohmann::json es100_limits;
    for (const auto& v : c6.manifest["variants"])
        if (v["glsl_version"] == "100") es100_limits = v["gl_limits_needed"];
    ASSERT_TRUE(es100_limits.is_object());
    EXPECT_EQ(es100_limits["max_fragment_uniform_vectors"], 19);
    EXPECT_EQ(es100_limits["max_fragment_uniform_vectors_guaranteed"], 16);
    EXPECT_NE(es100_limits["note"].get<std::string>().find("check GL_MAX_FRAGMENT_UNIFORM_VECTORS"), std::string::npos);
    // Only what is exported: ES 3.00 alone leaves ES 2.0 without; ES 1.00 alone serves ES 3.0 too.
    o.versions = {GlslVersion::kEs300};
    const nlohmann::json l300 = export_btf_gles(folder3(), o).manifest["load"];
    EXPECT_EQ(l300[0]["variant"], "btf-es300-highp");
    EXPECT_TRUE(l300[1]["variant"].is_null());
    EXPECT_NE(l300[1]["why"].get<std::string>().find("not exported"), std::string::npos);
    o.versions = {GlslVersion::kEs100};
    const BtfGlesExport e100 = export_btf_gles(folder3(), o);
    EXPECT_EQ(e100.manifest["load"][0]["variant"], "btf-es100-highp");
    EXPECT_EQ(e100.manifest["load"][1]["variant"], "btf-es100-highp");
    check_names(e100);
    // ES 1.00 alone serves ES 3.0 whatever C: its 19 vectors are within ES 3.0's 224.
    EXPECT_EQ(export_btf_gles(folder6(), o).manifest["load"][0]["variant"], "btf-es100-highp");
}

TEST(BtfGlesFiles, ShadersPassGlslangValidator) {
    // The reference compiler for each GLSL ES version, independent of the driver the draws ran on.
    ASSERT_EQ(std::system("glslangValidator --version > /dev/null 2>&1"), 0)
        << "glslangValidator (Debian glslang-tools, in make deps) is required";
    const std::string dir = inlight::testing::temp_dir("btf_gles_glslang");
    const BtfGlesExport e = export_btf_gles(folder6(), {});
    ASSERT_EQ(e.variants.size(), 2u);
    for (const auto& [name, bytes] : e.files()) {
        if (name.size() < 5 || (name.substr(name.size() - 5) != ".vert" && name.substr(name.size() - 5) != ".frag"))
            continue;
        const std::string path = dir + "/" + name;
        fs::write_text_atomic(path, bytes);
        std::string log;
        EXPECT_EQ(testing::run_glslang(path, &log), 0) << path << "\n" << log << "\n" << bytes;
    }
}

TEST(BtfGlesFiles, RefusesWhatItCannotDraw) {
    BtfGlesOptions o;
    const std::string srgb = make_folder("btf_gles_srgb", 2, btf::FitSpace::kSrgb);
    EXPECT_THROW(export_btf_gles(srgb, o), Error);
    const std::string exr = make_folder("btf_gles_exr", 2, btf::FitSpace::kLinear, btf::ComponentEncoding::kExrHalf);
    EXPECT_THROW(export_btf_gles(exr, o), Error);
    EXPECT_THROW(export_btf_gles(inlight::testing::temp_dir("btf_gles_empty"), o), Error);
    o.sh_bands = 10;
    EXPECT_THROW(export_btf_gles(folder3(), o), UsageError);
    // ES 1.00 reads both slabs of C = 6 and shows the whole stream; a variant reading one slab
    // (made by hand: none is exported) refuses a prefix with more than 3 components in a group.
    BtfGlesOptions o2;
    o2.versions = {GlslVersion::kEs100};
    const BtfGlesExport e = export_btf_gles(folder6(), o2);
    EXPECT_EQ(e.variants[0].slabs_used, 2);
    EXPECT_EQ(e.variants[0].fragment_uniform_vectors, 19);
    const auto all = static_cast<int64_t>(e.stream.size());
    EXPECT_NO_THROW(btf_frame_weights(e, e.variants[0], {0, 0}, lighting(3, 1), all));
    BtfGlesVariant one_slab = e.variants[0];
    one_slab.slabs_used = 1;
    EXPECT_THROW(btf_frame_weights(e, one_slab, {0, 0}, lighting(3, 1), all), Error);
    // 96 components in a group need 25 slabs, 226 vectors: more than ES 3.0 guarantees (224), so
    // neither version is exported (95 would fit: 24 slabs, 217). The manifest of folder6 lists
    // its PNGs again as components 6-95.
    const std::string big = inlight::testing::temp_dir("btf_gles_c96");
    std::filesystem::copy(folder6(), big, std::filesystem::copy_options::overwrite_existing |
                                              std::filesystem::copy_options::recursive);
    nlohmann::json m = nlohmann::json::parse(fs::read_file(big + "/btf-pca.json"));
    auto& comps = m["groups"][0]["components"];
    for (int k = 6; k < 96; ++k) comps.push_back(comps[static_cast<size_t>(k % 6)]);
    fs::write_text_atomic(big + "/btf-pca.json", m.dump(2));
    for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        BtfGlesOptions o3;
        o3.versions = {ver};
        try {
            export_btf_gles(big, o3);
            ADD_FAILURE() << "96 components exported";
        } catch (const Error& err) {
            EXPECT_NE(std::string(err.what()).find("226 fragment uniform vectors, OpenGL ES 3.0 guarantees 224"),
                      std::string::npos) << err.what();
        }
    }
}

}  // namespace
}  // namespace inlight::gles
