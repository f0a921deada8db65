#include "calib/camera_model.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"

namespace inlight::calib {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Step of the scan for the end of the one-to-one domain: fine enough that no turning point of
/// a 4-term polynomial is skipped (their features are > 0.05 rad wide), cheap (3,142 samples).
constexpr double kScanStep = 1e-3;
/// Newton/bisection converge when the radial residual is below this (normalised units; 1e-12
/// times a focal length of 1,000 px is 1e-9 px).
constexpr double kRadialTolerance = 1e-12;
/// The 2-D undistortion must reproduce the distorted point to this (normalised units).
constexpr double kUndistortTolerance = 1e-10;

int expected_distortion_size(ModelType type) {
    switch (type) {
        case ModelType::kFisheye:
            return 4;
        case ModelType::kPinhole:
            return 5;
        case ModelType::kOmnidir:
            return 4;
    }
    return 0;
}

double dist(const std::vector<double>& d, size_t i) { return i < d.size() ? d[i] : 0.0; }

/// r (1 + k1 r^2 + k2 r^4 + k3 r^6) and its derivative in r (pinhole/omnidir radial part).
void radial_poly(const CameraModel& m, double r, double& value, double& deriv) {
    const double k1 = dist(m.distortion, 0), k2 = dist(m.distortion, 1);
    const double k3 = m.type == ModelType::kPinhole ? dist(m.distortion, 4) : 0.0;
    const double r2 = r * r;
    value = r * (1 + r2 * (k1 + r2 * (k2 + r2 * k3)));
    deriv = 1 + r2 * (3 * k1 + r2 * (5 * k2 + r2 * 7 * k3));
}

/// Fisheye theta_d(theta) and its derivative.
void fisheye_poly(const CameraModel& m, double theta, double& value, double& deriv) {
    const double k1 = m.distortion[0], k2 = m.distortion[1], k3 = m.distortion[2],
                 k4 = m.distortion[3];
    const double t2 = theta * theta;
    value = theta * (1 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
    deriv = 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4)));
}

/// Solves f(x) = target for x in [0, hi] where f is increasing there, f(0) = 0, by Newton
/// steps kept inside a shrinking bracket (bisection when a step leaves it).
template <typename F>
std::optional<double> solve_increasing(F f, double target, double hi) {
    double lo = 0, x = std::min(target, hi);
    for (int it = 0; it < 100; ++it) {
        double v, d;
        f(x, v, d);
        const double r = v - target;
        if (std::abs(r) < kRadialTolerance) return x;
        if (r > 0)
            hi = x;
        else
            lo = x;
        double next = d > 0 ? x - r / d : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (hi - lo < 1e-15) return x;
        x = next;
    }
    return std::nullopt;
}

/// Brown-Conrady distortion of normalised undistorted coordinates and its Jacobian.
Eigen::Vector2d distort(const CameraModel& m, const Eigen::Vector2d& p, Eigen::Matrix2d* jac) {
    const double k1 = dist(m.distortion, 0), k2 = dist(m.distortion, 1);
    const double p1 = dist(m.distortion, 2), p2 = dist(m.distortion, 3);
    const double k3 = m.type == ModelType::kPinhole ? dist(m.distortion, 4) : 0.0;
    const double x = p.x(), y = p.y(), r2 = x * x + y * y;
    const double c = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    Eigen::Vector2d out(x * c + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                        y * c + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y);
    if (jac) {
        const double cp = k1 + r2 * (2 * k2 + r2 * 3 * k3);  // dc / d(r2)
        (*jac)(0, 0) = c + 2 * x * x * cp + 2 * p1 * y + 6 * p2 * x;
        (*jac)(0, 1) = 2 * x * y * cp + 2 * p1 * x + 2 * p2 * y;
        (*jac)(1, 0) = 2 * x * y * cp + 2 * p1 * x + 2 * p2 * y;
        (*jac)(1, 1) = c + 2 * y * y * cp + 6 * p1 * y + 2 * p2 * x;
    }
    return out;
}

/// Normalised distorted coordinates of a pixel (inverse of the affine K).
Eigen::Vector2d normalised(const CameraModel& m, const Eigen::Vector2d& pixel) {
    const double y = (pixel.y() - m.cy) / m.fy;
    const double x = (pixel.x() - m.cx - m.skew * y) / m.fx;
    return {x, y};
}

}  // namespace

constexpr EnumName<ModelType> kModelTypeNames[] = {
    {ModelType::kFisheye, "fisheye"},
    {ModelType::kPinhole, "pinhole"},
    {ModelType::kOmnidir, "omnidir"},
};

std::string to_string(ModelType type) { return enum_to_string(kModelTypeNames, type); }

ModelType model_type_from_string(const std::string& name) {
    return enum_from_string(kModelTypeNames, name, "camera model");
}

CameraModel CameraModel::make(ModelType type, int width, int height, double fx, double fy,
                              double cx, double cy) {
    CameraModel m;
    m.type = type;
    m.width = width;
    m.height = height;
    m.fx = fx;
    m.fy = fy;
    m.cx = cx;
    m.cy = cy;
    m.distortion.assign(static_cast<size_t>(expected_distortion_size(type)), 0.0);
    return m;
}

double CameraModel::radial(double theta) const {
    INLIGHT_CHECK_EQ(static_cast<int>(distortion.size()), expected_distortion_size(type));
    switch (type) {
        case ModelType::kFisheye: {
            double v, d;
            fisheye_poly(*this, theta, v, d);
            return v;
        }
        case ModelType::kPinhole: {
            if (theta >= 0.5 * kPi) return kInf;
            double v, d;
            radial_poly(*this, std::tan(theta), v, d);
            return v;
        }
        case ModelType::kOmnidir: {
            const double den = std::cos(theta) + xi;
            if (den <= 0) return kInf;
            double v, d;
            radial_poly(*this, std::sin(theta) / den, v, d);
            return v;
        }
    }
    return kInf;
}

double CameraModel::max_theta() const {
    // The radial function must be finite and increasing: scan, then bisect the first failure.
    auto increasing_at = [&](double t) {
        const double a = radial(t - 0.5 * kScanStep * 1e-3), b = radial(t + 0.5 * kScanStep * 1e-3);
        return std::isfinite(b) && b > a;
    };
    double prev = radial(0.0);
    double t = 0;
    while (t + kScanStep <= kPi) {
        const double next_t = t + kScanStep;
        const double v = radial(next_t);
        if (!std::isfinite(v) || v <= prev) break;
        prev = v;
        t = next_t;
    }
    if (t + kScanStep > kPi) return t;
    double lo = t, hi = t + kScanStep;
    for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (increasing_at(mid))
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& p) const {
    INLIGHT_CHECK_EQ(static_cast<int>(distortion.size()), expected_distortion_size(type));
    Eigen::Vector2d nd = Eigen::Vector2d::Zero();
    switch (type) {
        case ModelType::kFisheye: {
            const double rxy = std::hypot(p.x(), p.y());
            const double theta = std::atan2(rxy, p.z());
            double td, d;
            fisheye_poly(*this, theta, td, d);
            if (rxy > 0) {
                nd = Eigen::Vector2d(p.x(), p.y()) * (td / rxy);
            } else {
                nd = Eigen::Vector2d::Zero();
            }
            break;
        }
        case ModelType::kPinhole: {
            if (p.z() <= 0) return std::nullopt;
            nd = distort(*this, Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()), nullptr);
            break;
        }
        case ModelType::kOmnidir: {
            const double n = p.norm();
            if (n <= 0) return std::nullopt;
            const double den = p.z() / n + xi;
            if (den <= 0) return std::nullopt;
            nd = distort(*this, Eigen::Vector2d(p.x() / n / den, p.y() / n / den), nullptr);
            break;
        }
    }
    return Eigen::Vector2d(fx * nd.x() + skew * nd.y() + cx, fy * nd.y() + cy);
}

std::optional<Eigen::Vector3d> CameraModel::unproject(const Eigen::Vector2d& pixel) const {
    return Unprojector(*this)(pixel);
}

std::vector<std::string> CameraModel::parameter_names() const {
    std::vector<std::string> names = {"fx", "fy", "cx", "cy", "skew"};
    switch (type) {
        case ModelType::kFisheye:
            names.insert(names.end(), {"k1", "k2", "k3", "k4"});
            break;
        case ModelType::kPinhole:
            names.insert(names.end(), {"k1", "k2", "p1", "p2", "k3"});
            break;
        case ModelType::kOmnidir:
            names.insert(names.end(), {"xi", "k1", "k2", "p1", "p2"});
            break;
    }
    return names;
}

Eigen::VectorXd CameraModel::parameters() const {
    INLIGHT_CHECK_EQ(static_cast<int>(distortion.size()), expected_distortion_size(type));
    const int n = static_cast<int>(parameter_names().size());
    Eigen::VectorXd p(n);
    p << fx, fy, cx, cy, skew, Eigen::VectorXd::Zero(n - 5);
    int i = 5;
    if (type == ModelType::kOmnidir) p[i++] = xi;
    for (double d : distortion) p[i++] = d;
    return p;
}

void CameraModel::set_parameters(const Eigen::VectorXd& p) {
    INLIGHT_CHECK_EQ(static_cast<int>(p.size()), static_cast<int>(parameter_names().size()));
    fx = p[0];
    fy = p[1];
    cx = p[2];
    cy = p[3];
    skew = p[4];
    int i = 5;
    if (type == ModelType::kOmnidir) xi = p[i++];
    distortion.assign(static_cast<size_t>(expected_distortion_size(type)), 0.0);
    for (double& d : distortion) d = p[i++];
}

Unprojector::Unprojector(const CameraModel& model) : m_model(model) {
    INLIGHT_CHECK_EQ(static_cast<int>(model.distortion.size()),
                     expected_distortion_size(model.type));
    INLIGHT_CHECK(model.fx > 0 && model.fy > 0) << "focal lengths must be positive";
    m_max_theta = model.max_theta();
    m_max_radial = model.radial(m_max_theta);
    if (model.type == ModelType::kPinhole) {
        m_max_undist_r = std::tan(m_max_theta);
    } else if (model.type == ModelType::kOmnidir) {
        m_max_undist_r = std::sin(m_max_theta) / (std::cos(m_max_theta) + model.xi);
    }
}

std::optional<Eigen::Vector3d> Unprojector::operator()(const Eigen::Vector2d& pixel) const {
    const CameraModel& m = m_model;
    const Eigen::Vector2d nd = normalised(m, pixel);
    if (m.type == ModelType::kFisheye) {
        const double td = nd.norm();
        if (!(td <= m_max_radial)) return std::nullopt;
        if (td == 0) return Eigen::Vector3d(0, 0, 1);
        auto theta = solve_increasing(
            [&](double t, double& v, double& d) { fisheye_poly(m, t, v, d); }, td, m_max_theta);
        if (!theta) return std::nullopt;
        const double s = std::sin(*theta) / td;
        return Eigen::Vector3d(nd.x() * s, nd.y() * s, std::cos(*theta));
    }

    // Pinhole and omnidir: invert the radial part first (robust start), then Newton in 2-D for
    // the tangential terms.
    const double rd = nd.norm();
    Eigen::Vector2d u = nd;
    if (rd > 0) {
        double max_rd, unused;
        radial_poly(m, m_max_undist_r, max_rd, unused);
        if (!(rd <= max_rd * (1 + 1e-12))) {
            // Tangential terms can push a valid point slightly beyond; let Newton decide.
            u = nd * (m_max_undist_r / rd);
        } else {
            auto r =
                solve_increasing([&](double x, double& v, double& d) { radial_poly(m, x, v, d); },
                                 rd, m_max_undist_r);
            if (!r) return std::nullopt;
            u = nd * (*r / rd);
        }
    }
    bool converged = false;
    for (int it = 0; it < 50; ++it) {
        Eigen::Matrix2d jac;
        const Eigen::Vector2d res = distort(m, u, &jac) - nd;
        if (res.norm() < kUndistortTolerance) {
            converged = true;
            break;
        }
        u -= jac.inverse() * res;
        if (!u.allFinite()) return std::nullopt;
    }
    if (!converged || u.norm() > m_max_undist_r * (1 + 1e-9)) return std::nullopt;

    if (m.type == ModelType::kPinhole) return Eigen::Vector3d(u.x(), u.y(), 1.0).normalized();
    // Mei lift from the normalised plane to the unit sphere.
    const double r2 = u.squaredNorm();
    const double disc = 1 + (1 - m.xi * m.xi) * r2;
    if (disc < 0) return std::nullopt;
    const double factor = (m.xi + std::sqrt(disc)) / (1 + r2);
    return Eigen::Vector3d(factor * u.x(), factor * u.y(), factor - m.xi).normalized();
}

Eigen::Matrix3d rotation_from_rodrigues(const Eigen::Vector3d& rvec) {
    const double angle = rvec.norm();
    if (angle < 1e-15) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(angle, rvec / angle).toRotationMatrix();
}

Eigen::Vector3d rodrigues_from_rotation(const Eigen::Matrix3d& rotation) {
    const Eigen::AngleAxisd aa(rotation);
    return aa.axis() * aa.angle();
}

}  // namespace inlight::calib
