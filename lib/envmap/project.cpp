#include "envmap/project.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/check.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/log.h"
#include "core/parallel.h"
#include "envmap/validate.h"
#include "sh/quadrature.h"
#include "sh/rotation.h"

namespace inlight::envmap {

constexpr EnumName<PartialMethod> kPartialMethodNames[] = {{PartialMethod::kFit, "fit"},
                                                           {PartialMethod::kZeroFill, "zero-fill"}};
constexpr EnumName<LatlongPrecision> kLatlongPrecisionNames[] = {
    {LatlongPrecision::kFloatRowSums, "float"}, {LatlongPrecision::kDouble, "double"}};

PartialMethod partial_method_from_string(const std::string& name) {
    return enum_from_string(kPartialMethodNames, name, "partial method");
}

LatlongPrecision latlong_precision_from_string(const std::string& name) {
    return enum_from_string(kLatlongPrecisionNames, name, "lat-long precision");
}

namespace {

/// Column sums of one row in float: out(ch, k) = sum_c px(c, ch) trig(c, k) for k < K, trig
/// stored row-major with stride K (zero-padded). Each block of kFloatBlock columns is summed in
/// float, vectorised over k (3 independent chains of K lanes), and the block sums are added in
/// double. Error (Higham 2002, eq. 3.5, an inner product of length B plus trig's own rounding):
/// |out - exact| <= kFloatRowSumBound * sum_c |px(c, ch)| |trig_exact(c, k)|.
// GCC/Clang vector extensions: 8 float lanes (one AVX register, or two SSE ones), written out
// because auto-vectorisation of the scalar loop transposes across columns instead.
typedef float Float8 __attribute__((vector_size(32)));
typedef float Float4 __attribute__((vector_size(16)));
typedef double Double4 __attribute__((vector_size(32)));
template <int K>
inline __attribute__((always_inline)) void row_sums_float_body(const float* px, const float* trig,
                                                               int w, double* out /* 3 x K */) {
    static_assert(K % 8 == 0, "K is padded to whole vectors");
    static_assert(kFloatBlock % 2 == 0, "columns go in pairs");
    constexpr int V = K / 8;
    Double4 acc[3][2 * V] = {};
    const auto add = [&](int c, Float8 (&sum)[3][V]) {
        const float* t = trig + static_cast<size_t>(c) * K;
        for (int v = 0; v < V; ++v) {
            Float8 tv;
            std::memcpy(&tv, t + 8 * v, sizeof tv);
            for (int ch = 0; ch < 3; ++ch) sum[ch][v] += px[3 * c + ch] * tv;
        }
    };
    for (int c0 = 0; c0 < w; c0 += kFloatBlock) {
        const int c1 = std::min(w, c0 + kFloatBlock);
        // Even and odd columns in separate sums: six independent chains hide the FMA latency.
        Float8 even[3][V] = {}, odd[3][V] = {};
        int c = c0;
        for (; c + 1 < c1; c += 2) {
            add(c, even);
            add(c + 1, odd);
        }
        if (c < c1) add(c, even);
        for (int ch = 0; ch < 3; ++ch) {
            for (int v = 0; v < V; ++v) {
                const Float8 sum = even[ch][v] + odd[ch][v];
                Float4 lo, hi;
                std::memcpy(&lo, &sum, sizeof lo);
                std::memcpy(&hi, reinterpret_cast<const char*>(&sum) + sizeof lo, sizeof hi);
                acc[ch][2 * v] += __builtin_convertvector(lo, Double4);
                acc[ch][2 * v + 1] += __builtin_convertvector(hi, Double4);
            }
        }
    }
    for (int ch = 0; ch < 3; ++ch)
        for (int v = 0; v < 2 * V; ++v)
            std::memcpy(out + ch * K + 4 * v, &acc[ch][v], sizeof acc[ch][v]);
}

// The same code compiled twice: for AVX2 + FMA (8 float lanes, one fused rounding per term, so
// within the same bound) where the CPU has them, and for the baseline x86-64 (SSE2) otherwise.
#if defined(__x86_64__) && defined(__GNUC__)
#define INLIGHT_ENVMAP_AVX2 1
template <int K>
__attribute__((target("avx2,fma"))) void row_sums_float_avx2(const float* px, const float* trig,
                                                              int w, double* out) {
    row_sums_float_body<K>(px, trig, w, out);
}
bool cpu_has_avx2_fma() {
    static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return has;
}
#endif
// The baseline instantiation is kept out of line so that it stays a separate function compiled
// for the baseline target (it is what CPUs without AVX2 run, and what kBaseline selects).
template <int K>
__attribute__((noinline)) void row_sums_float_baseline(const float* px, const float* trig, int w,
                                                       double* out) {
    row_sums_float_body<K>(px, trig, w, out);
}
template <int K>
void row_sums_float(const float* px, const float* trig, int w, double* out, bool avx2) {
#ifdef INLIGHT_ENVMAP_AVX2
    if (avx2) return row_sums_float_avx2<K>(px, trig, w, out);
#endif
    row_sums_float_baseline<K>(px, trig, w, out);
}

}  // namespace

bool float_row_sums_use_avx2() {
#ifdef INLIGHT_ENVMAP_AVX2
    return cpu_has_avx2_fma();
#else
    return false;
#endif
}

Eigen::MatrixXd project_latlong(const image::Image& img, int sh_bands, LatlongPrecision precision,
                                FloatRowSumIsa isa) {
    INLIGHT_CHECK_EQ(img.channels, 3);
    INLIGHT_CHECK_EQ(img.width, 2 * img.height);
    const int w = img.width, h = img.height, n = sh::count(sh_bands);
    const double dphi = 2.0 * kPi / w;
    // Azimuth: cos(m phi_c), sin(m phi_c) per column, phi_c = pi (1 - 2 (c + 0.5) / W) (Cycles),
    // and the exact integral over the pixel's phi range: dphi * sinc(m dphi / 2) * cos(m phi_c).
    // trig(c, m) = cos(m phi_c) and trig(c, sh_bands + m) = sin(m phi_c), times the exact
    // azimuthal integral factor; one row's sums are then a (3 x W) x (W x 2 sh_bands) product.
    Eigen::MatrixXd trig(w, 2 * sh_bands);
    for (int c = 0; c < w; ++c) {
        const double phi = kPi * (1.0 - 2.0 * (c + 0.5) / w);
        for (int m = 0; m < sh_bands; ++m) {
            const double x = 0.5 * m * dphi;
            const double a = m == 0 ? dphi : dphi * std::sin(x) / x;
            trig(c, m) = a * std::cos(m * phi);
            trig(c, sh_bands + m) = a * std::sin(m * phi);
        }
    }
    // Float row sums for up to kMaxFloatBands bands (2 sh_bands <= 16 terms, padded to 8 or 16).
    const bool use_float = precision == LatlongPrecision::kFloatRowSums &&
                           sh_bands <= kMaxFloatBands;
    const int k_pad = 2 * sh_bands <= 8 ? 8 : 16;
    const bool avx2 = isa == FloatRowSumIsa::kBest && float_row_sums_use_avx2();
    // The float weights are trig / dphi (dphi is applied to the sums in double): the m = 0
    // weight is then exactly 1, so the m = 0 sums round only in the additions.
    std::vector<float> trig_f;
    if (use_float) {
        trig_f.assign(static_cast<size_t>(w) * k_pad, 0.0f);
        for (int c = 0; c < w; ++c)
            for (int k = 0; k < 2 * sh_bands; ++k)
                trig_f[static_cast<size_t>(c) * k_pad + k] = static_cast<float>(trig(c, k) / dphi);
    }
    // Polar: the row integral of Y_lm(theta, 0) sin(theta) dtheta. For even m the factor is a
    // polynomial of degree <= sh_bands - 1 in z = cos(theta): Gauss-Legendre in z is exact. For
    // odd m it carries sin(theta) = sqrt(1 - z^2), singular in z at the poles but analytic in
    // theta: Gauss-Legendre in theta converges geometrically.
    std::vector<double> gz_x, gz_w, gt_x, gt_w;
    sh::gauss_legendre(sh_bands / 2 + 2, gz_x, gz_w);
    sh::gauss_legendre(sh_bands + 6, gt_x, gt_w);

    using Acc = Eigen::MatrixXd;
    const int64_t rows_per_chunk = 4;  // fixed: sums do not depend on the thread count
    return parallel::reduce(
        h, rows_per_chunk, Acc(Acc::Zero(n, 3)),
        [&](int64_t begin, int64_t end) {
            Acc acc = Acc::Zero(n, 3);
            std::vector<double> y(static_cast<size_t>(n)), row(static_cast<size_t>(n)),
                row_odd(static_cast<size_t>(n));
            Eigen::Matrix<double, 3, Eigen::Dynamic> rgb(3, w);
            Eigen::Matrix<double, 3, Eigen::Dynamic> sums(3, 2 * sh_bands);
            std::vector<double> fsums(static_cast<size_t>(3 * k_pad));
            for (int64_t ri = begin; ri < end; ++ri) {
                const int r = static_cast<int>(ri);
                // Row factors: sqrt2 N_lm(z) sin^m(theta) (m > 0) or N_l0(z) (m = 0), integrated
                // over the row; `row` keeps the even-m entries, `row_odd` the odd-m ones.
                const double t0 = kPi * r / h, t1 = kPi * (r + 1) / h;
                const double z0 = std::cos(t0), z1 = std::cos(t1);
                std::fill(row.begin(), row.end(), 0.0);
                std::fill(row_odd.begin(), row_odd.end(), 0.0);
                for (size_t k = 0; k < gz_x.size(); ++k) {
                    const double z = 0.5 * (z0 + z1) + 0.5 * (z0 - z1) * gz_x[k];
                    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
                    sh::eval(sh_bands, Eigen::Vector3d(s, 0.0, z), y.data());
                    const double wk = 0.5 * (z0 - z1) * gz_w[k];
                    for (int i = 0; i < n; ++i) row[static_cast<size_t>(i)] += wk * y[static_cast<size_t>(i)];
                }
                if (sh_bands > 1) {
                    for (size_t k = 0; k < gt_x.size(); ++k) {
                        const double t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * gt_x[k];
                        sh::eval(sh_bands, Eigen::Vector3d(std::sin(t), 0.0, std::cos(t)), y.data());
                        const double wk = 0.5 * (t1 - t0) * gt_w[k] * std::sin(t);
                        for (int i = 0; i < n; ++i)
                            row_odd[static_cast<size_t>(i)] += wk * y[static_cast<size_t>(i)];
                    }
                }
                const float* px = img.pixels.data() + static_cast<size_t>(r) * w * 3;
                if (use_float) {
                    if (k_pad == 8) {
                        row_sums_float<8>(px, trig_f.data(), w, fsums.data(), avx2);
                    } else {
                        row_sums_float<16>(px, trig_f.data(), w, fsums.data(), avx2);
                    }
                    for (int ch = 0; ch < 3; ++ch)
                        for (int k = 0; k < 2 * sh_bands; ++k)
                            sums(ch, k) = dphi * fsums[static_cast<size_t>(ch * k_pad + k)];
                } else {
                    rgb = Eigen::Map<const Eigen::Matrix<float, 3, Eigen::Dynamic>>(px, 3, w)
                              .cast<double>();
                    sums.noalias() = rgb * trig;  // 3 x 2 sh_bands: cosine sums, then sine sums
                }
                for (int l = 0; l < sh_bands; ++l) {
                    for (int m = 0; m <= l; ++m) {
                        const double f = (m % 2 == 0 ? row : row_odd)[static_cast<size_t>(sh::index(l, m))];
                        for (int ch = 0; ch < 3; ++ch) {
                            acc(sh::index(l, m), ch) += f * sums(ch, m);
                            if (m > 0) acc(sh::index(l, -m), ch) += f * sums(ch, sh_bands + m);
                        }
                    }
                }
            }
            return acc;
        },
        [](Acc a, const Acc& b) { return Acc(a + b); });
}

namespace {

// min over t in [-1, 1] of sum_{l < bands} A_l (2l+1)/(4 pi) P_l(t): the band-limited clamped
// cosine's most negative value (0.25 for 1 band, -0.0396 for 3 bands), on a fine grid.
double kernel_min(int bands) {
    double lowest = INFINITY;
    for (int i = 0; i <= 4000; ++i) {
        const double t = -1.0 + 2.0 * i / 4000;
        double p0 = 1, p1 = t, k = 0;
        for (int l = 0; l < bands; ++l) {
            double pl = l == 0 ? 1.0 : t;
            if (l >= 2) {
                pl = ((2.0 * l - 1) * t * p1 - (l - 1.0) * p0) / l;
                p0 = p1;
                p1 = pl;
            }
            k += sh::cosine_zonal(l) * (2 * l + 1) / (4 * kPi) * pl;
        }
        lowest = std::min(lowest, k);
    }
    return lowest;
}

}  // namespace

bool irradiance_is_plausible(const Eigen::MatrixXd& coeffs, int sh_bands) {
    static const std::vector<Eigen::Vector3d> normals = validation_normals(1000);
    const double kmin = kernel_min(sh_bands);
    const Eigen::MatrixXd e = sh_irradiance(coeffs, sh_bands, normals);
    for (int c = 0; c < coeffs.cols(); ++c) {
        const double flux = 2.0 * std::sqrt(kPi) * coeffs(0, c);
        if (!(flux > 0)) return false;
        // 1e-9 of the flux absorbs rounding for lighting that sits exactly on the bound.
        if (e.col(c).minCoeff() < (kmin - 1e-9) * flux) return false;
    }
    return true;
}

ProjectResult project(const Environment& env, const ProjectOptions& options) {
    if (options.sh_bands < 1 || options.sh_bands > sh::kMaxBands)
        throw UsageError(str("sh_bands must be in [1, ", sh::kMaxBands, "], got ", options.sh_bands));
    ProjectResult result;
    const bool identity = env.world_from_input.isIdentity(0.0);
    if (env.layout == Layout::kLatLong) {
        result.coeffs = project_latlong(env.radiance, options.sh_bands, options.latlong_precision);
        if (!identity) result.coeffs = sh::rotation_matrix(options.sh_bands, env.world_from_input) *
                                       result.coeffs;
        result.method = "latlong-separable";
        result.covered_solid_angle_sr = 4 * kPi;
    } else {
        const auto samples = make_sample_set(env);
        if (env.full_sphere() || options.partial == PartialMethod::kZeroFill) {
            result.coeffs = sh::project(options.sh_bands, *samples);
            result.method = env.full_sphere() ? "quadrature" : "zero-fill";
            // The covered solid angle comes from the same weights the quadrature used.
            struct Ones : sh::SampleSet {
                const sh::SampleSet& s;
                explicit Ones(const sh::SampleSet& base) : s(base) {}
                int64_t size() const override { return s.size(); }
                int channels() const override { return 1; }
                bool sample(int64_t i, Eigen::Vector3d& d, double& w, double* v) const override {
                    double tmp[3];
                    if (!s.sample(i, d, w, tmp)) return false;
                    v[0] = 1.0;
                    return true;
                }
            } ones(*samples);
            result.covered_solid_angle_sr = sh::project(1, ones)(0, 0) * 2.0 * std::sqrt(kPi);
        } else {
            std::vector<double> ladder = {options.fit_lambda};
            if (options.fit_lambda < 0) {
                ladder = {0.0};
                for (double decade = 1e-6; decade < 20; decade *= 10)
                    for (double f : {1.0, 2.0, 5.0}) ladder.push_back(f * decade);
            }
            const auto path = sh::fit_least_squares_path(options.sh_bands, *samples, ladder);
            const sh::FitResult* chosen = nullptr;
            for (const auto& r : path) {
                if (r.coeffs.size() == 0) continue;
                chosen = &r;
                if (irradiance_is_plausible(r.coeffs, options.sh_bands)) break;
            }
            if (!chosen)
                throw Error(str(env.source, ": the observed directions do not determine ",
                                sh::count(options.sh_bands), " SH coefficients; use fewer bands"));
            result.fit = *chosen;
            result.fit_lambda_auto = options.fit_lambda < 0;
            result.fit_plausible = irradiance_is_plausible(chosen->coeffs, options.sh_bands);
            if (!result.fit_plausible)
                log::warn(str(env.source, ": the SH fit (lambda ", chosen->lambda,
                              ") has irradiance no non-negative lighting can produce"));
            result.coeffs = result.fit.coeffs;
            result.fitted = true;
            result.method = "least-squares";
            result.covered_solid_angle_sr = result.fit.observed_solid_angle_sr;
        }
    }
    result.coeffs_unwindowed = result.coeffs;
    sh::apply_window(options.window, options.sh_bands, result.coeffs);
    return result;
}

}  // namespace inlight::envmap
