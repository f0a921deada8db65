#include "calib/bundle.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>

#include "core/check.h"
#include "core/error.h"

namespace inlight::calib {

namespace {

/// The parameter layout of one problem: free intrinsics first, then 6 per view.
struct Layout {
    std::vector<int> free;  ///< indices into camera.parameters()
    bool fx_follows_fy = false;
    double aspect = 1;        ///< fx / fy at the start
    std::vector<int> offset;  ///< residual offset per view (size views + 1)
    int rows = 0;
    int nf = 0;
    int cols = 0;
};

Layout make_layout(const CameraModel& camera, const FreeParameters& free,
                   const std::vector<View>& views) {
    Layout l;
    const int np = static_cast<int>(camera.parameter_names().size());
    INLIGHT_CHECK_EQ(static_cast<int>(free.fixed.size()), np);
    for (int i = 0; i < np; ++i) {
        if (!free.fixed[static_cast<size_t>(i)]) l.free.push_back(i);
    }
    l.fx_follows_fy = free.fx_follows_fy;
    l.aspect = camera.fx / camera.fy;
    l.offset.assign(views.size() + 1, 0);
    for (size_t v = 0; v < views.size(); ++v) {
        INLIGHT_CHECK_EQ(views[v].image_points.size(), views[v].object_points.size());
        l.offset[v + 1] = l.offset[v] + 2 * static_cast<int>(views[v].image_points.size());
    }
    l.rows = l.offset.back();
    l.nf = static_cast<int>(l.free.size());
    l.cols = l.nf + 6 * static_cast<int>(views.size());
    return l;
}

CameraModel with_intrinsics(const CameraModel& camera, const Layout& l,
                            const Eigen::VectorXd& delta) {
    Eigen::VectorXd p = camera.parameters();
    for (int j = 0; j < l.nf; ++j) p[l.free[static_cast<size_t>(j)]] += delta[j];
    if (l.fx_follows_fy) p[0] = l.aspect * p[1];
    CameraModel c = camera;
    c.set_parameters(p);
    return c;
}

bool all_residuals(const CameraModel& camera, const std::vector<View>& views,
                   const std::vector<Pose>& poses, const Layout& l, Eigen::VectorXd& r) {
    r.resize(l.rows);
    for (size_t v = 0; v < views.size(); ++v) {
        if (!view_residuals(camera, views[v], poses[v], r.data() + l.offset[v])) return false;
    }
    return true;
}

/// Central-difference Jacobian: intrinsic block (rows x nf) and one 2n x 6 block per view.
struct Jacobian {
    Eigen::MatrixXd intrinsic;
    std::vector<Eigen::MatrixXd> pose;
};

Jacobian jacobian(const CameraModel& camera, const std::vector<View>& views,
                  const std::vector<Pose>& poses, const Layout& l) {
    Jacobian jac;
    jac.intrinsic.resize(l.rows, l.nf);
    Eigen::VectorXd plus, minus;
    const Eigen::VectorXd p0 = camera.parameters();
    for (int j = 0; j < l.nf; ++j) {
        const double h = 1e-6 * std::max(1.0, std::abs(p0[l.free[static_cast<size_t>(j)]]));
        Eigen::VectorXd d = Eigen::VectorXd::Zero(l.nf);
        d[j] = h;
        const bool ok_p = all_residuals(with_intrinsics(camera, l, d), views, poses, l, plus);
        const bool ok_m = all_residuals(with_intrinsics(camera, l, -d), views, poses, l, minus);
        jac.intrinsic.col(j) = ok_p && ok_m ? Eigen::VectorXd((plus - minus) / (2 * h))
                                            : Eigen::VectorXd::Zero(l.rows);
    }
    jac.pose.resize(views.size());
    for (size_t v = 0; v < views.size(); ++v) {
        const int n = l.offset[v + 1] - l.offset[v];
        Eigen::MatrixXd& b = jac.pose[v];
        b.resize(n, 6);
        Eigen::VectorXd rp(n), rm(n);
        for (int k = 0; k < 6; ++k) {
            const double h = k < 3 ? 1e-7 : 1e-6 * std::max(1.0, poses[v].tvec.norm());
            Pose pp = poses[v], pm = poses[v];
            if (k < 3) {
                pp.rvec[k] += h;
                pm.rvec[k] -= h;
            } else {
                pp.tvec[k - 3] += h;
                pm.tvec[k - 3] -= h;
            }
            const bool ok = view_residuals(camera, views[v], pp, rp.data()) &&
                            view_residuals(camera, views[v], pm, rm.data());
            b.col(k) = ok ? Eigen::VectorXd((rp - rm) / (2 * h)) : Eigen::VectorXd::Zero(n);
        }
    }
    return jac;
}

/// Normal matrix J^T J and gradient J^T r, exploiting the block structure.
void normal_equations(const Jacobian& jac, const Eigen::VectorXd& r, const Layout& l,
                      Eigen::MatrixXd& n, Eigen::VectorXd& g) {
    n = Eigen::MatrixXd::Zero(l.cols, l.cols);
    g = Eigen::VectorXd::Zero(l.cols);
    n.topLeftCorner(l.nf, l.nf) = jac.intrinsic.transpose() * jac.intrinsic;
    g.head(l.nf) = jac.intrinsic.transpose() * r;
    for (size_t v = 0; v < jac.pose.size(); ++v) {
        const int o = l.offset[v], rows = l.offset[v + 1] - l.offset[v];
        const int c = l.nf + 6 * static_cast<int>(v);
        const auto ji = jac.intrinsic.middleRows(o, rows);
        const Eigen::MatrixXd b = ji.transpose() * jac.pose[v];
        n.block(0, c, l.nf, 6) = b;
        n.block(c, 0, 6, l.nf) = b.transpose();
        n.block(c, c, 6, 6) = jac.pose[v].transpose() * jac.pose[v];
        g.segment(c, 6) = jac.pose[v].transpose() * r.segment(o, rows);
    }
}

}  // namespace

bool view_residuals(const CameraModel& camera, const View& view, const Pose& pose, double* out) {
    const Eigen::Matrix3d rot = rotation_from_rodrigues(pose.rvec);
    for (size_t i = 0; i < view.object_points.size(); ++i) {
        const auto px = camera.project(rot * view.object_points[i] + pose.tvec);
        if (!px) return false;
        out[2 * i] = px->x() - view.image_points[i].x();
        out[2 * i + 1] = px->y() - view.image_points[i].y();
    }
    return true;
}

BundleResult bundle_adjust(CameraModel& camera, const FreeParameters& free,
                           const std::vector<View>& views, std::vector<Pose>& poses,
                           int max_iterations) {
    INLIGHT_CHECK_EQ(views.size(), poses.size());
    const Layout l = make_layout(camera, free, views);
    BundleResult result;
    Eigen::VectorXd r;
    for (size_t v = 0; v < views.size(); ++v) {
        std::vector<double> tmp(2 * views[v].image_points.size());
        if (!view_residuals(camera, views[v], poses[v], tmp.data())) {
            throw Error(str(views[v].name, ": board does not project under the start values"));
        }
    }
    all_residuals(camera, views, poses, l, r);
    double cost = r.squaredNorm();
    const double points = std::max(1, l.rows / 2);
    result.initial_rms_px = std::sqrt(cost / points);
    double lambda = 1e-3;
    for (int it = 0; it < max_iterations; ++it) {
        const Jacobian jac = jacobian(camera, views, poses, l);
        Eigen::MatrixXd n;
        Eigen::VectorXd g;
        normal_equations(jac, r, l, n, g);
        bool accepted = false;
        double new_cost = cost;
        while (lambda < 1e12) {
            Eigen::MatrixXd damped = n;
            for (int i = 0; i < l.cols; ++i) damped(i, i) += lambda * std::max(n(i, i), 1e-12);
            const Eigen::VectorXd delta = damped.ldlt().solve(-g);
            if (!delta.allFinite()) {
                lambda *= 10;
                continue;
            }
            const CameraModel trial_cam = with_intrinsics(camera, l, delta.head(l.nf));
            std::vector<Pose> trial_poses = poses;
            for (size_t v = 0; v < poses.size(); ++v) {
                const int c = l.nf + 6 * static_cast<int>(v);
                trial_poses[v].rvec += delta.segment<3>(c);
                trial_poses[v].tvec += delta.segment<3>(c + 3);
            }
            Eigen::VectorXd trial_r;
            if (all_residuals(trial_cam, views, trial_poses, l, trial_r) &&
                trial_r.squaredNorm() < cost) {
                camera = trial_cam;
                poses = std::move(trial_poses);
                r = std::move(trial_r);
                new_cost = r.squaredNorm();
                lambda = std::max(lambda * 0.1, 1e-12);
                accepted = true;
                break;
            }
            lambda *= 10;
        }
        result.iterations = it + 1;
        if (!accepted) break;
        const double gain = (cost - new_cost) / std::max(cost, 1e-300);
        cost = new_cost;
        if (gain < 1e-12) break;
    }
    result.final_rms_px = std::sqrt(cost / points);
    return result;
}

Eigen::VectorXd intrinsic_std_dev(const CameraModel& camera, const FreeParameters& free,
                                  const std::vector<View>& views, const std::vector<Pose>& poses) {
    INLIGHT_CHECK_EQ(views.size(), poses.size());
    const Layout l = make_layout(camera, free, views);
    Eigen::VectorXd r;
    Eigen::VectorXd std_dev = Eigen::VectorXd::Zero(camera.parameters().size());
    if (!all_residuals(camera, views, poses, l, r)) return std_dev;
    const Jacobian jac = jacobian(camera, views, poses, l);
    Eigen::MatrixXd n;
    Eigen::VectorXd g;
    normal_equations(jac, r, l, n, g);
    const double sigma2 = r.squaredNorm() / std::max(1, l.rows - l.cols);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(n);
    for (int j = 0; j < l.nf; ++j) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(l.cols);
        e[j] = 1;
        const double var = ldlt.solve(e)[j] * sigma2;
        std_dev[l.free[static_cast<size_t>(j)]] = var > 0 ? std::sqrt(var) : 0.0;
    }
    if (l.fx_follows_fy) std_dev[0] = l.aspect * std_dev[1];
    return std_dev;
}

namespace {

/// Planar (or general) PnP on the rays of the corners that `camera` unprojects, in a virtual
/// camera looking along their mean. std::nullopt with fewer than 6 such corners.
std::optional<Pose> pose_from_rays(const CameraModel& camera, const View& view) {
    const Unprojector unproject(camera);
    std::vector<Eigen::Vector3d> rays;
    std::vector<size_t> which;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < view.image_points.size(); ++i) {
        const auto ray = unproject(view.image_points[i]);
        if (!ray) continue;
        rays.push_back(*ray);
        which.push_back(i);
        mean += *ray;
    }
    if (rays.size() < 6 || mean.norm() < 1e-9) return std::nullopt;
    // virtual_from_camera turns the mean ray onto +z.
    const Eigen::Matrix3d virtual_from_camera =
        Eigen::Quaterniond::FromTwoVectors(mean.normalized(), Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    std::vector<cv::Point2d> img;
    std::vector<cv::Point3d> obj;
    bool planar = true;
    for (size_t k = 0; k < rays.size(); ++k) {
        const Eigen::Vector3d q = virtual_from_camera * rays[k];
        if (q.z() < 0.05) continue;  // beyond ~87 degrees from the mean ray
        img.emplace_back(q.x() / q.z(), q.y() / q.z());
        const auto& o = view.object_points[which[k]];
        obj.emplace_back(o.x(), o.y(), o.z());
        planar = planar && std::abs(o.z()) < 1e-12;
    }
    if (img.size() < 6) return std::nullopt;
    cv::Mat rvec, tvec;
    bool ok = false;
    try {
        ok = cv::solvePnP(obj, img, cv::Mat::eye(3, 3, CV_64F), cv::Mat(), rvec, tvec, false,
                          planar ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_SQPNP);
    } catch (const cv::Exception&) {
        ok = false;
    }
    if (!ok) return std::nullopt;
    const Eigen::Vector3d rv(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
    const Eigen::Vector3d tv(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    Pose pose;
    pose.rvec =
        rodrigues_from_rotation(virtual_from_camera.transpose() * rotation_from_rodrigues(rv));
    pose.tvec = virtual_from_camera.transpose() * tv;
    return pose;
}

}  // namespace

std::optional<Pose> estimate_pose(const CameraModel& camera, const View& view) {
    // Under poor intrinsics some corners may lie outside the model's one-to-one domain; the
    // same camera without distortion unprojects everything and is close enough to start from.
    std::optional<Pose> pose = pose_from_rays(camera, view);
    if (!pose) {
        CameraModel plain = camera;
        std::fill(plain.distortion.begin(), plain.distortion.end(), 0.0);
        pose = pose_from_rays(plain, view);
    }
    if (!pose) return std::nullopt;
    std::vector<double> tmp(2 * view.image_points.size());
    if (!view_residuals(camera, view, *pose, tmp.data())) return std::nullopt;
    // Refine the pose alone on the pixel residuals.
    FreeParameters none;
    none.fixed.assign(camera.parameter_names().size(), true);
    CameraModel cam = camera;
    std::vector<View> one = {view};
    std::vector<Pose> poses = {*pose};
    bundle_adjust(cam, none, one, poses, 50);
    return poses[0];
}

}  // namespace inlight::calib
