#include "btf/pca_run.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <algorithm>

#include "btf/compressed.h"
#include "btf/quantize.h"
#include "btf/synthetic.h"
#include "core/fs.h"
#include "image/color.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

namespace stdfs = std::filesystem;

/// The run sums squared errors in double over float32 residuals; the decoder recomputes them
/// from float32 files in another order: both agree to float32 rounding of values <= 1
/// (relative ~1e-6 of the RMSE, with margin).
constexpr double kRmseRelTol = 1e-4;

AnalyticBtfOptions small_btf() {
    AnalyticBtfOptions o;
    o.width = 20;
    o.height = 14;
    o.rank = 5;
    o.lights = {{0, 0}, {15, 0}, {15, 120}, {30, 60}, {30, 240}, {45, 0}, {60, 90}, {75, 300}};
    o.views = {{0, 0}, {30, 0}, {30, 120}, {45, 180}, {60, 270}};
    return o;
}

PcaRunOptions run_options(const std::string& name, int k, int c) {
    PcaRunOptions o;
    o.output = testing::temp_dir(name);
    o.pca.view_group_size = k;
    o.pca.components = c;
    return o;
}

/// RMSE over every sample between two sources (the decoder's images and the truth).
double rmse_between(const BtfSource& a, const BtfSource& b, const std::function<image::Image(int, int)>& decode) {
    double sse = 0;
    const BtfShape& s = a.shape();
    for (int v = 0; v < s.n_views(); ++v)
        for (int l = 0; l < s.n_lights(); ++l) {
            const image::Image x = decode(l, v), y = b.read_image(l, v);
            for (size_t i = 0; i < x.pixels.size(); ++i) sse += std::pow(double(x.pixels[i]) - y.pixels[i], 2);
        }
    return std::sqrt(sse / s.sample_count());
}

TEST(Quantize8, EveryValueWithinHalfAStep) {
    const float v[] = {-0.25f, 0.0f, 0.1f, 0.7f, 1.75f};
    const Quantized8 q = quantize8(v, 5);
    EXPECT_FLOAT_EQ(q.offset, -0.25f);
    EXPECT_FLOAT_EQ(q.scale, 2.0f / 255);
    for (int i = 0; i < 5; ++i) EXPECT_LE(std::abs(q.value(i) - v[i]), 0.5f * q.scale * (1 + 1e-5f));
    EXPECT_EQ(q.codes.front(), 0);
    EXPECT_EQ(q.codes.back(), 255);
    const float c[] = {0.3f, 0.3f};
    const Quantized8 k = quantize8(c, 2);
    EXPECT_EQ(k.scale, 0.0f);
    EXPECT_EQ(k.value(1), 0.3f);
}

TEST(ThesisPacking, FactorIsTheLargestPowerOfTenKeepingTheRange) {
    EXPECT_EQ(thesis_factor(0.03), 10.0);
    EXPECT_EQ(thesis_factor(0.5), 1.0);
    EXPECT_EQ(thesis_factor(0.0004), 1000.0);
    EXPECT_EQ(thesis_factor(0.0), 1.0);
    EXPECT_EQ(thesis_factor(3.0), 1.0);
}

// The files decode to exactly the model whose error the run reports: the RMSE of the decoded
// BTF against the source equals metrics.error.rmse_linear, and the RMSE after j streamed
// components equals the curve's point j. PNG (quantised) and float EXR (the unquantised model).
TEST(CompressToFolder, FilesDecodeToTheReportedErrorAndStreamingCurve) {
    const AnalyticBtf btf(small_btf());
    for (ComponentEncoding e : {ComponentEncoding::kPng8, ComponentEncoding::kExrFloat}) {
        SCOPED_TRACE(to_string(e));
        PcaRunOptions o = run_options("btf_pca_run_" + to_string(e), 2, 3);
        o.encoding = e;
        const nlohmann::json m = compress_to_folder(btf, o, 0);
        const auto dec = CompressedBtf::open(o.output);
        ASSERT_EQ(dec->shape().n_views(), 5);
        EXPECT_EQ(m["pca"]["groups"], 3);  // 5 views in pairs: 2 + 2 + 1
        const double rmse = m["error"]["rmse_linear"];
        EXPECT_NEAR(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image(l, v); }), rmse, kRmseRelTol * rmse);
        if (e == ComponentEncoding::kExrFloat) {
            EXPECT_NEAR(rmse, m["error"]["rmse_linear_unquantised"].get<double>(), kRmseRelTol * rmse);
        } else {
            EXPECT_GT(rmse, m["error"]["rmse_linear_unquantised"].get<double>());  // 8 bits cost
        }
        const auto& curve = m["streaming"];
        ASSERT_EQ(dec->stream_length(), 9);
        ASSERT_EQ(curve["rmse_linear"].size(), 10u);
        for (int j : {0, 1, 4, 9}) {
            const double want = curve["rmse_linear"][j];
            EXPECT_NEAR(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image_streamed(l, v, j); }),
                        want, kRmseRelTol * want) << j;
        }
        for (size_t j = 1; j < curve["bytes_sent"].size(); ++j)
            EXPECT_GT(curve["bytes_sent"][j].get<double>(), curve["bytes_sent"][j - 1].get<double>());
        EXPECT_LT(curve["rmse_linear"][9].get<double>(), curve["rmse_linear"][0].get<double>());
    }
}

// A singular value whose digits need more than four is kept whole (the thesis: "adapt this
// technique further"), not clamped, and counted.
TEST(ThesisPacking, SigmaBeyondFourDigitsIsKeptAndCounted) {
    GroupPca g;
    g.pixels = 4;
    g.columns = 2;
    g.mean = Eigen::Vector4f(0.2f, 0.4f, 0.6f, 0.8f);
    g.basis = Eigen::MatrixXf::Zero(4, 2);
    g.basis(0, 0) = 1000;  // sigma 1000, u = (1, 0, 0, 0): factor_u = 1
    g.basis(1, 1) = 0.5f;  // sigma 0.5, u = (0, 1, 0, 0)
    g.weights = Eigen::MatrixXf::Identity(2, 2);  // factor_v = 1
    const ThesisGroup t = pack_thesis(g, 2);
    EXPECT_EQ(t.factor_u, 1.0);
    EXPECT_EQ(t.factor_v, 1.0);
    ASSERT_EQ(t.sigma_digits.size(), 2u);
    EXPECT_EQ(t.sigma_digits[0], 255000);  // 255 x 1000: six digits
    EXPECT_EQ(t.sigma_digits[1], 128);     // round(127.5)
    EXPECT_EQ(t.sigma_overflows, 1);
    const StoredGroup s = t.decoded();
    EXPECT_FLOAT_EQ(s.basis(0, 0), 1000.0f);  // code 255: f^-1 = 1, times 255000 / 255
    EXPECT_NEAR(s.basis(1, 1), 128.0 / 255, 1e-6);
    EXPECT_NEAR(s.basis(2, 0), 1000.0 / 255, 1e-3);  // u = 0 sits on code 128 (f(0) = 127.5 rounds up): 1 / 255 x 1000
    EXPECT_EQ(t.mean_codes, (std::vector<uint8_t>{51, 102, 153, 204}));
    EXPECT_FLOAT_EQ(s.weights(0, 0), 1.0f);
    EXPECT_NEAR(s.weights(1, 0), 1.0 / 255, 1e-7);  // 0 -> code 128 -> 2 x 128 / 255 - 1
}

// Our 8-bit storage against the thesis' packing on the same model: ours uses each component's
// own range, so its error is smaller; the thesis' power-of-ten scaling leaves unit-norm U
// columns on few of the 256 levels.
TEST(CompressToFolder, OurPackingBeatsTheThesisPacking) {
    const AnalyticBtf btf(small_btf());
    const PcaRunOptions o = run_options("btf_pca_run_packing", 5, 5);
    const nlohmann::json m = compress_to_folder(btf, o, 0);
    EXPECT_LT(m["error"]["rmse_rgb8"].get<double>(), m["thesis_packing"]["rmse_rgb8"].get<double>());
    EXPECT_EQ(m["error"]["color_triples"], 20 * 14 * 8 * 5);  // all triples: below color_samples
}

// A table row cut to c components is the run with C = c: the Gram fit's leading components do
// not depend on C, and each component is quantised on its own, so the figures agree.
TEST(CompressToFolder, TableRowsEqualRunsWithThatManyComponents) {
    const AnalyticBtf btf(small_btf());
    PcaRunOptions o = run_options("btf_pca_table_all", 2, 4);
    o.table_components = {1, 2, 4};
    const nlohmann::json all = compress_to_folder(btf, o, 0);
    ASSERT_EQ(all["table"].size(), 3u);
    for (int i : {0, 1}) {
        PcaRunOptions one = o;
        one.output = testing::temp_dir("btf_pca_table_" + std::to_string(i));
        one.pca.components = o.table_components[static_cast<size_t>(i)];
        one.table_components.clear();
        const nlohmann::json m = compress_to_folder(btf, one, 0);
        const auto& row = all["table"][static_cast<size_t>(i)];
        for (const char* key : {"rmse_linear", "mae_lab", "delta_e2000_mean", "rmse_rgb8"})
            EXPECT_NEAR(row[key].get<double>(), m["error"][key].get<double>(), kRmseRelTol * m["error"][key].get<double>()) << key << " C=" << one.pca.components;
        // the same files, the manifest too (the row counts the manifest listing its components)
        EXPECT_EQ(row["stored_bytes"], m["bytes"]["stored"]);
        EXPECT_EQ(row["manifest_bytes"], m["bytes"]["manifest"]);
    }
    EXPECT_NEAR(all["table"][2]["mae_lab"].get<double>(), all["error"]["mae_lab"].get<double>(), 1e-12);
}

// --reference: measured against itself the input has no error and every row's figures against
// the reference are the row's own (the same triples); another BTF of the same shape gives an
// error; another shape is an Error naming the option.
TEST(CompressToFolder, ReferenceMeasuresInputAndRowsAgainstASecondBtf) {
    // The run's input value is float(a - m) + m, one float rounding (<= 6e-8) from the value read;
    // times the steepest slopes (8-bit sRGB code 255 x 12.92, L* 903.3) that is < 1e-4 units.
    constexpr double kRoundTrip = 1e-3;
    const AnalyticBtf btf(small_btf());
    PcaRunOptions o = run_options("btf_pca_ref_self", 2, 4);
    o.table_components = {1, 4};
    o.reference = "self";
    const nlohmann::json m = compress_to_folder(btf, o, 0, nullptr, &btf);
    for (const char* key : {"mae_lab", "mae_rgb8", "rmse_rgb8", "delta_e2000_mean"}) {
        EXPECT_NEAR(m["reference"]["input"][key].get<double>(), 0.0, kRoundTrip) << key;
        for (const auto& row : m["table"])
            EXPECT_NEAR(row["vs_reference"][key].get<double>(), row[key].get<double>(), kRoundTrip) << key;
    }
    AnalyticBtfOptions brighter = small_btf();
    brighter.scale = 1.5;
    const AnalyticBtf other(brighter);
    o.output = testing::temp_dir("btf_pca_ref_other");
    const nlohmann::json x = compress_to_folder(btf, o, 0, nullptr, &other);
    EXPECT_GT(x["reference"]["input"]["mae_rgb8"].get<double>(), 1.0);  // scale 1.5: codes differ by more than 1
    EXPECT_EQ(x["table"][1]["mae_lab"].get<double>(), m["table"][1]["mae_lab"].get<double>());
    AnalyticBtfOptions wide = small_btf();
    wide.width = 21;
    const AnalyticBtf bad(wide);
    o.output = testing::temp_dir("btf_pca_ref_bad");
    o.reference = "wide/";
    const std::string err = testing::error_of([&] { compress_to_folder(btf, o, 0, nullptr, &bad); });
    EXPECT_NE(err.find("--reference wide/"), std::string::npos) << err;
}

/// A BTF whose sRGB-encoded values are a rank-one product a_p b_j (p pixel, j the column of the
/// whole BTF's layout), a in [0.2, 0.9], b in [0.3, 1]: linear values srgb_decode(a_p b_j).
/// Mean-centred per pixel within any group it stays of rank one, a (b - mean b)^T, in the
/// encoded values, but not in the linear ones (the sRGB curve is not a power law).
class EncodedRankOne : public BtfSource {
  public:
    EncodedRankOne() {
        const AnalyticBtfOptions o = small_btf();
        m_shape.lights = o.lights;
        m_shape.views = o.views;
        m_shape.width = o.width;
        m_shape.height = o.height;
    }
    const BtfShape& shape() const override { return m_shape; }
    image::Image read_image(int light, int view) const override {
        image::Image img(m_shape.width, m_shape.height, 3, image::ColorSpace::kLinearSrgb);
        for (int64_t p = 0; p < m_shape.pixel_count(); ++p)
            for (int ch = 0; ch < 3; ++ch) {
                const int64_t j = (int64_t(view) * m_shape.n_lights() + light) * 3 + ch;
                const double a = 0.2 + 0.7 * double((p * 7) % 13) / 12, b = 0.3 + 0.7 * double((j * 5) % 11) / 10;
                img.pixels[static_cast<size_t>(p * 3 + ch)] = image::srgb_decode(float(a * b));
            }
        return img;
    }

  private:
    BtfShape m_shape;
};

/// A BTF whose CIELAB values are of rank two with its per-pixel mean: (L*, a*, b*) = (10 + 75 x y,
/// 8 x y', -8 x y'') with x per pixel and y, y', y'' per image, well inside the sRGB gamut.
class LabLowRank : public EncodedRankOne {
  public:
    image::Image read_image(int light, int view) const override {
        const BtfShape& s = shape();
        image::Image img(s.width, s.height, 3, image::ColorSpace::kLinearSrgb);
        const int64_t j = int64_t(view) * s.n_lights() + light;
        const double y[3] = {0.3 + 0.7 * double((j * 5) % 11) / 10, double((j * 3) % 7) / 6 - 0.5, double((j * 2) % 5) / 4 - 0.5};
        for (int64_t p = 0; p < s.pixel_count(); ++p) {
            const double x = 0.4 + 0.6 * double((p * 7) % 13) / 12;
            const Eigen::Vector3d rgb = image::linear_srgb_from_lab(Eigen::Vector3d(10 + 75 * x * y[0], 8 * x * y[1], -8 * x * y[2]));
            for (int ch = 0; ch < 3; ++ch) img.pixels[static_cast<size_t>(p * 3 + ch)] = float(rgb[ch]);
        }
        return img;
    }
};

// --fit-space lab: data of low rank in CIELAB is reproduced by its rank (float EXR storage), where
// the linear fit is not; the decoder converts each pixel's Lab back to linear values.
TEST(CompressToFolder, LabFitSpaceReproducesDataOfLowRankInLab) {
    // Lab values <= 85 in float32: ~5e-6 each; the Lab -> linear slope is below 0.03 per unit of
    // L* here, so linear values carry ~1e-7: 1e-5 (Lab units: 1e-4) leaves a margin of ~25.
    constexpr double kFloatRounding = 1e-5, kLabRounding = 1e-4;
    const LabLowRank btf;
    PcaRunOptions o = run_options("btf_pca_lab_linear", 2, 2);
    o.encoding = ComponentEncoding::kExrFloat;
    const nlohmann::json lin = compress_to_folder(btf, o, 0);
    o.output = testing::temp_dir("btf_pca_lab");
    o.fit_space = FitSpace::kLab;
    const nlohmann::json lab = compress_to_folder(btf, o, 0);
    EXPECT_EQ(lab["error_space"], "cielab_d65");
    EXPECT_EQ(lab["pca"]["fit_space"], "lab");
    EXPECT_LT(lab["error"]["rmse_linear"].get<double>(), kLabRounding);  // in Lab units (error_space)
    EXPECT_LT(lab["error"]["mae_lab"].get<double>(), kLabRounding);
    // The linear fit of the same C does not reproduce it (measured 800x the Lab fit's MAE).
    EXPECT_GT(lin["error"]["mae_lab"].get<double>(), 100 * lab["error"]["mae_lab"].get<double>());
    const auto dec = CompressedBtf::open(o.output);
    EXPECT_EQ(dec->fit_space(), FitSpace::kLab);
    EXPECT_EQ(dec->manifest()["color_space"], "cielab_d65");
    EXPECT_LT(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image(l, v); }), kFloatRounding);
    const std::vector<ImageTerm> terms = {{1, 0, Eigen::Vector3d(0.5, 0.25, 1.0)}, {7, 4, Eigen::Vector3d(1.0, 1.0, 1.0)}};
    const image::Image sum = dec->combine(terms), want = btf.combine(terms);
    ASSERT_EQ(sum.pixels.size(), want.pixels.size());
    for (size_t i = 0; i < sum.pixels.size(); ++i) ASSERT_NEAR(sum.pixels[i], want.pixels[i], 2 * kFloatRounding) << i;  // weights sum to <= 2
    EXPECT_EQ(fit_space_from_string("lab"), FitSpace::kLab);
}

// --fit-norm l1 lowers the MAE figures of a group with outliers below the PCA's at the same C,
// and is refused before any work when a group would be fitted out of core.
TEST(CompressToFolder, L1RefitLowersMaeAndNeedsGroupsInMemory) {
    const EncodedRankOne btf;  // rank one in sRGB-encoded values: in linear values the PCA leaves a heavy-tailed residual
    PcaRunOptions o = run_options("btf_pca_l2", 2, 1);
    o.encoding = ComponentEncoding::kExrFloat;
    const nlohmann::json l2 = compress_to_folder(btf, o, 0);
    o.output = testing::temp_dir("btf_pca_l1");
    o.pca.l1_iterations = 8;
    const nlohmann::json l1 = compress_to_folder(btf, o, 0);
    EXPECT_EQ(l1["pca"]["fit_norm"], "l1");
    EXPECT_EQ(l2["pca"]["fit_norm"], "l2");
    EXPECT_LT(l1["error"]["mae_linear"].get<double>(), l2["error"]["mae_linear"].get<double>());
    // Least squares is the RMSE optimum among models of C components: the refit cannot beat it.
    EXPECT_GE(l1["error"]["rmse_linear"].get<double>(), l2["error"]["rmse_linear"].get<double>() * (1 - 1e-6));
    o.output = testing::temp_dir("btf_pca_l1_streamed");
    o.pca.stream_views = 1;
    const std::string err = testing::error_of([&] { compress_to_folder(btf, o, 0); });
    EXPECT_NE(err.find("--fit-norm l1"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(o.output + "/btf-pca.json"));
}

// --fit-space srgb: data of rank one in encoded values is reproduced by one component (float
// EXR storage, so only float rounding remains), where the linear fit leaves an error; the
// decoder returns linear values (the manifest says srgb_encoded) and sums images after decoding.
TEST(CompressToFolder, SrgbFitSpaceReproducesDataOfRankOneInEncodedValues) {
    // Float32 values <= 1 through a double Gram fit and float storage: ~1e-7 per value; the
    // sRGB decode's slope is at most 2.4 / 1.055 = 2.3 on [0, 1]: 1e-5 leaves a margin of ~40.
    constexpr double kFloatRounding = 1e-5;
    const EncodedRankOne btf;
    PcaRunOptions o = run_options("btf_pca_srgb_linear", 2, 1);
    o.encoding = ComponentEncoding::kExrFloat;
    const nlohmann::json lin = compress_to_folder(btf, o, 0);
    EXPECT_EQ(lin["error_space"], "linear_srgb");
    o.output = testing::temp_dir("btf_pca_srgb_encoded");
    o.fit_space = FitSpace::kSrgb;
    const nlohmann::json enc = compress_to_folder(btf, o, 0);
    EXPECT_EQ(enc["error_space"], "srgb_encoded");
    EXPECT_EQ(enc["pca"]["fit_space"], "srgb");
    EXPECT_LT(enc["error"]["rmse_linear"].get<double>(), kFloatRounding);
    // Not of rank one in linear values: a pure power law would keep products of rank one; the
    // sRGB curve's offset and linear toe leave 4.3e-4 (measured), 43x the tolerance above.
    EXPECT_GT(lin["error"]["rmse_linear"].get<double>(), 10 * kFloatRounding);
    EXPECT_LT(enc["error"]["mae_lab"].get<double>(), 0.01 * lin["error"]["mae_lab"].get<double>());

    const auto dec = CompressedBtf::open(o.output);
    EXPECT_EQ(dec->fit_space(), FitSpace::kSrgb);
    EXPECT_EQ(dec->manifest()["color_space"], "srgb_encoded");
    EXPECT_LT(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image(l, v); }), kFloatRounding);
    // combine = the weighted sum of the decoded (linear) images, not of the encoded model
    const std::vector<ImageTerm> terms = {{1, 0, Eigen::Vector3d(0.5, 0.25, 1.0)},
                                          {3, 2, Eigen::Vector3d(0.5, 2.0, 0.0)},
                                          {7, 4, Eigen::Vector3d(1.0, 1.0, 1.0)}};
    const image::Image sum = dec->combine(terms), want = btf.combine(terms);
    ASSERT_EQ(sum.pixels.size(), want.pixels.size());
    for (size_t i = 0; i < sum.pixels.size(); ++i) ASSERT_NEAR(sum.pixels[i], want.pixels[i], 4 * kFloatRounding) << i;  // 4: the weights' magnitudes sum to <= 3.25 per channel

    EXPECT_EQ(fit_space_from_string("srgb"), FitSpace::kSrgb);
    EXPECT_NE(testing::error_of([] { fit_space_from_string("log"); }).find("log"), std::string::npos);
}

// --codec thesis writes the thesis' method (sections 4.3 and 6.1), checked against an
// independent fit: Eigen's BDCSVD in double of each group's matrix of sRGB-encoded values
// (k consecutive views, centred per pixel). Its files hold the SVD's U, Sigma and V through the
// thesis' packing: one power-of-ten factor per matrix, the largest keeping [-1, 1]; Sigma as
// round(255 sigma / (factor_u factor_v)); U Sigma decoded within the packing's own rounding; V's
// codes f(factor_v v) in weights.bin; the stream component by component across groups; and the
// folder decodes to the error the run reports.
TEST(CompressToFolder, ThesisCodecStoresTheSvdOfConsecutiveViewsInTheThesisPacking) {
    // Our Gram fit in double against BDCSVD: singular vectors agree to ~1e-6 relative here
    // (distinct singular values of a 280 x 48 matrix); a value on a rounding boundary may take
    // the neighbouring code, so codes and digits agree within one and values within half a step
    // of the packing plus this.
    constexpr double kFitAgreement = 1e-4;
    const AnalyticBtf btf(small_btf());
    PcaRunOptions o = run_options("btf_pca_thesis_codec", 2, 3);
    o.codec = Codec::kThesis;
    o.fit_space = FitSpace::kSrgb;
    o.weights_format = WeightsFormat::kUint8;
    o.pca.grouping = ViewGrouping::kConsecutive;
    const nlohmann::json m = compress_to_folder(btf, o, 0);
    EXPECT_EQ(m["pca"]["codec"], "thesis");
    const auto dec = CompressedBtf::open(o.output);
    const nlohmann::json& man = dec->manifest();
    EXPECT_EQ(man["codec"], "thesis");
    EXPECT_EQ(man["view_grouping"], "consecutive");
    const std::vector<std::vector<int>> want_groups = {{0, 1}, {2, 3}, {4}};
    ASSERT_EQ(man["groups"].size(), want_groups.size());
    // The stream: component 0 of groups 0, 1, 2, then component 1 of each, ...
    for (size_t i = 0; i < man["stream"].size(); ++i) {
        EXPECT_EQ(man["stream"][i][0], int(i % 3)) << i;
        EXPECT_EQ(man["stream"][i][1], int(i / 3)) << i;
    }
    const double rmse = m["error"]["rmse_linear"];  // in sRGB-encoded units: compare encoded
    {
        double sse = 0;
        const BtfShape& sh = btf.shape();
        for (int v = 0; v < sh.n_views(); ++v)
            for (int l = 0; l < sh.n_lights(); ++l) {
                const image::Image x = dec->read_image(l, v), y = btf.read_image(l, v);
                for (size_t i = 0; i < x.pixels.size(); ++i)
                    sse += std::pow(double(image::srgb_encode(x.pixels[i])) - image::srgb_encode(y.pixels[i]), 2);
            }
        // The decoder clamps to [0, 1] before decoding, which can only lower the error.
        EXPECT_LE(std::sqrt(sse / sh.sample_count()), rmse * (1 + kRmseRelTol));
        EXPECT_GT(std::sqrt(sse / sh.sample_count()), 0.5 * rmse);
    }
    const std::string weights = fs::read_file(o.output + "/weights.bin");
    const int P = 20 * 14, n_lights = 8;
    for (size_t g = 0; g < want_groups.size(); ++g) {
        SCOPED_TRACE("group " + std::to_string(g));
        const nlohmann::json& gj = man["groups"][g];
        ASSERT_EQ(gj["views"].get<std::vector<int>>(), want_groups[g]);
        const int N = 3 * n_lights * int(want_groups[g].size());
        Eigen::MatrixXd a(P, N);
        for (size_t vi = 0; vi < want_groups[g].size(); ++vi)
            for (int l = 0; l < n_lights; ++l) {
                const image::Image img = btf.read_image(l, want_groups[g][vi]);
                for (int p = 0; p < P; ++p)
                    for (int ch = 0; ch < 3; ++ch)
                        a(p, (int(vi) * n_lights + l) * 3 + ch) = image::srgb_encode(img.pixels[size_t(p) * 3 + size_t(ch)]);
            }
        const Eigen::VectorXd mean = a.rowwise().mean();
        a.colwise() -= mean;
        const Eigen::BDCSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
        const int C = 3;
        const Eigen::MatrixXd u = svd.matrixU().leftCols(C), v = svd.matrixV().leftCols(C);
        auto power_of_ten = [](double max_abs) {  // the largest 10^n (n >= 0) with max_abs 10^n <= 1
            double f = 1;
            while (max_abs * f * 10 <= 1) f *= 10;
            return f;
        };
        const double fu = power_of_ten(u.cwiseAbs().maxCoeff()), fv = power_of_ten(v.cwiseAbs().maxCoeff());
        EXPECT_EQ(gj["thesis"]["factor_u"].get<double>(), fu);
        EXPECT_EQ(gj["thesis"]["factor_v"].get<double>(), fv);
        // The mean: an 8-bit image.
        for (int p = 0; p < P; ++p) ASSERT_NEAR(dec->group_mean(int(g))[p], mean[p], 0.5 / 255 + kFitAgreement) << p;
        const Eigen::MatrixXf& basis = dec->group_basis(int(g));
        const uint64_t w0 = gj["weights_offset_bytes"];
        for (int c = 0; c < C; ++c) {
            SCOPED_TRACE("component " + std::to_string(c));
            const double sigma = svd.singularValues()[c];
            const int64_t digits = gj["thesis"]["sigma_digits"][size_t(c)];
            EXPECT_NEAR(digits, 255 * sigma / (fu * fv), 0.5 + kFitAgreement * digits);
            // The sign of a singular pair is arbitrary: take the fit's.
            const double sign = basis.col(c).cast<double>().dot(u.col(c)) < 0 ? -1 : 1;
            // U Sigma as decoded = f^-1(code) (digits / 255) with f^-1(code) within half a code
            // step (1 / 255) of factor_u u: within (1 / 255) (digits / 255) + |factor_u u| (0.5 /
            // 255) of factor_u u sigma / (factor_u factor_v), plus the fits' disagreement.
            for (int p = 0; p < P; ++p) {
                const double want = sign * u(p, c) * sigma / fv;
                const double bound = (1.0 / 255) * (digits / 255.0) + std::abs(fu * u(p, c)) * (0.5 / 255) +
                                     kFitAgreement * std::abs(sigma / fv) / 255;
                ASSERT_NEAR(basis(p, c), want, bound) << p;
            }
            // V's codes: round(255 (factor_v v + 1) / 2), within one code.
            for (int j = 0; j < N; ++j) {
                const int code = uint8_t(weights[size_t(w0) + size_t(c) * size_t(N) + size_t(j)]);
                ASSERT_NEAR(code, 255 * (fv * sign * v(j, c) + 1) / 2, 0.5 + 255 * kFitAgreement) << j;
            }
            EXPECT_FLOAT_EQ(gj["components"][size_t(c)]["v_scale"].get<float>(), 2.0f / 255);
            EXPECT_FLOAT_EQ(gj["components"][size_t(c)]["v_offset"].get<float>(), -1.0f);
        }
    }
    // The thesis' own bytes: its mean and U files as written, V and Sigma beside them.
    uint64_t mean_files = 0, u_files = 0;
    for (const auto& gj : man["groups"]) {
        mean_files += stdfs::file_size(o.output + "/" + gj["mean"]["file"].get<std::string>());
        for (const auto& cj : gj["components"]) u_files += stdfs::file_size(o.output + "/" + cj["file"].get<std::string>());
    }
    const nlohmann::json& tp = m["thesis_packing"];
    EXPECT_EQ(tp["mean_png_bytes"].get<uint64_t>(), mean_files);
    EXPECT_EQ(tp["u_png_bytes"].get<uint64_t>(), u_files);
    EXPECT_EQ(tp["stored_bytes"].get<uint64_t>(), mean_files + u_files + tp["v_sigma_bytes"].get<uint64_t>());
    EXPECT_GE(tp["v_sigma_bytes"].get<uint64_t>(), 3 * 2 * 3u);  // at least Sigma's two channels per component
    // Its error is the thesis_packing figure of the same model.
    EXPECT_NEAR(m["error"]["mae_lab"].get<double>(), m["thesis_packing"]["mae_lab"].get<double>(),
                kRmseRelTol * m["error"]["mae_lab"].get<double>());
    // What differs from the method is named, not run.
    for (auto bad : std::vector<std::function<void(PcaRunOptions&)>>{
             [](PcaRunOptions& x) { x.fit_space = FitSpace::kLab; }, [](PcaRunOptions& x) { x.pca.l1_iterations = 4; },
             [](PcaRunOptions& x) { x.pca.grouping = ViewGrouping::kNeighbours; },
             [](PcaRunOptions& x) { x.weights_format = WeightsFormat::kFloat32; },
             [](PcaRunOptions& x) { x.encoding = ComponentEncoding::kExrHalf; },
             [](PcaRunOptions& x) { x.quant_noise = 0.1; }, [](PcaRunOptions& x) { x.pca.max_rmse = 0.01; }}) {
        PcaRunOptions x = o;
        x.output = testing::temp_dir("btf_pca_thesis_bad");
        bad(x);
        EXPECT_NE(testing::error_of([&] { compress_to_folder(btf, x, 0); }).find("--codec thesis: "), std::string::npos);
    }
    EXPECT_EQ(codec_from_string("thesis"), Codec::kThesis);
    EXPECT_NE(testing::error_of([] { codec_from_string("jpeg"); }).find("jpeg"), std::string::npos);
}

// table_equal_bytes: each row is the longest prefix of the stream within the fixed-C row's
// bytes; the decoder holding that prefix has exactly the row's error, and the next component
// of the stream would not have fit.
TEST(CompressToFolder, EqualBytesRowsAreStreamPrefixesWithinTheRowsBytes) {
    const AnalyticBtf btf(small_btf());
    PcaRunOptions o = run_options("btf_pca_equal_bytes", 2, 4);
    o.table_components = {1, 2, 4};
    const nlohmann::json m = compress_to_folder(btf, o, 0);
    const auto dec = CompressedBtf::open(o.output);
    const nlohmann::json& man = dec->manifest();
    ASSERT_EQ(m["table_equal_bytes"].size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        const auto& row = m["table_equal_bytes"][i];
        SCOPED_TRACE(i);
        EXPECT_EQ(row["byte_budget"], m["table"][i]["stored_bytes"].get<int64_t>() - m["table"][i]["manifest_bytes"].get<int64_t>());
        const int64_t budget = row["byte_budget"], n = row["components_total"];
        const int64_t bytes = row["stored_bytes"].get<int64_t>() - row["manifest_bytes"].get<int64_t>();
        EXPECT_LE(bytes, budget);
        int64_t per_group_sum = 0;
        for (const auto& c : row["components_per_group"]) per_group_sum += c.get<int64_t>();
        EXPECT_EQ(per_group_sum, n);
        if (n < dec->stream_length()) {
            const int g = man["stream"][size_t(n)][0], c = man["stream"][size_t(n)][1];
            const auto& gj = man["groups"][size_t(g)];
            EXPECT_GT(bytes + gj["components"][size_t(c)]["bytes"].get<int64_t>() + 4 * gj["columns"].get<int64_t>(), budget);
        }
        const double want = row["rmse_linear"];
        EXPECT_NEAR(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image_streamed(l, v, n); }), want,
                    kRmseRelTol * want);
    }
    // The whole model's bytes: the whole stream, the same figures as the row of all components.
    EXPECT_EQ(m["table_equal_bytes"][2]["components_total"].get<int64_t>(), dec->stream_length());
    EXPECT_EQ(m["table_equal_bytes"][2]["mae_lab"], m["table"][2]["mae_lab"]);
    EXPECT_EQ(m["table_equal_bytes"][2]["stored_bytes"], m["bytes"]["stored"]);
}

// --weights-format: V in float16 or uint8 decodes to the error the run reports (it measures the
// stored V); weights.bin holds N x C values of 4, 2 or 1 bytes; each stored value lies within
// half a step of the float32 V of the same (deterministic Gram) fit: half a uint8 step of its
// column, or float16's rounding (2^-11 relative, 2^-25 absolute below its normal range).
TEST(CompressToFolder, WeightsFormatsDecodeToTheReportedErrorWithinTheirStep) {
    const AnalyticBtf btf(small_btf());
    const int64_t values = (48 + 48 + 24) * 3;  // groups of 2, 2, 1 views x 8 lights x 3, C = 3
    std::vector<float> v32;
    for (WeightsFormat f : {WeightsFormat::kFloat32, WeightsFormat::kFloat16, WeightsFormat::kUint8}) {
        SCOPED_TRACE(to_string(f));
        PcaRunOptions o = run_options("btf_pca_weights_" + to_string(f), 2, 3);
        o.encoding = ComponentEncoding::kExrFloat;  // only V's storage differs between the runs
        o.weights_format = f;
        const nlohmann::json m = compress_to_folder(btf, o, 0);
        const std::string bin = fs::read_file(o.output + "/weights.bin");
        ASSERT_EQ(int64_t(bin.size()), values * bytes_per_weight(f));
        EXPECT_EQ(m["bytes"]["weights"], bin.size());
        const auto dec = CompressedBtf::open(o.output);
        EXPECT_EQ(dec->manifest()["weights"]["dtype"], weights_dtype(f));
        const double rmse = m["error"]["rmse_linear"];
        EXPECT_NEAR(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image(l, v); }), rmse, kRmseRelTol * rmse);
        if (f == WeightsFormat::kFloat32) {
            v32.resize(size_t(values));
            std::memcpy(v32.data(), bin.data(), bin.size());
            continue;
        }
        int64_t i = 0;
        for (const auto& g : dec->manifest()["groups"])
            for (const auto& c : g["components"])
                for (int64_t r = 0; r < g["columns"].get<int64_t>(); ++r, ++i) {
                    const float want = v32[size_t(i)];
                    if (f == WeightsFormat::kUint8) {
                        const float scale = c["v_scale"], value = c["v_offset"].get<float>() + scale * float(uint8_t(bin[size_t(i)]));
                        ASSERT_LE(std::abs(value - want), 0.5f * scale * (1 + 1e-5f)) << i;
                    } else {
                        const uint16_t bits = uint16_t(uint8_t(bin[size_t(2 * i)]) | (uint16_t(uint8_t(bin[size_t(2 * i + 1)])) << 8));
                        const Eigen::half h(Eigen::half_impl::raw_uint16_to_half(bits));
                        ASSERT_LE(std::abs(float(h) - want), std::ldexp(std::abs(want), -11) + std::ldexp(1.0f, -25)) << i;
                    }
                }
        EXPECT_EQ(i, values);
    }
    EXPECT_EQ(weights_format_from_string("uint8"), WeightsFormat::kUint8);
    EXPECT_NE(testing::error_of([] { weights_format_from_string("int4"); }).find("int4"), std::string::npos);
}

// uint8-deflate: weights.bin holds, per column, a zlib stream of exactly the uint8 format's codes
// (inflated here by zlib itself), so the model and its error are the uint8 run's. With
// --quant-noise F, V's columns are rounded on coarser steps: the components' images are
// orthogonal and orthogonal to the residual (the Gram PCA), so the error energy rises by exactly
// sum_c |b_c|^2 |dV_c|^2 <= sum_c |b_c|^2 N (v_scale_c / 2)^2, and the coarser codes deflate to
// fewer bytes.
TEST(CompressToFolder, Uint8DeflateStoresTheUint8CodesAndQuantNoiseCoarsensV) {
    // Energies are sums over 20 x 14 x 8 x 5 x 3 values <= 1 in double of float32 residuals:
    // relative 1e-5 covers their rounding (the bound itself is exact).
    constexpr double kEnergyRelTol = 1e-5;
    const AnalyticBtf btf(small_btf());
    auto run = [&](const std::string& name, WeightsFormat f, double quant_noise) {
        PcaRunOptions o = run_options(name, 2, 3);
        o.encoding = ComponentEncoding::kExrFloat;  // only V's storage differs
        o.weights_format = f;
        o.quant_noise = quant_noise;
        return std::make_pair(o.output, compress_to_folder(btf, o, 0));
    };
    // Every column of a uint8_deflate folder, inflated by zlib: codes in file order.
    auto inflate_all = [](const std::string& dir) {
        const auto d = CompressedBtf::open(dir);
        const std::string bin = fs::read_file(dir + "/weights.bin");
        std::vector<std::string> cols;
        size_t at = 0;
        for (const auto& g : d->manifest()["groups"]) {
            EXPECT_EQ(g["weights_offset_bytes"].get<size_t>(), at);
            for (const auto& c : g["components"]) {
                const size_t n = g["columns"], zb = c["v_bytes"];
                std::string col(n, '\0');
                uLongf got = uLongf(n);
                EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(col.data()), &got, reinterpret_cast<const Bytef*>(bin.data() + at), uLong(zb)), Z_OK);
                EXPECT_EQ(got, uLongf(n));
                cols.push_back(col);
                at += zb;
            }
        }
        EXPECT_EQ(at, bin.size());
        return cols;
    };
    const auto [raw_dir, raw] = run("btf_pca_v_uint8", WeightsFormat::kUint8, 0);
    const auto [z_dir, z] = run("btf_pca_v_deflate", WeightsFormat::kUint8Deflate, 0);
    const auto dec = CompressedBtf::open(z_dir);
    EXPECT_EQ(dec->manifest()["weights"]["dtype"], "uint8_deflate");
    std::string codes;
    for (const auto& col : inflate_all(z_dir)) codes += col;
    EXPECT_EQ(codes, fs::read_file(raw_dir + "/weights.bin"));
    EXPECT_EQ(z["error"]["rmse_linear"].get<double>(), raw["error"]["rmse_linear"].get<double>());
    const double rmse = z["error"]["rmse_linear"];
    EXPECT_NEAR(rmse_between(*dec, btf, [&](int l, int v) { return dec->read_image(l, v); }), rmse, kRmseRelTol * rmse);

    const double F = 0.5;
    const auto [q_dir, q] = run("btf_pca_v_deflate_noise", WeightsFormat::kUint8Deflate, F);
    const auto qdec = CompressedBtf::open(q_dir);
    const double samples = btf.shape().sample_count();
    const double unquantised = std::pow(q["error"]["rmse_linear_unquantised"].get<double>(), 2) * samples;
    const double added = std::pow(q["error"]["rmse_linear"].get<double>(), 2) * samples - unquantised;
    double bound = 0;
    for (const auto& g : qdec->manifest()["groups"])
        for (const auto& c : g["components"]) {
            const double step = c["v_scale"];
            bound += c["energy"].get<double>() * g["columns"].get<double>() * step * step / 4;
        }
    EXPECT_GT(added, 0.0);
    EXPECT_LE(added, bound * (1 + kEnergyRelTol) + kEnergyRelTol * unquantised);
    // Some column's step exceeds its range / 255: its codes stop short of 255.
    int coarse = 0;
    for (const auto& col : inflate_all(q_dir)) coarse += *std::max_element(col.begin(), col.end(), [](char a, char b) { return uint8_t(a) < uint8_t(b); }) != char(255);
    EXPECT_GT(coarse, 0);
    EXPECT_LT(q["bytes"]["weights"].get<uint64_t>(), z["bytes"]["weights"].get<uint64_t>());
    // The step: with one group (k = 5) E is the run's unquantised residual energy, and each
    // column's step is max(its range / 255, sqrt(12 F E / (C N |b_c|^2))).
    PcaRunOptions one = run_options("btf_pca_v_deflate_one_group", 5, 3);
    one.encoding = ComponentEncoding::kExrFloat;
    one.weights_format = WeightsFormat::kUint8Deflate;
    one.quant_noise = F;
    const nlohmann::json m1 = compress_to_folder(btf, one, 0);
    const double e1 = std::pow(m1["error"]["rmse_linear_unquantised"].get<double>(), 2) * samples;
    const nlohmann::json g1 = CompressedBtf::open(one.output)->manifest()["groups"][0];
    const auto cols1 = inflate_all(one.output);
    for (size_t c = 0; c < 3; ++c) {
        const double n = g1["columns"], b2 = g1["components"][c]["energy"], step = g1["components"][c]["v_scale"];
        const double want = std::sqrt(12 * F * e1 / (3 * n * b2));
        const bool short_of_255 = *std::max_element(cols1[c].begin(), cols1[c].end(), [](char a, char b) { return uint8_t(a) < uint8_t(b); }) != char(255);
        // float32 step against the double formula (E and |b|^2 from float sums): 1e-4 relative
        EXPECT_GE(step, want * (1 - 1e-4)) << c;
        if (short_of_255) {
            EXPECT_NEAR(step, want, 1e-4 * want) << c;
        }
    }
    EXPECT_EQ(weights_format_from_string("uint8-deflate"), WeightsFormat::kUint8Deflate);
}

// A uint8_deflate column that is not a zlib stream of its codes is an Error naming weights.bin.
TEST(CompressedBtf, Uint8DeflateColumnsAreChecked) {
    const AnalyticBtf btf(small_btf());
    PcaRunOptions o = run_options("btf_pca_v_deflate_bad", 2, 2);
    o.weights_format = WeightsFormat::kUint8Deflate;
    compress_to_folder(btf, o, 0);
    std::string bin = fs::read_file(o.output + "/weights.bin");
    bin[bin.size() / 2] = char(bin[bin.size() / 2] ^ 0x5a);
    fs::write_text_atomic(o.output + "/weights.bin", bin);
    EXPECT_NE(testing::error_of([&] { CompressedBtf::open(o.output); }).find("weights.bin: group "), std::string::npos);
    fs::write_text_atomic(o.output + "/weights.bin", bin.substr(0, 10));
    EXPECT_NE(testing::error_of([&] { CompressedBtf::open(o.output); }).find("v_bytes"), std::string::npos);
}

TEST(Quantize8, MinStepLeavesSmallColumnsOnFewerCodes) {
    const float v[] = {0.0f, 0.1f, 0.25f, 0.3f};
    const Quantized8 q = quantize8(v, 4, 0.1f);
    EXPECT_FLOAT_EQ(q.scale, 0.1f);  // range / 255 = 0.0012 < 0.1
    EXPECT_EQ(q.codes.back(), 3);
    for (int i = 0; i < 4; ++i) EXPECT_LE(std::abs(q.value(i) - v[i]), 0.5f * q.scale * (1 + 1e-5f));
    EXPECT_FLOAT_EQ(quantize8(v, 4, 1e-6f).scale, 0.3f / 255);  // the range's step when larger
}

// --quant-noise F: one step per group, step^2 = 12 F E / (C P). The residual is orthogonal to
// the span of V and to 1 (V's columns are), so the stored model's squared error is exactly
// E + sum_c ||e_c||^2 + N ||d||^2 (e_c the rounding of component c, d the mean's), checked
// against the unquantised components of the same Gram fit (float EXR); each value lies within
// half its column's step, and sum_c ||e_c||^2 is near its design value F E.
TEST(CompressToFolder, QuantNoiseRoundsComponentsWithOneStepPerGroup) {
    constexpr double kF = 0.1;
    const AnalyticBtf btf(small_btf());
    const int P = 20 * 14, N = 3 * 8 * 5, C = 3;
    PcaRunOptions o = run_options("btf_pca_quant_exact", 5, C);  // one group
    o.encoding = ComponentEncoding::kExrFloat;
    const nlohmann::json exact = compress_to_folder(btf, o, 0);
    const std::string exact_dir = o.output;
    o.output = testing::temp_dir("btf_pca_quant_noise");
    o.encoding = ComponentEncoding::kPng8;
    o.quant_noise = kF;
    const nlohmann::json m = compress_to_folder(btf, o, 0);
    const double samples = double(P) * N;
    const double E = std::pow(exact["error"]["rmse_linear_unquantised"].get<double>(), 2) * samples;
    const double step = std::sqrt(12 * kF * E / (C * P));
    const nlohmann::json man = nlohmann::json::parse(fs::read_file(o.output + "/btf-pca.json"));
    auto column = [](const std::string& path, float scale, float offset) {
        const image::Image img = image::read_image(path, {false});
        std::vector<double> out;
        for (float x : img.pixels) out.push_back(offset + double(scale) * x);
        return out;
    };
    double rounding = 0, comp_rounding = 0;
    for (int c = -1; c < C; ++c) {
        const auto& meta = c < 0 ? man["groups"][0]["mean"] : man["groups"][0]["components"][size_t(c)];
        const std::string name = meta["file"];
        const std::vector<double> want = column(exact_dir + "/" + name.substr(0, name.size() - 3) + "exr", 1, 0);
        const std::vector<double> got = column(o.output + "/" + name, meta["scale"], meta["offset"]);
        const auto [lo, hi] = std::minmax_element(want.begin(), want.end());
        const double col_step = meta["scale"].get<double>() / 255;
        // float32 offset + scale * code: relative 1e-5 of the step covers its rounding
        EXPECT_NEAR(col_step, c < 0 ? (*hi - *lo) / 255 : std::max((*hi - *lo) / 255, step), 1e-5 * col_step) << c;
        double e2 = 0;
        for (size_t i = 0; i < want.size(); ++i) {
            ASSERT_LE(std::abs(got[i] - want[i]), 0.5 * col_step * (1 + 1e-4)) << c << " " << i;
            e2 += std::pow(got[i] - want[i], 2);
        }
        rounding += c < 0 ? N * e2 : e2;  // the mean enters every column, component c through a unit-norm V column
        if (c >= 0) comp_rounding += e2;
        if (c == C - 1) {
            EXPECT_GT(col_step, 1.5 * (*hi - *lo) / 255) << "the smallest component is not on fewer codes";
        }
    }
    const double sse = std::pow(m["error"]["rmse_linear"].get<double>(), 2) * samples;
    EXPECT_NEAR(sse, E + rounding, kRmseRelTol * sse);
    // Design value F E: uniform rounding over P C = 840 values has a relative spread of
    // 0.894 / sqrt(840) = 3%, and columns of range / 255 above the step round finer (less), so
    // 0.3x-1.3x of F E.
    EXPECT_GT(comp_rounding, 0.3 * kF * E);
    EXPECT_LT(comp_rounding, 1.3 * kF * E);
    EXPECT_EQ(m["pca"]["quant_noise"], kF);
}

TEST(CompressedBtf, BadFolderNamesTheFile) {
    const std::string dir = testing::temp_dir("btf_pca_bad");
    EXPECT_NE(testing::error_of([&] { CompressedBtf::open(dir); }).find("btf-pca.json"), std::string::npos);
    const AnalyticBtf btf(small_btf());
    PcaRunOptions o;
    o.output = dir;
    o.pca.components = 2;
    compress_to_folder(btf, o, 0);
    std::filesystem::remove(dir + "/g001-c01.png");
    EXPECT_NE(testing::error_of([&] { CompressedBtf::open(dir); }).find("g001-c01.png"), std::string::npos);
}

// Seen by reading CompressedBtf::open for fuzz/btfpca_fuzz.cpp: numbers in the manifest are
// checked as integers in range before they size or index anything (get<int>() of 1e300 is
// undefined behaviour; a weights offset near 2^64 wrapped the size check and memcpy read past
// weights.bin; a 65536 x 65536 claim allocated 16 GiB before the mean image was read).
TEST(CompressedBtf, ManifestNumbersAreCheckedBeforeUse) {
    const std::string dir = testing::temp_dir("btf_pca_numbers");
    PcaRunOptions o;
    o.output = dir;
    o.pca.components = 2;
    compress_to_folder(AnalyticBtf(small_btf()), o, 0);
    const nlohmann::json good = nlohmann::json::parse(fs::read_file(dir + "/btf-pca.json"));
    const uint64_t weights_bytes = fs::read_file(dir + "/weights.bin").size();
    const struct {
        std::function<void(nlohmann::json&)> edit;
        std::string message;
    } cases[] = {
        {[](nlohmann::json& m) { m["width"] = 1e300; }, "width must be an integer in [1, 65536]"},
        {[](nlohmann::json& m) { m["height"] = 65537; }, "height must be an integer in [1, 65536]"},
        {[](nlohmann::json& m) { m["width"] = m["width"].get<int>() * 2; }, "g000-mean.png: expected a"},
        {[](nlohmann::json& m) { m["groups"][0]["weights_offset_bytes"] = UINT64_MAX - 3; },
         "weights_offset_bytes must be an integer"},
        {[&](nlohmann::json& m) { m["groups"][0]["weights_offset_bytes"] = weights_bytes - 4; },
         "weights.bin: "},
        {[](nlohmann::json& m) { m["groups"][0]["views"][0] = -1; }, "group 0: a view must be an integer"},
        {[](nlohmann::json& m) { m["groups"][0]["views"][0] = 2.5; }, "group 0: a view must be an integer"},
        {[](nlohmann::json& m) { m["stream"][0][1] = 1e300; }, "a stream entry's component must be"},
        {[](nlohmann::json& m) { m["stream"][0][0] = 99; }, "a stream entry's group must be"},
    };
    for (const auto& c : cases) {
        nlohmann::json m = good;
        c.edit(m);
        fs::write_text_atomic(dir + "/btf-pca.json", m.dump());
        const std::string e = testing::error_of([&] { CompressedBtf::open(dir); });
        EXPECT_NE(e.find(c.message), std::string::npos) << e;
    }
    fs::write_text_atomic(dir + "/btf-pca.json", good.dump());
    EXPECT_EQ(CompressedBtf::open(dir)->shape().width, small_btf().width);
}

}  // namespace
}  // namespace inlight::btf
