#include "render/weave_geometry.h"

#include <cmath>

#include "core/check.h"
#include "core/conventions.h"

namespace inlight::render {

WeaveShapes weave_shapes(const weave::Weave& w, const Eigen::Vector2d& lo,
                         const Eigen::Vector2d& hi, double z_offset_mm) {
    INLIGHT_CHECK(lo.x() < hi.x() && lo.y() < hi.y()) << "empty region";
    auto curves = std::make_shared<CurveSet>();
    for (const weave::Yarn& y : w.yarns) {
        const bool warp = y.set == weave::ThreadSet::kWarp;
        // Copies of this thread across the region: warp threads repeat along x, weft along y.
        const double period = warp ? w.period_x_mm : w.period_y_mm;
        const double across_lo = (warp ? lo.x() : lo.y()) - y.radius_mm - y.offset_mm;
        const double across_hi = (warp ? hi.x() : hi.y()) + y.radius_mm - y.offset_mm;
        const double along_lo = warp ? lo.y() : lo.x(), along_hi = warp ? hi.y() : hi.x();
        for (long long k = static_cast<long long>(std::floor(across_lo / period));
             k <= static_cast<long long>(std::ceil(across_hi / period)); ++k) {
            const Eigen::Vector2d shift = warp ? Eigen::Vector2d(k * period, 0)
                                               : Eigen::Vector2d(0, k * period);
            double s_start = 0;
            const std::vector<Eigen::Vector4d> cps =
                y.control_points(along_lo - y.radius_mm, along_hi + y.radius_mm, shift, &s_start);
            const auto base = static_cast<unsigned>(curves->control_points.size());
            for (const Eigen::Vector4d& q : cps) {
                curves->control_points.emplace_back(static_cast<float>(q.x()),
                                                    static_cast<float>(q.y()),
                                                    static_cast<float>(q.z() + z_offset_mm),
                                                    static_cast<float>(q.w()));
            }
            for (size_t seg = 0; seg + 3 < cps.size(); ++seg) {
                curves->first.push_back(base + static_cast<unsigned>(seg));
                curves->albedo.push_back(y.albedo.cast<float>());
                curves->s_start.push_back(
                    static_cast<float>(s_start + static_cast<double>(seg) * y.knot_spacing_mm));
                curves->ds_du.push_back(static_cast<float>(y.knot_spacing_mm));
            }
        }
    }
    const weave::Twist& t = w.spec.twist;
    curves->plies = t.plies;
    curves->angle = t.angle_deg * kPi / 180;
    curves->depth = t.depth_deg * kPi / 180;

    WeaveShapes out;
    out.segments = static_cast<int>(curves->first.size());
    out.yarns.kind = ShapeKind::kCurves;
    out.yarns.curves = std::move(curves);
    out.backing.kind = ShapeKind::kPatch;
    // Just below the lowest yarn surface: 1% of the slab's thickness, so that nothing pierces it
    // and rays between yarns and plate are not mistaken for self-intersections.
    const double gap = 0.01 * (w.z_max_mm - w.z_min_mm);
    out.backing.center = {0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()),
                          w.z_min_mm - gap + z_offset_mm};
    // The plate reaches 60 slab thicknesses past the region: a ray leaving a yarn downward at
    // 1 degree below the horizon still meets it (tan 89 = 57), so no light from below the
    // sample's plane leaks in at the edges.
    out.backing.size = (hi - lo) + Eigen::Vector2d::Constant(120 * (w.z_max_mm - w.z_min_mm));
    out.yarn_material = w.spec.material;
    out.backing_material.specular = brdf::Model::kLambert;
    out.backing_material.albedo = w.spec.backing_albedo;
    return out;
}

double slab_margin_mm(const weave::Weave& w, double max_theta_deg) {
    INLIGHT_CHECK(max_theta_deg >= 0 && max_theta_deg < 90) << max_theta_deg;
    return (w.z_max_mm - w.z_min_mm) * std::tan(max_theta_deg * kPi / 180);
}

}  // namespace inlight::render
