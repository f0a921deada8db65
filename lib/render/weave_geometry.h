// render/weave_geometry.h: a woven fabric (lib/weave) as renderable shapes: its yarns as round
// B-spline tubes (render/accel.h CurveSet, the weave's own control points, so Embree's curve is
// the weave's centre-line exactly) repeated periodically over a region, so that every point of
// the region has its neighbours for shadowing, masking and inter-reflection, and the holder
// plate under it.
//
// Frame: the weave's sample frame (weave/weave.h) is the world frame, lengths in millimetres:
// the tile's corner at the world origin, the fabric's mid-plane at z = 0 plus `z_offset_mm`.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "brdf/brdf.h"
#include "render/accel.h"
#include "weave/weave.h"

namespace inlight::render {

struct WeaveShapes {
    Shape yarns;    ///< kCurves
    Shape backing;  ///< kPatch just below the lowest yarn surface, the region and 60 slab
                    ///< thicknesses around it
    brdf::Material yarn_material;     ///< the fabric's material (albedo replaced per yarn)
    brdf::Material backing_material;  ///< Lambertian, the fabric's backing_albedo
    int segments = 0;
};

/// Yarn tubes covering at least the rectangle [lo_mm, hi_mm] (x, y) (the caller adds any margin
/// it needs) and a backing plate under them. Precondition: lo_mm < hi_mm (checked).
WeaveShapes weave_shapes(const weave::Weave& weave, const Eigen::Vector2d& lo_mm,
                         const Eigen::Vector2d& hi_mm, double z_offset_mm = 0);

/// How far (mm, horizontally) a ray may travel inside the fabric's slab [z_min, z_max] before
/// leaving it, for directions at most `max_theta_deg` from the normal: the margin a region
/// needs around the part that is seen so that shadows and masking find their neighbours.
double slab_margin_mm(const weave::Weave& weave, double max_theta_deg);

}  // namespace inlight::render
