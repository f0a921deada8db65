// Tests of SH rotation and coefficient files.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "sh/rotation.h"
#include "sh/sh.h"
#include "sh/sh_io.h"
#include "testing/testing.h"

namespace inlight::sh {
namespace {

// rotation_matrix is an exact quadrature over N = (bands + 1) (2 bands + 2) nodes, so each entry's
// error is rounding only: at most N u sum_nodes w |Y_k Y_k'| <= N u (Cauchy-Schwarz with the
// orthonormality the rule reproduces), u = 2^-53. Blocks are (2l + 1) wide, so a product of two
// such matrices, or of one with a vector, gathers at most 2 (2 lmax + 1) of these errors.
double rotation_entry_tol(int bands) { return (bands + 1.0) * (2 * bands + 2) * 0x1p-53; }

TEST(ShRotation, RotatedCoefficientsEvaluateRotatedFunction) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g;
    const int bands = 8, n = count(bands);
    Eigen::VectorXd c(n);
    for (int k = 0; k < n; ++k) c(k) = g(rng);
    const Eigen::Matrix3d r = parse_rotation("z=37,x=-71,y=12");
    const Eigen::VectorXd cr = rotation_matrix(bands, r) * c;
    for (int i = 0; i < 50; ++i) {
        const Eigen::Vector3d w = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
        const auto yw = eval(bands, w);
        const auto yi = eval(bands, (r.transpose() * w).normalized());
        double fw = 0, fi = 0;
        for (int k = 0; k < n; ++k) {
            fw += cr(k) * yw[static_cast<size_t>(k)];  // g(w)
            fi += c(k) * yi[static_cast<size_t>(k)];   // f(R^-1 w)
        }
        // |(D c - exact) . Y(w)| <= (2 lmax + 1) eps_D |c| |Y(w)|, |Y(w)|^2 = n / (4 pi) (addition
        // theorem); Y's own evaluation at two points adds the same order again: factor 2.
        const double tol = 2 * (2 * bands - 1) * rotation_entry_tol(bands) * c.norm() *
                           std::sqrt(n / (4 * kPi));
        EXPECT_NEAR(fw, fi, tol);
    }
}

TEST(ShRotation, InverseRoundTripAndOrthogonality) {
    const int bands = 16;
    const Eigen::Matrix3d r = parse_rotation("y-up");
    const Eigen::MatrixXd d = rotation_matrix(bands, r);
    const Eigen::MatrixXd di = rotation_matrix(bands, r.transpose());
    const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(count(bands), count(bands));
    const double tol = 2 * (2 * bands - 1) * rotation_entry_tol(bands);
    EXPECT_LT((di * d - id).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT((d.transpose() * d - id).cwiseAbs().maxCoeff(), tol);
    std::printf("rotation, %d bands: |D^-1 D - I| %.1e, |D^T D - I| %.1e, bound %.1e\n", bands,
                (di * d - id).cwiseAbs().maxCoeff(), (d.transpose() * d - id).cwiseAbs().maxCoeff(),
                tol);
}

TEST(ShIo, JsonAndBinaryRoundTrip) {
    CoefficientSet set;
    set.sh_bands = 3;
    set.coeffs = Eigen::MatrixXd::Random(9, 3);
    const std::string dir = inlight::testing::temp_dir("shio");
    write_binary(dir + "/a.bin", set);
    const CoefficientSet b = read_binary(dir + "/a.bin");
    EXPECT_EQ(b.sh_bands, 3);
    // float32 storage: relative rounding 2^-24 of values in [-1, 1].
    EXPECT_LT((b.coeffs - set.coeffs).cwiseAbs().maxCoeff(), 1.0 / (1 << 24));
    const nlohmann::json doc = to_json(set);
    EXPECT_TRUE(doc.contains("irradiance_matrices"));
    const CoefficientSet j = from_json(nlohmann::json::parse(doc.dump()), "mem");
    EXPECT_EQ((j.coeffs - set.coeffs).cwiseAbs().maxCoeff(), 0.0);  // JSON doubles round-trip
    fs::write_text_atomic(dir + "/bad.bin", "INLSHxxx");
    try {
        read_binary(dir + "/bad.bin");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.bin"), std::string::npos);
    }
}

}  // namespace
}  // namespace inlight::sh
