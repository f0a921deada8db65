// render/accel.h: ray queries against the scene's shapes through Embree 3 (the only file that
// includes Embree is accel.cpp). The patch and the sphere are Embree user geometries
// intersected analytically in double precision; meshes are Embree triangle meshes; curves
// (woven yarns, render/weave_geometry.h) are Embree round uniform cubic B-spline curves
// (RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/mesh.h"

namespace inlight::render {

enum class ShapeKind {
    kPatch,   ///< rectangle in the plane z = center.z facing +z: |x - cx| <= w/2, |y - cy| <= h/2
    kSphere,  ///< center, radius
    kMesh,    ///< triangles in world coordinates
    kCurves,  ///< round B-spline tubes (yarns), world coordinates
    kWeave,   ///< scene files only: a fabric file, turned into kCurves and a backing kPatch
};
/// "patch" | "sphere" | "mesh" | "weave" (a scene file's name); throws Error otherwise.
ShapeKind shape_from_string(const std::string& name);

/// Round uniform cubic B-spline tubes, Embree's RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE layout:
/// segment k uses control points first[k] .. first[k] + 3, each (x, y, z, radius).
struct CurveSet {
    std::vector<Eigen::Vector4f> control_points;
    std::vector<unsigned> first;  ///< per segment: index of its first control point
    /// Per segment: the curve's colour (linear_srgb albedo replacing the material's), the
    /// along-curve coordinate at u = 0 and the curve length per unit u (both world units), for
    /// the ply-twist relief.
    std::vector<Eigen::Vector3f> albedo;
    std::vector<float> s_start, ds_du;
    /// Ply twist as a shading-normal relief (weave::Twist): `plies` helical ridges at
    /// `angle` (radians) to the axis tilt the normal by up to `depth` (radians); 0 = none.
    int plies = 0;
    double angle = 0, depth = 0;
};

/// One shape in world coordinates.
struct Shape {
    ShapeKind kind = ShapeKind::kPatch;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    Eigen::Vector2d size{1, 1};  ///< patch width (x) and height (y)
    double radius = 0.5;
    std::shared_ptr<const TriangleMesh> mesh;  ///< kMesh, world coordinates
    std::shared_ptr<const CurveSet> curves;    ///< kCurves, world coordinates
};

/// A ray's closest intersection.
struct SurfaceHit {
    double t = 0;
    int shape = -1;                                 ///< index into the shape list
    int prim = 0;                                   ///< triangle index for meshes
    Eigen::Vector3d p = Eigen::Vector3d::Zero();    ///< world position (on the surface)
    Eigen::Vector3d ng = Eigen::Vector3d::UnitZ();  ///< unit geometric normal (outward / CCW side)
    Eigen::Vector3d ns = Eigen::Vector3d::UnitZ();  ///< unit shading normal (same side as ng)
    Eigen::Vector3d dpdu = Eigen::Vector3d::UnitX();  ///< unit tangent along increasing u
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();     ///< texture coordinates, v down
    /// kCurves: the curve's albedo, which replaces the material's (has_albedo = true).
    bool has_albedo = false;
    Eigen::Vector3d albedo = Eigen::Vector3d::Zero();
};

/// Embree device + scene over a list of shapes. Queries are thread-safe and deterministic.
class Accel {
  public:
    /// Builds the acceleration structure. Throws Error on an Embree error (the device's error
    /// callback is installed right after rtcNewDevice) or on degenerate shapes.
    explicit Accel(std::vector<Shape> shapes);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    /// Closest hit with t in (0, ray.t_max]. Returns false on a miss.
    bool intersect(const Ray& ray, SurfaceHit* hit) const;
    /// True if anything is hit with t in (0, ray.t_max).
    bool occluded(const Ray& ray) const;

    const std::vector<Shape>& shapes() const;
    /// Length of the scene's bounding-box diagonal (world units), for ray offsets.
    double scene_scale() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> m;
};

}  // namespace inlight::render
