#include "core/conventions.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/number.h"

namespace inlight {

Eigen::Vector3d direction_from_spherical(double theta, double phi) {
    const double s = std::sin(theta);
    return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

void spherical_from_direction(const Eigen::Vector3d& dir, double& theta, double& phi) {
    const double r = dir.norm();
    theta = std::acos(std::clamp(dir.z() / r, -1.0, 1.0));
    phi = std::atan2(dir.y(), dir.x());
}

Eigen::Vector3d latlong_direction(double u, double v) {
    return direction_from_spherical(kPi * v, kPi * (1.0 - 2.0 * u));
}

Eigen::Vector2d latlong_uv(const Eigen::Vector3d& dir) {
    double theta, phi;
    spherical_from_direction(dir, theta, phi);
    double u = 0.5 * (1.0 - phi * kInvPi);  // phi in (-pi, pi] -> u in [0, 1)
    if (u >= 1.0) u -= 1.0;
    if (u < 0.0) u += 1.0;
    return {u, theta * kInvPi};
}

double latlong_pixel_solid_angle(int row, int width, int height) {
    const double theta0 = kPi * row / height;
    const double theta1 = kPi * (row + 1) / height;
    return (2.0 * kPi / width) * (std::cos(theta0) - std::cos(theta1));
}

Eigen::Matrix3d parse_rotation(const std::string& spec) {
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    if (spec.empty() || spec == "none") return r;
    if (spec == "y-up") return Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX()).matrix();
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const auto eq = item.find('=');
        if (eq != 1 || (item[0] != 'x' && item[0] != 'y' && item[0] != 'z')) {
            throw UsageError(str("rotation '", spec,
                                 "': expected 'none', 'y-up' or axis=degrees items such as "
                                 "'z=90,x=-30'"));
        }
        const double deg = parse_finite(item.substr(2), str("rotation '", spec, "'"));
        if (std::abs(deg) > 360) {
            throw UsageError(str("rotation '", spec, "': ", deg, " degrees is outside [-360, 360]"));
        }
        const Eigen::Vector3d axis = item[0] == 'x'   ? Eigen::Vector3d::UnitX()
                                     : item[0] == 'y' ? Eigen::Vector3d::UnitY()
                                                      : Eigen::Vector3d::UnitZ();
        r = Eigen::AngleAxisd(deg * kPi / 180.0, axis).matrix() * r;
    }
    return r;
}

}  // namespace inlight
