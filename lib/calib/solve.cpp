#include "calib/solve.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>
#include <optional>

#include "calib/bundle.h"
#include "core/check.h"
#include "core/error.h"
#include "core/log.h"

namespace inlight::calib {

namespace {

/// One solver run on a subset of the views.
struct Solution {
    CameraModel camera;
    std::vector<size_t> used;  ///< indices into the subset passed in
    std::vector<Eigen::Vector3d> rvecs, tvecs;
    std::vector<size_t> rejected;  ///< subset indices the solver itself refused (omnidir init)
    std::vector<std::string> rejected_reason;
    std::string solver = "opencv";
};

Eigen::Vector3d to_eigen(const cv::Vec3d& v) { return {v[0], v[1], v[2]}; }
Eigen::Vector3d to_eigen3(const cv::Mat& m) {
    cv::Mat d;
    m.convertTo(d, CV_64F);
    return {d.at<double>(0), d.at<double>(1), d.at<double>(2)};
}

Solution opencv_solve(const std::vector<const View*>& views, int width, int height,
                      const CalibrateOptions& opt) {
    Solution s;
    const cv::Size size(width, height);
    switch (opt.model) {
        case ModelType::kFisheye: {
            std::vector<std::vector<cv::Point3d>> op(views.size());
            std::vector<std::vector<cv::Point2d>> ip(views.size());
            for (size_t v = 0; v < views.size(); ++v) {
                for (const auto& p : views[v]->object_points)
                    op[v].emplace_back(p.x(), p.y(), p.z());
                for (const auto& p : views[v]->image_points) ip[v].emplace_back(p.x(), p.y());
            }
            cv::Matx33d k = cv::Matx33d::eye();
            cv::Vec4d d;
            std::vector<cv::Vec3d> rv, tv;
            int flags = cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC;
            if (opt.fix_skew) flags |= cv::fisheye::CALIB_FIX_SKEW;
            // OpenCV's default termination (100 iterations, machine epsilon), as ROS uses; with
            // the joint LM finishing, 30 iterations are enough to start it (4x faster).
            cv::fisheye::calibrate(
                op, ip, size, k, d, rv, tv, flags,
                cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS,
                                 opt.polish ? 30 : 100, std::numeric_limits<double>::epsilon()));
            s.camera = CameraModel::make(ModelType::kFisheye, width, height, k(0, 0), k(1, 1),
                                         k(0, 2), k(1, 2));
            s.camera.skew = k(0, 1);
            s.camera.distortion = {d[0], d[1], d[2], d[3]};
            for (size_t v = 0; v < views.size(); ++v) {
                s.used.push_back(v);
                s.rvecs.push_back(to_eigen(rv[v]));
                s.tvecs.push_back(to_eigen(tv[v]));
            }
            break;
        }
        case ModelType::kPinhole: {
            std::vector<std::vector<cv::Point3f>> op(views.size());
            std::vector<std::vector<cv::Point2f>> ip(views.size());
            for (size_t v = 0; v < views.size(); ++v) {
                for (const auto& p : views[v]->object_points) {
                    op[v].emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                       static_cast<float>(p.z()));
                }
                for (const auto& p : views[v]->image_points) {
                    ip[v].emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
                }
            }
            cv::Mat k = cv::Mat::eye(3, 3, CV_64F), d;
            std::vector<cv::Mat> rv, tv;
            int flags = 0;
            if (opt.fix_aspect_ratio) flags |= cv::CALIB_FIX_ASPECT_RATIO;
            if (!opt.pinhole_k3) flags |= cv::CALIB_FIX_K3;
            cv::calibrateCamera(op, ip, size, k, d, rv, tv, flags,
                                cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS,
                                                 100, std::numeric_limits<double>::epsilon()));
            s.camera =
                CameraModel::make(ModelType::kPinhole, width, height, k.at<double>(0, 0),
                                  k.at<double>(1, 1), k.at<double>(0, 2), k.at<double>(1, 2));
            for (int i = 0; i < 5; ++i) s.camera.distortion[i] = d.at<double>(i);
            for (size_t v = 0; v < views.size(); ++v) {
                s.used.push_back(v);
                s.rvecs.push_back(to_eigen3(rv[v]));
                s.tvecs.push_back(to_eigen3(tv[v]));
            }
            break;
        }
        case ModelType::kOmnidir: {
            std::vector<cv::Mat> op, ip;
            for (const View* v : views) {
                cv::Mat o(1, static_cast<int>(v->object_points.size()), CV_64FC3);
                cv::Mat i(1, static_cast<int>(v->image_points.size()), CV_64FC2);
                for (int j = 0; j < o.cols; ++j) {
                    const auto& p = v->object_points[static_cast<size_t>(j)];
                    o.at<cv::Vec3d>(0, j) = cv::Vec3d(p.x(), p.y(), p.z());
                }
                for (int j = 0; j < i.cols; ++j) {
                    const auto& p = v->image_points[static_cast<size_t>(j)];
                    i.at<cv::Vec2d>(0, j) = cv::Vec2d(p.x(), p.y());
                }
                op.push_back(o);
                ip.push_back(i);
            }
            cv::Mat k, d, xi, idx;
            std::vector<cv::Mat> rv, tv;
            const int flags = opt.fix_skew ? cv::omnidir::CALIB_FIX_SKEW : 0;
            cv::omnidir::calibrate(
                op, ip, size, k, xi, d, rv, tv, flags,
                cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 300, 1e-10), idx);
            s.camera =
                CameraModel::make(ModelType::kOmnidir, width, height, k.at<double>(0, 0),
                                  k.at<double>(1, 1), k.at<double>(0, 2), k.at<double>(1, 2));
            s.camera.skew = k.at<double>(0, 1);
            s.camera.xi = xi.at<double>(0);
            for (int i = 0; i < 4; ++i) s.camera.distortion[i] = d.at<double>(i);
            std::vector<bool> in(views.size(), false);
            cv::Mat idx_int;
            idx.convertTo(idx_int, CV_32S);
            for (int j = 0; j < static_cast<int>(idx_int.total()); ++j) {
                const size_t v = static_cast<size_t>(idx_int.at<int>(j));
                in[v] = true;
                s.used.push_back(v);
                s.rvecs.push_back(to_eigen3(rv[static_cast<size_t>(j)]));
                s.tvecs.push_back(to_eigen3(tv[static_cast<size_t>(j)]));
            }
            for (size_t v = 0; v < views.size(); ++v) {
                if (!in[v]) {
                    s.rejected.push_back(v);
                    s.rejected_reason.push_back(
                        "the omnidir solver could not initialise this view");
                }
            }
            break;
        }
    }
    return s;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Largest distance of a view's corners from the image centre, pixels.
double eccentricity(const View& v, int width, int height) {
    double e = 0;
    for (const auto& p : v.image_points) {
        e = std::max(e, (p - Eigen::Vector2d(0.5 * (width - 1), 0.5 * (height - 1))).norm());
    }
    return e;
}

/// The fisheye fallback: OpenCV on the most central views (a third of them, at least 3,
/// shrinking while it fails), then every other view posed under those intrinsics; the joint
/// refinement (by the caller) finishes.
Solution fisheye_fallback(const std::vector<const View*>& views, int width, int height,
                          const CalibrateOptions& opt, const std::string& first_error) {
    std::vector<size_t> order(views.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return eccentricity(*views[a], width, height) < eccentricity(*views[b], width, height);
    });
    std::optional<Solution> best;
    std::vector<size_t> subset;
    for (size_t n = std::max<size_t>(3, views.size() / 3); n >= 3 && !best; --n) {
        subset.assign(order.begin(),
                      order.begin() + static_cast<ptrdiff_t>(std::min(n, order.size())));
        std::vector<const View*> vs;
        for (size_t j : subset) vs.push_back(views[j]);
        try {
            best = opencv_solve(vs, width, height, opt);
        } catch (const cv::Exception&) {
        }
    }
    if (!best) {
        throw Error(
            str("fisheye calibration failed: OpenCV's solver fails even on the three "
                "most central views (",
                first_error, ")"));
    }
    Solution s;
    s.camera = best->camera;
    s.solver = "opencv-subset+bundle";
    log::verbose(str("fisheye fallback: OpenCV solved the ", subset.size(), " most central of ",
                     log::count(int64_t(views.size()), "view"), " (", first_error, ")"));
    for (size_t v = 0; v < views.size(); ++v) {
        const auto it = std::find(subset.begin(), subset.end(), v);
        if (it != subset.end()) {
            const size_t k = static_cast<size_t>(it - subset.begin());
            s.used.push_back(v);
            s.rvecs.push_back(best->rvecs[k]);
            s.tvecs.push_back(best->tvecs[k]);
            continue;
        }
        const auto pose = estimate_pose(s.camera, *views[v]);
        if (pose) {
            s.used.push_back(v);
            s.rvecs.push_back(pose->rvec);
            s.tvecs.push_back(pose->tvec);
        } else {
            s.rejected.push_back(v);
            s.rejected_reason.push_back(
                "its pose could not be estimated under the intrinsics of "
                "the other views");
        }
    }
    return s;
}

FreeParameters free_parameters(const CameraModel& cam, const CalibrateOptions& opt);

Solution solve_once(const std::vector<const View*>& views, int width, int height,
                    const CalibrateOptions& opt) {
    Solution s;
    try {
        s = opencv_solve(views, width, height, opt);
    } catch (const cv::Exception& e) {
        if (opt.model != ModelType::kFisheye) {
            throw Error(str(to_string(opt.model), " calibration failed in OpenCV: ", e.err));
        }
        s = fisheye_fallback(views, width, height, opt, e.err);
    }
    // OpenCV's solvers can return a wrong pose for a view while the intrinsics are right (seen
    // with cv::fisheye on boards near 90 degrees): where our own pose estimate under the same
    // intrinsics fits better, it replaces OpenCV's.
    for (size_t j = 0; j < s.used.size(); ++j) {
        const View& v = *views[s.used[j]];
        const double rms = view_error(s.camera, v, s.rvecs[j], s.tvecs[j]).rms_px;
        const auto pose = estimate_pose(s.camera, v);
        if (pose && view_error(s.camera, v, pose->rvec, pose->tvec).rms_px < rms) {
            s.rvecs[j] = pose->rvec;
            s.tvecs[j] = pose->tvec;
        }
    }
    const bool must_bundle = s.solver != "opencv";
    if ((opt.polish || must_bundle) && !s.used.empty()) {
        std::vector<View> used;
        std::vector<Pose> poses;
        for (size_t j = 0; j < s.used.size(); ++j) {
            used.push_back(*views[s.used[j]]);
            poses.push_back({s.rvecs[j], s.tvecs[j]});
        }
        const FreeParameters free = free_parameters(s.camera, opt);
        // A view that started from a wrong pose (a planar-pose ambiguity under poor first
        // intrinsics) stays in its local minimum: re-pose such views under the refined
        // intrinsics and refine again.
        for (int round = 0; round < 3; ++round) {
            bundle_adjust(s.camera, free, used, poses);
            std::vector<double> rms;
            for (size_t j = 0; j < used.size(); ++j) {
                rms.push_back(view_error(s.camera, used[j], poses[j].rvec, poses[j].tvec).rms_px);
            }
            const double limit = std::max(3 * median(rms), opt.outlier_min_px);
            bool changed = false;
            for (size_t j = 0; j < used.size(); ++j) {
                if (rms[j] <= limit) continue;
                const auto pose = estimate_pose(s.camera, used[j]);
                if (pose && view_error(s.camera, used[j], pose->rvec, pose->tvec).rms_px < rms[j]) {
                    poses[j] = *pose;
                    changed = true;
                }
            }
            if (!changed) break;
        }
        for (size_t j = 0; j < poses.size(); ++j) {
            s.rvecs[j] = poses[j].rvec;
            s.tvecs[j] = poses[j].tvec;
        }
        if (!must_bundle) s.solver = "opencv+polish";
    }
    return s;
}

FreeParameters free_parameters(const CameraModel& cam, const CalibrateOptions& opt) {
    const auto names = cam.parameter_names();
    FreeParameters free;
    free.fixed.assign(names.size(), false);
    for (size_t i = 0; i < names.size(); ++i) {
        const std::string& n = names[i];
        if (n == "skew") free.fixed[i] = opt.fix_skew || cam.type == ModelType::kPinhole;
        if (n == "k3" && cam.type == ModelType::kPinhole) free.fixed[i] = !opt.pinhole_k3;
    }
    if (cam.type == ModelType::kPinhole && opt.fix_aspect_ratio) {
        free.fixed[0] = true;  // fx follows fy
        free.fx_follows_fy = true;
    }
    return free;
}

}  // namespace

ViewError view_error(const CameraModel& camera, const View& view, const Eigen::Vector3d& rvec,
                     const Eigen::Vector3d& tvec) {
    ViewError e;
    e.name = view.name;
    e.points = static_cast<int>(view.image_points.size());
    e.rvec = rvec;
    e.tvec = tvec;
    std::vector<double> r(2 * view.image_points.size());
    if (!view_residuals(camera, view, Pose{rvec, tvec}, r.data())) {
        e.rms_px = e.max_error_px = std::numeric_limits<double>::infinity();
        return e;
    }
    double sum = 0;
    for (size_t i = 0; i < view.image_points.size(); ++i) {
        const double sq = r[2 * i] * r[2 * i] + r[2 * i + 1] * r[2 * i + 1];
        sum += sq;
        e.max_error_px = std::max(e.max_error_px, std::sqrt(sq));
    }
    e.rms_px = std::sqrt(sum / std::max<size_t>(1, view.image_points.size()));
    return e;
}

Calibration calibrate(const std::vector<View>& views, int width, int height,
                      const CalibrateOptions& opt) {
    INLIGHT_CHECK(width > 0 && height > 0) << "image size not set";
    std::vector<size_t> active(views.size());
    for (size_t i = 0; i < views.size(); ++i) active[i] = i;
    Calibration cal;
    std::vector<size_t> final_idx;  // indices into `views` of cal.views

    auto fail_if_too_few = [&]() {
        if (static_cast<int>(active.size()) >= opt.min_views) return;
        std::string msg = str("only ", active.size(), " usable view", active.size() == 1 ? "" : "s",
                              ", need at least ", opt.min_views);
        for (const DroppedView& d : cal.dropped) msg += str("; ", d.name, ": ", d.reason);
        throw Error(msg);
    };

    for (;;) {
        fail_if_too_few();
        std::vector<const View*> subset;
        for (size_t i : active) subset.push_back(&views[i]);
        const Solution s = solve_once(subset, width, height, opt);
        ++cal.rounds;
        if (!s.rejected.empty()) {
            std::vector<size_t> keep;
            for (size_t j = 0; j < subset.size(); ++j) {
                const auto it = std::find(s.rejected.begin(), s.rejected.end(), j);
                if (it != s.rejected.end()) {
                    cal.dropped.push_back(
                        {subset[j]->name,
                         s.rejected_reason[static_cast<size_t>(it - s.rejected.begin())]});
                } else {
                    keep.push_back(active[j]);
                }
            }
            active = keep;
            continue;
        }
        cal.camera = s.camera;
        cal.solver = s.solver;
        cal.views.clear();
        final_idx.clear();
        for (size_t j = 0; j < s.used.size(); ++j) {
            cal.views.push_back(view_error(s.camera, *subset[s.used[j]], s.rvecs[j], s.tvecs[j]));
            final_idx.push_back(active[s.used[j]]);
        }
        if (opt.outlier_factor > 0 && cal.views.size() > 1) {
            std::vector<double> rms;
            for (const ViewError& e : cal.views) rms.push_back(e.rms_px);
            const double med = median(rms);
            const size_t worst =
                static_cast<size_t>(std::max_element(rms.begin(), rms.end()) - rms.begin());
            const double limit = std::max(opt.outlier_factor * med, opt.outlier_min_px);
            if (rms[worst] > limit) {
                cal.dropped.push_back({cal.views[worst].name,
                                       str("reprojection outlier: RMS ", rms[worst], " px > ",
                                           limit, " px (max of ", opt.outlier_factor, " x median ",
                                           med, " px and ", opt.outlier_min_px, " px)")});
                active.erase(active.begin() + static_cast<ptrdiff_t>(s.used[worst]));
                continue;
            }
        }
        break;
    }

    // Quality figures on the final set.
    std::vector<View> used;
    double sum = 0;
    size_t n = 0;
    for (const ViewError& e : cal.views) {
        sum += e.rms_px * e.rms_px * e.points;
        n += static_cast<size_t>(e.points);
    }
    cal.rms_px = std::sqrt(sum / std::max<size_t>(1, n));
    for (size_t i : final_idx) used.push_back(views[i]);
    cal.view_index = final_idx;
    for (size_t v = 0; v < used.size(); ++v) {
        const Eigen::Matrix3d r = rotation_from_rodrigues(cal.views[v].rvec);
        for (const auto& p : used[v].object_points) {
            const Eigen::Vector3d q = r * p + cal.views[v].tvec;
            cal.max_observed_theta =
                std::max(cal.max_observed_theta, std::atan2(std::hypot(q.x(), q.y()), q.z()));
        }
    }
    cal.parameter_names = cal.camera.parameter_names();
    const FreeParameters free = free_parameters(cal.camera, opt);
    cal.fixed = free.fixed;
    std::vector<Pose> poses;
    for (const ViewError& e : cal.views) poses.push_back({e.rvec, e.tvec});
    cal.std_dev = intrinsic_std_dev(cal.camera, free, used, poses);
    return cal;
}

}  // namespace inlight::calib
