// calib/maps.h: what the renderer needs to read light from a camera frame (the inlight report,
// section 2.2.1): a unit direction per pixel in the device frame, the solid angle each pixel
// covers, and a validity mask, at full resolution and downscaled.
//
// Solid angles are exact spherical areas: each pixel is the quad of the rays through its four
// corners, split into two spherical triangles (Van Oosterom and Strackee 1983, "The solid angle
// of a plane triangle", eq. 8: tan(omega / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a)). The
// quads tile the covered part of the sphere, so the sum over any set of pixels is the solid
// angle of their union.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/camera_model.h"
#include "image/image.h"

namespace inlight::calib {

/// The default device_from_camera for a front camera: diag(-1, -1, 1). The device frame
/// (docs/conventions.md) has +z out of the screen toward the viewer (the front camera's optical
/// axis), +x right and +y up as the viewer sees the screen; OpenCV's camera frame has x right in
/// the image, y down, z forward. With the image upright, camera z = device z and camera y =
/// -device y, so camera x = -device x: the raw front-camera image appears mirrored to the viewer.
Eigen::Matrix3d default_device_from_camera();

/// A lens' image circle in pixels (OpenCV convention). radius_px = 0 means none.
struct ImageCircle {
    double cx = 0;
    double cy = 0;
    double radius_px = 0;
};

struct MapOptions {
    /// Rotation applied to camera-frame rays (see default_device_from_camera).
    Eigen::Matrix3d device_from_camera = default_device_from_camera();
    /// Valid pixels see at most this far from the optical axis (radians); 0 = up to the
    /// model's one-to-one limit (CameraModel::max_theta).
    double max_theta = 0;
    /// Valid pixels lie inside this circle (radius 0 = no circle).
    ImageCircle circle;
};

/// Direction, solid-angle and mask images of one resolution. Pixel (x, y) of a map refers to
/// the camera pixel (x, y) (its centre, OpenCV convention). All are ColorSpace::kData.
struct DirectionMaps {
    image::Image directions;   ///< 3 channels: unit x, y, z in the device frame; 0 outside mask
    image::Image solid_angle;  ///< 1 channel: steradians per pixel; 0 outside the mask
    image::Image mask;         ///< 1 channel: 1 inside, 0 outside
    double covered_solid_angle_sr = 0;  ///< sum of solid_angle
    int64_t valid_pixels = 0;
    double max_theta = 0;  ///< the polar-angle limit the mask used, radians
};

/// Full-resolution maps of `camera` (camera.width x camera.height). Parallel over rows;
/// bit-identical for any thread count.
DirectionMaps compute_maps(const CameraModel& camera, const MapOptions& options);

/// Downscales to width x height (each at most the full size, checked: UsageError). Output pixel
/// (X, Y) gathers the full-resolution pixels x in [floor(X W / w), floor((X + 1) W / w)) and
/// likewise in y: the mask is their majority (more than half valid); the direction is the
/// component-wise median of the valid pixels' directions, renormalised (as the inlight report
/// did); the solid angle is the sum over the valid pixels when the output pixel is valid, else
/// 0 (so covered_solid_angle_sr may drop slightly at the mask's edge).
DirectionMaps downscale_maps(const DirectionMaps& full, int width, int height);

/// Writes <dir>/directions.exr (float RGB = x, y, z), <dir>/solid_angle.exr (float, channel Y)
/// and <dir>/mask.png (8-bit 0/255, written linearly), each atomically. Returns the paths.
std::vector<std::string> write_maps(const std::string& dir, const DirectionMaps& maps);

/// Largest map side accepted by parse_sizes, pixels.
inline constexpr int kMaxMapSidePx = 16384;

/// Parses "WxH[,WxH...]" (e.g. "200x126,100x63"), each side an integer in [1, kMaxMapSidePx].
/// Throws UsageError "<flag> '<spec>': ..." naming the bad item.
std::vector<Eigen::Vector2i> parse_sizes(const std::string& spec,
                                         const std::string& flag = "--downscale");

/// Estimates a lens' image circle from `brightest`, the per-pixel maximum of photographs taken
/// through it: pixels above 8% of its 99th percentile (and above code 12) are lit, and the
/// circle's radius is the first radius around (cx, cy) from which on fewer than half the pixels
/// of each 1-px ring inside the frame are lit. radius_px = 0 when lit pixels reach the
/// frame's farthest corner (no circle inside the image).
ImageCircle detect_image_circle(const GrayImage& brightest, double cx, double cy);

/// Per-pixel maximum of `image` into `brightest` (which starts empty). Precondition: same size.
void accumulate_max(GrayImage& brightest, const GrayImage& image);

}  // namespace inlight::calib
