#include "render/accel.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <mutex>

#include "core/check.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/log.h"
#include "weave/weave.h"

namespace inlight::render {

constexpr EnumName<ShapeKind> kShapeNames[] = {
    {ShapeKind::kPatch, "patch"},
    {ShapeKind::kSphere, "sphere"},
    {ShapeKind::kMesh, "mesh"},
    {ShapeKind::kWeave, "weave"},
};

ShapeKind shape_from_string(const std::string& name) {
    return enum_from_string<Error>(kShapeNames, name, "shape");
}

namespace {

/// Embree's context extended with the query's double-precision ray, so that the analytic
/// shapes intersect in double (the Embree ray itself is float).
struct QueryContext {
    RTCIntersectContext rtc;  // must stay the first member
    const Ray* ray = nullptr;
};

/// Any tangent orthogonal to unit n (Duff et al. 2017).
Eigen::Vector3d any_tangent(const Eigen::Vector3d& n) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    return {1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x()};
}

/// Closest positive t of the analytic shape, or +inf.
double intersect_analytic(const Shape& s, const Ray& ray) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (s.kind == ShapeKind::kPatch) {
        if (ray.dir.z() == 0) return kInf;
        const double t = (s.center.z() - ray.origin.z()) / ray.dir.z();
        if (!(t > 0)) return kInf;
        const double x = ray.origin.x() + t * ray.dir.x() - s.center.x();
        const double y = ray.origin.y() + t * ray.dir.y() - s.center.y();
        return (std::abs(x) <= 0.5 * s.size.x() && std::abs(y) <= 0.5 * s.size.y()) ? t : kInf;
    }
    // Sphere: t^2 + 2 b t + c = 0 with unit dir; stable roots q and c / q.
    const Eigen::Vector3d oc = ray.origin - s.center;
    const double b = oc.dot(ray.dir);
    const double c = oc.squaredNorm() - s.radius * s.radius;
    const double disc = b * b - c;
    if (disc < 0) return kInf;
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = q, t1 = q != 0 ? c / q : q;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > 0) return t0;
    if (t1 > 0) return t1;
    return kInf;
}

void bounds_fn(const RTCBoundsFunctionArguments* args) {
    const Shape& s = *static_cast<const Shape*>(args->geometryUserPtr);
    Eigen::Vector3d lo, hi;
    if (s.kind == ShapeKind::kPatch) {
        const Eigen::Vector3d half(0.5 * s.size.x(), 0.5 * s.size.y(), 0.0);
        lo = s.center - half;
        hi = s.center + half;
    } else {
        lo = s.center - Eigen::Vector3d::Constant(s.radius);
        hi = s.center + Eigen::Vector3d::Constant(s.radius);
    }
    // Pad by a relative float ulp-scale margin so float bounds contain the double shape.
    const double pad = 1e-5 * (1.0 + (hi - lo).norm() + s.center.cwiseAbs().maxCoeff());
    RTCBounds* b = args->bounds_o;
    b->lower_x = static_cast<float>(lo.x() - pad);
    b->lower_y = static_cast<float>(lo.y() - pad);
    b->lower_z = static_cast<float>(lo.z() - pad);
    b->upper_x = static_cast<float>(hi.x() + pad);
    b->upper_y = static_cast<float>(hi.y() + pad);
    b->upper_z = static_cast<float>(hi.z() + pad);
}

void intersect_fn(const RTCIntersectFunctionNArguments* args) {
    if (args->N != 1 || !args->valid[0]) return;
    const Shape& s = *static_cast<const Shape*>(args->geometryUserPtr);
    const auto* ctx = reinterpret_cast<const QueryContext*>(args->context);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    const double t = intersect_analytic(s, *ctx->ray);
    if (!(t > rh->ray.tnear && t < rh->ray.tfar)) return;
    rh->ray.tfar = static_cast<float>(t);
    rh->hit.geomID = args->geomID;
    rh->hit.primID = args->primID;
    rh->hit.instID[0] = args->context->instID[0];
    rh->hit.u = rh->hit.v = 0;
    rh->hit.Ng_x = rh->hit.Ng_y = 0;
    rh->hit.Ng_z = 1;
}

void occluded_fn(const RTCOccludedFunctionNArguments* args) {
    if (args->N != 1 || !args->valid[0]) return;
    const Shape& s = *static_cast<const Shape*>(args->geometryUserPtr);
    const auto* ctx = reinterpret_cast<const QueryContext*>(args->context);
    auto* ray = reinterpret_cast<RTCRay*>(args->ray);
    const double t = intersect_analytic(s, *ctx->ray);
    if (t > ray->tnear && t < ray->tfar) ray->tfar = -std::numeric_limits<float>::infinity();
}

/// Collects the errors Embree reports through its device callback.
struct ErrorSink {
    std::mutex mutex;
    std::string first_error;
};

void error_fn(void* user, RTCError code, const char* message) {
    auto* sink = static_cast<ErrorSink*>(user);
    const std::string text = str("error ", static_cast<int>(code), ": ", message ? message : "");
    log::warn(str("Embree ", text));
    std::lock_guard<std::mutex> lock(sink->mutex);
    if (sink->first_error.empty()) sink->first_error = text;
}

}  // namespace

struct Accel::Impl {
    std::vector<Shape> shapes;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    double scale = 1;
    ErrorSink errors;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
    void throw_if_error(const std::string& what) {
        std::lock_guard<std::mutex> lock(errors.mutex);
        if (!errors.first_error.empty()) {
            throw Error(str("Embree: ", what, ": ", errors.first_error));
        }
    }

    /// A geometry of `type` whose Embree buffers hold `vertices` vertices of Dim floats
    /// (vertex(k): x, y, z[, radius] in double) and `prims` primitives of IndexDim indices
    /// (index(k, c)); [lo, hi] grows by each vertex's box (+- the radius when Dim is 4).
    template <int Dim, int IndexDim, typename Vertex, typename Index>
    RTCGeometry new_buffered_geometry(RTCGeometryType type, size_t vertices, size_t prims,
                                      Vertex vertex, Index index, const std::string& what,
                                      Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
        static_assert((Dim == 3 || Dim == 4) && (IndexDim == 1 || IndexDim == 3));
        RTCGeometry geom = rtcNewGeometry(device, type);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, Dim == 3 ? RTC_FORMAT_FLOAT3 : RTC_FORMAT_FLOAT4,
            Dim * sizeof(float), vertices));
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, IndexDim == 3 ? RTC_FORMAT_UINT3 : RTC_FORMAT_UINT,
            IndexDim * sizeof(unsigned), prims));
        try {
            throw_if_error(str("allocating ", what, " buffers"));
        } catch (...) {
            rtcReleaseGeometry(geom);
            throw;
        }
        for (size_t k = 0; k < vertices; ++k) {
            const Eigen::Matrix<double, Dim, 1> q = vertex(k);
            for (int j = 0; j < Dim; ++j) v[Dim * k + j] = static_cast<float>(q[j]);
            const Eigen::Vector3d r = Eigen::Vector3d::Constant(Dim == 4 ? q[Dim - 1] : 0.0);
            lo = lo.cwiseMin(q.template head<3>() - r);
            hi = hi.cwiseMax(q.template head<3>() + r);
        }
        for (size_t k = 0; k < prims; ++k) {
            for (int c = 0; c < IndexDim; ++c) idx[IndexDim * k + c] = index(k, c);
        }
        return geom;
    }
};

Accel::Accel(std::vector<Shape> shapes) : m(std::make_unique<Impl>()) {
    m->shapes = std::move(shapes);
    m->device = rtcNewDevice(nullptr);
    if (!m->device) {
        throw Error(str("Embree: rtcNewDevice failed (error ",
                        static_cast<int>(rtcGetDeviceError(nullptr)), ")"));
    }
    rtcSetDeviceErrorFunction(m->device, error_fn, &m->errors);
    m->scene = rtcNewScene(m->device);
    rtcSetSceneFlags(m->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m->scene, RTC_BUILD_QUALITY_HIGH);

    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (size_t i = 0; i < m->shapes.size(); ++i) {
        Shape& s = m->shapes[i];
        RTCGeometry geom = nullptr;
        if (s.kind == ShapeKind::kMesh) {
            if (!s.mesh || s.mesh->triangles.empty()) {
                throw Error(str("shape ", i, ": mesh without triangles"));
            }
            const TriangleMesh& mesh = *s.mesh;
            geom = m->new_buffered_geometry<3, 3>(
                RTC_GEOMETRY_TYPE_TRIANGLE, mesh.positions.size(), mesh.triangles.size(),
                [&mesh](size_t k) { return mesh.positions[k]; },
                [&mesh](size_t k, int c) { return static_cast<unsigned>(mesh.triangles[k][c]); },
                "mesh", lo, hi);
        } else if (s.kind == ShapeKind::kCurves) {
            if (!s.curves || s.curves->first.empty()) {
                throw Error(str("shape ", i, ": curves without segments"));
            }
            const CurveSet& c = *s.curves;
            // Each vertex is (x, y, z, radius); segment k uses control points first[k] .. + 3.
            geom = m->new_buffered_geometry<4, 1>(
                RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE, c.control_points.size(), c.first.size(),
                [&c](size_t k) { return Eigen::Vector4d(c.control_points[k].cast<double>()); },
                [&c](size_t k, int) {
                    INLIGHT_CHECK_LT(c.first[k] + 3, c.control_points.size());
                    return c.first[k];
                },
                "curve", lo, hi);
        } else if (s.kind == ShapeKind::kWeave) {
            throw Error(str("shape ", i, ": a weave must be turned into curves first (Scene)"));
        } else {
            if (s.kind == ShapeKind::kSphere && !(s.radius > 0)) {
                throw Error(str("shape ", i, ": sphere radius must be > 0, got ", s.radius));
            }
            if (s.kind == ShapeKind::kPatch && !(s.size.x() > 0 && s.size.y() > 0)) {
                throw Error(str("shape ", i, ": patch size must be > 0, got ", s.size.x(), "x",
                                s.size.y()));
            }
            geom = rtcNewGeometry(m->device, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(geom, 1);
            rtcSetGeometryUserData(geom, &s);
            rtcSetGeometryBoundsFunction(geom, bounds_fn, nullptr);
            rtcSetGeometryIntersectFunction(geom, intersect_fn);
            rtcSetGeometryOccludedFunction(geom, occluded_fn);
            const Eigen::Vector3d ext =
                s.kind == ShapeKind::kSphere
                    ? Eigen::Vector3d::Constant(s.radius)
                    : Eigen::Vector3d(0.5 * s.size.x(), 0.5 * s.size.y(), 0);
            lo = lo.cwiseMin(s.center - ext);
            hi = hi.cwiseMax(s.center + ext);
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(m->scene, geom, static_cast<unsigned>(i));
        rtcReleaseGeometry(geom);
        m->throw_if_error(str("building shape ", i));
    }
    rtcCommitScene(m->scene);
    m->throw_if_error("committing the scene");
    m->scale = m->shapes.empty() ? 1.0 : std::max(1e-6, (hi - lo).norm());
}

Accel::~Accel() = default;

const std::vector<Shape>& Accel::shapes() const { return m->shapes; }
double Accel::scene_scale() const { return m->scale; }

namespace {
RTCRay to_rtc(const Ray& ray) {
    RTCRay r;
    r.org_x = static_cast<float>(ray.origin.x());
    r.org_y = static_cast<float>(ray.origin.y());
    r.org_z = static_cast<float>(ray.origin.z());
    r.dir_x = static_cast<float>(ray.dir.x());
    r.dir_y = static_cast<float>(ray.dir.y());
    r.dir_z = static_cast<float>(ray.dir.z());
    r.tnear = 0.0f;
    r.tfar = std::isfinite(ray.t_max) ? static_cast<float>(ray.t_max)
                                      : std::numeric_limits<float>::infinity();
    r.time = 0;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
    return r;
}
}  // namespace

namespace {

/// Fills a curve hit: position, normals (the tube's, then the ply-twist relief), the tangent
/// along the curve and its colour.
void curve_hit(const CurveSet& c, const Ray& ray, double u, const Eigen::Vector3d& embree_ng,
               SurfaceHit* hit) {
    SurfaceHit& h = *hit;
    const auto seg = static_cast<size_t>(h.prim);
    const Eigen::Vector4d b = weave::bspline_basis(u), db = weave::bspline_basis_du(u);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), tangent = Eigen::Vector3d::Zero();
    double radius = 0;
    for (int j = 0; j < 4; ++j) {
        const Eigen::Vector4d q = c.control_points[c.first[seg] + static_cast<size_t>(j)].cast<double>();
        centre += b[j] * q.head<3>();
        tangent += db[j] * q.head<3>();
        radius += b[j] * q[3];
    }
    h.p = ray.origin + h.t * ray.dir;
    h.ng = embree_ng.squaredNorm() > 0 ? embree_ng.normalized() : (h.p - centre).normalized();
    if (!h.ng.allFinite()) h.ng = -ray.dir;
    const Eigen::Vector3d t_axis =
        tangent.squaredNorm() > 0 ? tangent.normalized() : any_tangent(h.ng);
    h.ns = h.ng;
    h.dpdu = t_axis;
    const double s = c.s_start[seg] + u * c.ds_du[seg];
    h.uv = {s, 0};
    h.has_albedo = true;
    h.albedo = c.albedo[seg].cast<double>();
    if (c.plies > 0 && c.depth > 0 && radius > 0) {
        // Azimuth psi around the axis from the axis-orthogonal direction nearest +z, so the
        // ridges' phase is a function of the surface point alone (continuous along the yarn).
        Eigen::Vector3d r = Eigen::Vector3d::UnitZ() - t_axis.z() * t_axis;
        r = r.squaredNorm() > 1e-12 ? r.normalized() : any_tangent(t_axis);
        const Eigen::Vector3d bb = t_axis.cross(r);
        const Eigen::Vector3d n = h.ng;
        const double psi = std::atan2(n.dot(bb), n.dot(r));
        // Ridges are the helices psi - s tan(angle) / radius = const; the relief
        // cos(plies * phase) tilts the normal across them (toward p_dir) by depth sin(...).
        const double phase = c.plies * (psi - s * std::tan(c.angle) / radius);
        const Eigen::Vector3d t_psi = t_axis.cross(n);
        const Eigen::Vector3d p_dir = std::cos(c.angle) * t_psi - std::sin(c.angle) * t_axis;
        const double delta = c.depth * std::sin(phase);
        const Eigen::Vector3d ns = std::cos(delta) * n - std::sin(delta) * p_dir;
        if (ns.dot(n) > 0) h.ns = ns.normalized();
    }
}

}  // namespace

bool Accel::intersect(const Ray& ray, SurfaceHit* hit) const {
    QueryContext ctx;
    rtcInitIntersectContext(&ctx.rtc);
    ctx.ray = &ray;
    RTCRayHit rh;
    rh.ray = to_rtc(ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m->scene, &ctx.rtc, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

    const Shape& s = m->shapes[rh.hit.geomID];
    SurfaceHit& h = *hit;
    h.shape = static_cast<int>(rh.hit.geomID);
    h.prim = static_cast<int>(rh.hit.primID);
    h.t = rh.ray.tfar;
    if (s.kind == ShapeKind::kPatch) {
        const double t = intersect_analytic(s, ray);  // the double t, not Embree's float copy
        h.t = t;
        h.p = ray.origin + t * ray.dir;
        h.p.z() = s.center.z();
        h.ng = h.ns = Eigen::Vector3d::UnitZ();
        h.dpdu = Eigen::Vector3d::UnitX();
        h.uv = {(h.p.x() - (s.center.x() - 0.5 * s.size.x())) / s.size.x(),
                ((s.center.y() + 0.5 * s.size.y()) - h.p.y()) / s.size.y()};
    } else if (s.kind == ShapeKind::kSphere) {
        const double t = intersect_analytic(s, ray);
        h.t = t;
        const Eigen::Vector3d n = (ray.origin + t * ray.dir - s.center).normalized();
        h.p = s.center + s.radius * n;
        h.ng = h.ns = n;
        h.uv = latlong_uv(n);
        const double phi = kPi * (1.0 - 2.0 * h.uv[0]);
        // d/du of the lat-long direction: phi decreases as u grows.
        const Eigen::Vector3d t_u(std::sin(phi), -std::cos(phi), 0.0);
        h.dpdu = t_u.squaredNorm() > 0 ? t_u : any_tangent(n);
    } else if (s.kind == ShapeKind::kCurves) {
        curve_hit(*s.curves, ray, rh.hit.u, Eigen::Vector3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z),
                  &h);
    } else {
        const TriangleMesh& mesh = *s.mesh;
        const Eigen::Vector3i tri = mesh.triangles[static_cast<size_t>(h.prim)];
        const Eigen::Vector3d& p0 = mesh.positions[static_cast<size_t>(tri[0])];
        const Eigen::Vector3d& p1 = mesh.positions[static_cast<size_t>(tri[1])];
        const Eigen::Vector3d& p2 = mesh.positions[static_cast<size_t>(tri[2])];
        const double b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0 - b1 - b2;
        h.p = b0 * p0 + b1 * p1 + b2 * p2;
        h.ng = (p1 - p0).cross(p2 - p0).normalized();
        h.ns = h.ng;
        if (!mesh.normals.empty()) {
            const Eigen::Vector3d n = b0 * mesh.normals[static_cast<size_t>(tri[0])] +
                                      b1 * mesh.normals[static_cast<size_t>(tri[1])] +
                                      b2 * mesh.normals[static_cast<size_t>(tri[2])];
            if (n.squaredNorm() > 0) {
                h.ns = n.normalized();
                if (h.ns.dot(h.ng) < 0) h.ng = -h.ng;  // the vertex normals define the outside
            }
        }
        h.dpdu = any_tangent(h.ns);
        h.uv = Eigen::Vector2d::Zero();
        if (!mesh.uvs.empty()) {
            const Eigen::Vector2d& t0 = mesh.uvs[static_cast<size_t>(tri[0])];
            const Eigen::Vector2d& t1 = mesh.uvs[static_cast<size_t>(tri[1])];
            const Eigen::Vector2d& t2 = mesh.uvs[static_cast<size_t>(tri[2])];
            h.uv = b0 * t0 + b1 * t1 + b2 * t2;
            const Eigen::Vector2d d1 = t1 - t0, d2 = t2 - t0;
            const double det = d1.x() * d2.y() - d1.y() * d2.x();
            if (std::abs(det) > 1e-20) {
                const Eigen::Vector3d dpdu = (d2.y() * (p1 - p0) - d1.y() * (p2 - p0)) / det;
                if (dpdu.squaredNorm() > 0) h.dpdu = dpdu;
            }
        }
    }
    // Tangent orthonormal to the shading normal (Gram-Schmidt), as the shading frame needs.
    Eigen::Vector3d tangent = h.dpdu - h.ns * h.ns.dot(h.dpdu);
    h.dpdu = tangent.squaredNorm() > 1e-24 ? tangent.normalized() : any_tangent(h.ns);
    return true;
}

bool Accel::occluded(const Ray& ray) const {
    QueryContext ctx;
    rtcInitIntersectContext(&ctx.rtc);
    ctx.ray = &ray;
    RTCRay r = to_rtc(ray);
    rtcOccluded1(m->scene, &ctx.rtc, &r);
    return r.tfar < 0;
}

}  // namespace inlight::render
