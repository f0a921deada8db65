#include "envmap/validate.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/Geometry>

#include "core/conventions.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "sh/sh.h"

namespace inlight::envmap {

std::vector<Eigen::Vector3d> validation_normals(int count, double max_angle_from_z) {
    std::vector<Eigen::Vector3d> all = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                        {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / count;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        all.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    if (max_angle_from_z >= kPi) return all;
    std::vector<Eigen::Vector3d> kept;
    const double cos_max = std::cos(max_angle_from_z);
    for (const auto& n : all) {
        if (n.z() >= cos_max) kept.push_back(n);
    }
    return kept;
}

std::vector<Eigen::Vector3d> holdout_normals(int count, double max_angle_from_z) {
    // A rotation other than fit_normals' (0.3 rad about (1, 2, 3)): any that moves the lattice
    // off the other two sets will do.
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(1.1, Eigen::Vector3d(-2, 1, 4).normalized()).toRotationMatrix();
    std::vector<Eigen::Vector3d> out;
    const std::vector<Eigen::Vector3d> lattice = validation_normals(count);
    const double cos_max = std::cos(max_angle_from_z);
    for (size_t i = 6; i < lattice.size(); ++i) {
        const Eigen::Vector3d n = turn * lattice[i];
        if (max_angle_from_z >= kPi || n.z() >= cos_max) out.push_back(n);
    }
    return out;
}

Eigen::MatrixXd brute_force_irradiance(const Environment& env,
                                       const std::vector<Eigen::Vector3d>& normals) {
    const auto samples = make_sample_set(env);
    const int nn = static_cast<int>(normals.size());
    Eigen::Matrix3Xd nm(3, nn);
    for (int i = 0; i < nn; ++i) nm.col(i) = normals[static_cast<size_t>(i)];
    using Acc = Eigen::MatrixXd;
    Progress progress("brute-force irradiance", samples->size());
    return parallel::reduce(
        samples->size(), 8192, Acc(Acc::Zero(nn, 3)),
        [&](int64_t begin, int64_t end) {
            Acc acc = Acc::Zero(nn, 3);
            progress.add(end - begin);
            Eigen::Vector3d dir;
            double w, v[3];
            Eigen::VectorXd cosines(nn);
            for (int64_t i = begin; i < end; ++i) {
                if (!samples->sample(i, dir, w, v)) continue;
                if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;
                cosines.noalias() = nm.transpose() * dir;
                for (int k = 0; k < nn; ++k) {
                    const double c = cosines(k);
                    if (c <= 0) continue;
                    const double wc = w * c;
                    acc(k, 0) += wc * v[0];
                    acc(k, 1) += wc * v[1];
                    acc(k, 2) += wc * v[2];
                }
            }
            return acc;
        },
        [](Acc a, const Acc& b) { return Acc(a + b); });
}

double brute_force_self_error(const Environment& env, const std::vector<Eigen::Vector3d>& normals) {
    if (!env.full_sphere()) return 0.0;
    Environment unit;
    unit.layout = env.layout;
    unit.world_from_input = env.world_from_input;
    unit.radiance = image::Image(env.radiance.width, env.radiance.height, 3);
    std::fill(unit.radiance.pixels.begin(), unit.radiance.pixels.end(), 1.0f);
    const Eigen::MatrixXd e = brute_force_irradiance(unit, normals);
    return (e.col(0).array() - kPi).abs().maxCoeff() / kPi;
}

Eigen::MatrixXd sh_irradiance(const Eigen::MatrixXd& coeffs, int sh_bands,
                              const std::vector<Eigen::Vector3d>& normals) {
    const int n = sh::count(sh_bands);
    Eigen::MatrixXd out(static_cast<Eigen::Index>(normals.size()), coeffs.cols());
    std::vector<double> y(static_cast<size_t>(n));
    for (size_t i = 0; i < normals.size(); ++i) {
        sh::eval(sh_bands, normals[i], y.data());
        for (int c = 0; c < coeffs.cols(); ++c) {
            double e = 0;
            for (int l = 0; l < sh_bands; ++l) {
                const double a = sh::cosine_zonal(l);
                if (a == 0) continue;
                for (int m = -l; m <= l; ++m)
                    e += a * coeffs(sh::index(l, m), c) * y[static_cast<size_t>(sh::index(l, m))];
            }
            out(static_cast<Eigen::Index>(i), c) = e;
        }
    }
    return out;
}

IrradianceError irradiance_error(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& reference) {
    IrradianceError err;
    const Eigen::Index n = reference.rows();
    if (n == 0) return err;
    std::vector<double> ref(static_cast<size_t>(n)), est(static_cast<size_t>(n));
    double ref_max = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        ref[static_cast<size_t>(i)] = luminance(reference(i, 0), reference(i, 1), reference(i, 2));
        est[static_cast<size_t>(i)] = luminance(approx(i, 0), approx(i, 1), approx(i, 2));
        ref_max = std::max(ref_max, std::abs(ref[static_cast<size_t>(i)]));
    }
    const double floor = kRelFloor * ref_max;
    double sum = 0, sum2 = 0, abs1 = 0, abs2 = 0, ref_sum = 0;
    for (size_t i = 0; i < ref.size(); ++i) {
        const double abs_err = std::abs(est[i] - ref[i]);
        const double rel = abs_err / std::max(std::abs(ref[i]), floor > 0 ? floor : 1e-30);
        sum += rel;
        sum2 += rel * rel;
        abs1 += abs_err;
        abs2 += abs_err * abs_err;
        ref_sum += ref[i];
        err.max_rel = std::max(err.max_rel, rel);
        err.max_abs = std::max(err.max_abs, abs_err);
    }
    err.mean_rel = sum / static_cast<double>(n);
    err.rms_rel = std::sqrt(sum2 / static_cast<double>(n));
    if (ref_sum != 0) {
        err.rms_over_mean = std::sqrt(abs2 / static_cast<double>(n)) * n / ref_sum;
        err.abs_over_mean = abs1 / ref_sum;
    }
    return err;
}

nlohmann::json validation_json(const Environment& env, const Eigen::MatrixXd& coeffs_unwindowed,
                               const Eigen::MatrixXd& coeffs_final, int sh_bands,
                               const std::vector<Eigen::Vector3d>& normals) {
    auto to_json = [](const IrradianceError& e) {
        return nlohmann::json{{"mean_rel", e.mean_rel}, {"rms_rel", e.rms_rel},
                              {"max_rel", e.max_rel},   {"max_abs", e.max_abs},
                              {"rms_over_mean", e.rms_over_mean},
                              {"abs_over_mean", e.abs_over_mean}};
    };
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::MatrixXd ref = brute_force_irradiance(env, normals);
    const double brute_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json by_bands = nlohmann::json::object();
    for (int b = 1; b <= sh_bands; ++b)
        by_bands[std::to_string(b)] = to_json(irradiance_error(sh_irradiance(coeffs_unwindowed, b, normals), ref));
    nlohmann::json out = to_json(irradiance_error(sh_irradiance(coeffs_final, sh_bands, normals), ref));
    out["normals"] = normals.size();
    out["brute_force_time_s"] = brute_s;
    out["reference_self_error"] = brute_force_self_error(env, normals);
    out["rel_floor_of_max"] = kRelFloor;
    out["error_by_sh_bands"] = by_bands;
    return out;
}

}  // namespace inlight::envmap
