#include "render/camera.h"

#include <Eigen/Geometry>
#include <cmath>

#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"

namespace inlight::render {

constexpr EnumName<Projection> kProjectionNames[] = {{Projection::kOrthographic, "orthographic"},
                                                     {Projection::kPerspective, "perspective"}};

Projection projection_from_string(const std::string& name) {
    return enum_from_string<Error>(kProjectionNames, name, "projection");
}

std::string to_string(Projection p) { return enum_to_string(kProjectionNames, p); }

void Camera::validate(const std::string& context) const {
    const Eigen::Vector3d forward = look_at - position;
    if (!(forward.norm() > 0)) throw Error(str(context, "position equals look_at"));
    if (!(forward.normalized().cross(up).norm() > 1e-9)) {
        throw Error(str(context, "up is parallel to the view direction"));
    }
    if (width_px < 1 || height_px < 1 || width_px > 16384 || height_px > 16384) {
        throw Error(
            str(context, "image size ", width_px, "x", height_px, " is outside 1..16384 pixels"));
    }
    if (projection == Projection::kPerspective && !(fov_deg > 0 && fov_deg < 180)) {
        throw Error(str(context, "fov_deg ", fov_deg, " is outside (0, 180)"));
    }
    if (projection == Projection::kOrthographic && !(ortho_height > 0)) {
        throw Error(str(context, "ortho_height ", ortho_height, " must be > 0"));
    }
}

Ray Camera::generate_ray(double x, double y) const {
    const Eigen::Vector3d forward = (look_at - position).normalized();
    const Eigen::Vector3d right = forward.cross(up).normalized();
    const Eigen::Vector3d true_up = right.cross(forward);
    // Screen coordinates: sx in [-aspect, aspect], sy in [-1, 1] (+1 at the top row).
    const double aspect = static_cast<double>(width_px) / height_px;
    const double sx = (2.0 * x / width_px - 1.0) * aspect;
    const double sy = 1.0 - 2.0 * y / height_px;
    Ray ray;
    if (projection == Projection::kOrthographic) {
        const double half = 0.5 * ortho_height;
        ray.origin = position + right * (sx * half) + true_up * (sy * half);
        ray.dir = forward;
    } else {
        const double t = std::tan(0.5 * fov_deg * kPi / 180.0);
        ray.origin = position;
        ray.dir = (forward + right * (sx * t) + true_up * (sy * t)).normalized();
    }
    return ray;
}

}  // namespace inlight::render
