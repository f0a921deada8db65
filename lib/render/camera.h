// render/camera.h: the viewer: an orthographic or pinhole perspective camera producing primary
// rays for image positions. The app's case is the device frame of docs/conventions.md: the
// viewer sits on +z and looks along -z at the fabric patch in the z = 0 plane, +y up.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>

namespace inlight::render {

/// A ray: origin and unit direction in the world frame, valid for t in [0, t_max].
struct Ray {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d dir = Eigen::Vector3d::UnitZ();
    double t_max = std::numeric_limits<double>::infinity();
};

enum class Projection { kOrthographic, kPerspective };
/// "orthographic" | "perspective" (a scene file's name); throws Error otherwise.
Projection projection_from_string(const std::string& name);
std::string to_string(Projection p);

struct Camera {
    Projection projection = Projection::kOrthographic;
    Eigen::Vector3d position{0, 0, 1};  ///< world units
    Eigen::Vector3d look_at{0, 0, 0};
    Eigen::Vector3d up{0, 1, 0};  ///< need not be orthogonal to the view direction
    double fov_deg = 40;          ///< perspective: full vertical field of view, (0, 180)
    double ortho_height = 1;      ///< orthographic: world-space height of the image, > 0
    int width_px = 256;
    int height_px = 256;

    /// The primary ray through image position (x, y) in pixels: origin top-left, y down,
    /// pixel centres at +0.5. Preconditions (checked by validate()): position != look_at,
    /// up not parallel to the view direction.
    Ray generate_ray(double x, double y) const;
    /// Throws Error (prefixed by `context`) when the parameters cannot make rays.
    void validate(const std::string& context) const;
};

}  // namespace inlight::render
