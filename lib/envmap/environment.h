// envmap/environment.h: environments as images plus their parameterisation: lat-long
// (Blender/Cycles), cube map (6 faces in a horizontal strip), angular light probe (Debevec),
// and fisheye camera frames with per-pixel direction and solid-angle maps.
//
// Every layout exposes its pixels as directional samples (direction in the world frame,
// exact solid angle in sr, linear radiance), so projection and brute-force integration share
// one quadrature. See docs/conventions.md for the frames.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "image/image.h"
#include "sh/fit.h"

namespace inlight::envmap {

enum class Layout {
    kLatLong,  ///< 2:1, Cycles: theta = pi v from +z, phi = pi (1 - 2u); exact row solid angles
    kCube,     ///< 6:1 strip of square faces +X -X +Y -Y +Z -Z, OpenGL face orientation
    kAngular,  ///< square Debevec angular map: r = |(u,v)|, theta = pi r from the view axis
    kFisheye,  ///< camera frame + direction map + solid-angle map (from `calibrate`)
};
/// "latlong" | "cube" | "angular" | "fisheye"; throws UsageError otherwise.
Layout layout_from_string(const std::string& name);
std::string to_string(Layout layout);

/// What to do with NaN/Inf pixels.
enum class NonFinitePolicy {
    kReject,  ///< throw Error naming the first bad pixel and the count (default)
    kZero,    ///< replace by 0, count them, warn
};

/// An environment ready to integrate. Radiance has 3 channels (linear_srgb).
struct Environment {
    Layout layout = Layout::kLatLong;
    image::Image radiance;
    image::Image directions;   ///< kFisheye: 3 channels, unit vectors in the input frame
    image::Image solid_angle;  ///< kFisheye: 1 channel, sr per pixel (0 = not observed)
    Eigen::Matrix3d world_from_input = Eigen::Matrix3d::Identity();
    std::string source;        ///< file name, for messages

    /// True when the layout covers the whole sphere (everything but kFisheye).
    bool full_sphere() const { return layout != Layout::kFisheye; }
};

/// Loading options (the CLI's --input-kind, --rotate, --intensity, --nonfinite, ...).
struct LoadOptions {
    Layout layout = Layout::kLatLong;
    std::string rotate = "none";  ///< core/conventions.h parse_rotation syntax
    double intensity = 1.0;       ///< linear scale applied to the radiance
    NonFinitePolicy nonfinite = NonFinitePolicy::kReject;
    std::string directions_path;   ///< kFisheye: direction map (EXR, 3 channels)
    std::string solid_angle_path;  ///< kFisheye: solid-angle map (EXR, 1 channel, sr)
};

/// What was found in the input pixels.
struct InputStats {
    int64_t nonfinite_values = 0;  ///< NaN/Inf channel values (replaced by 0 under kZero)
    int64_t negative_values = 0;   ///< slightly negative values are kept (linear quadrature)
    double min_value = 0;
    double max_value = 0;
};

/// Loads and checks an environment. Throws Error naming the file when the shape does not
/// match the layout ("sky.exr: expected a 2:1 lat-long map, got 1024x1000"), on non-finite
/// pixels under kReject, or when fisheye maps are missing or of another size.
Environment load_environment(const std::string& path, const LoadOptions& options,
                             InputStats* stats = nullptr);

/// As load_environment, for radiance already in memory (e.g. an 8-bit camera frame turned into
/// radiance through a response curve). `radiance` may be tagged linear_srgb or raw_camera.
Environment environment_from_image(image::Image radiance, const std::string& source,
                                   const LoadOptions& options, InputStats* stats = nullptr);

/// Checks an in-memory environment's shape for its layout (same messages as above).
void check_layout(const Environment& env);

/// Scans for NaN/Inf and negative values; applies the policy. `source` names the image.
InputStats scan_pixels(image::Image& img, NonFinitePolicy policy, const std::string& source);

/// The environment's pixels as directional samples in the world frame (valid while env lives).
std::unique_ptr<sh::SampleSet> make_sample_set(const Environment& env);

/// Exact solid angle of the cube texel (i, j) on a face of n x n texels (sums to 4 pi / 6).
double cube_texel_solid_angle(int i, int j, int n);
/// Direction of texture coordinates (s, t) in [0, 1]^2 of cube face `face` (0..5 = +X -X +Y -Y
/// +Z -Z) in the OpenGL cube-map convention (t grows downward, row 0 is t = 0).
Eigen::Vector3d cube_direction(int face, double s, double t);
/// Angular map (Debevec's light probes): direction of (u, v) in [-1, 1]^2 (v up),
/// r = |(u, v)| <= 1: (sin(pi r) u / r, sin(pi r) v / r, cos(pi r)) -- the inverse of Debevec's
/// (u, v) = (Dx, Dy) acos(Dz) / (pi |(Dx, Dy)|); the map's centre looks along +z.
Eigen::Vector3d angular_direction(double u, double v);

}  // namespace inlight::envmap
