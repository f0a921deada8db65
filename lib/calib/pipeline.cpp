#include "calib/pipeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "calib/camera_yaml.h"
#include "calib/corner_file.h"
#include "calib/detect.h"
#include "calib/refine.h"
#include "calib/response.h"
#include "core/app.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/json_out.h"
#include "core/log.h"
#include "core/number.h"
#include "core/parallel.h"

namespace inlight::calib {

namespace {

constexpr double kDeg = 180.0 / kPi;
/// Warn when the mask reaches this much beyond the largest observed corner angle: the model is
/// extrapolated there.
constexpr double kExtrapolationWarnDeg = 5.0;

Eigen::Vector2i parse_size(const std::string& spec, const std::string& flag) {
    const auto sizes = parse_sizes(spec, flag);
    if (sizes.size() != 1) throw UsageError(str(flag, " '", spec, "': expected one WxH, e.g. 1280x800"));
    return sizes[0];
}

}  // namespace

ImageCircle parse_image_circle(const std::string& spec) {
    const std::string context = str("--image-circle '", spec, "'");
    const std::vector<std::string> items = split(spec, ',');
    if (items.size() != 3) throw UsageError(str(context, ": expected auto, none or CX,CY,R (pixels)"));
    ImageCircle c;
    c.cx = parse_finite(items[0], context);
    c.cy = parse_finite(items[1], context);
    c.radius_px = parse_finite(items[2], context);
    if (!(c.radius_px > 0)) throw UsageError(str(context, ": the radius must be > 0"));
    return c;
}

namespace {

nlohmann::json matrix_json(const Eigen::Matrix3d& m) {
    nlohmann::json a = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) a.push_back({m(r, 0), m(r, 1), m(r, 2)});
    return a;
}

std::string list_dropped(const std::vector<DroppedView>& dropped) {
    std::string s;
    for (const DroppedView& d : dropped) s += str("; ", d.name, ": ", d.reason);
    return s;
}

/// calibrate() with the views dropped before it named in its error.
Calibration calibrate_views(const std::vector<View>& views, int w, int h,
                            const CalibrateOptions& co, const std::vector<DroppedView>& before) {
    try {
        return calibrate(views, w, h, co);
    } catch (const app::QualityGateFailed&) {
        throw;
    } catch (const Error& e) {
        throw Error(str(e.what(), list_dropped(before)));
    }
}

double largest_theta(const DirectionMaps& maps, const Eigen::Vector3d& axis) {
    double t = 0;
    for (size_t i = 0; i < maps.mask.pixel_count(); ++i) {
        if (!(maps.mask.pixels[i] > 0)) continue;
        const Eigen::Vector3d d(maps.directions.pixels[3 * i], maps.directions.pixels[3 * i + 1],
                                maps.directions.pixels[3 * i + 2]);
        t = std::max(t, std::acos(std::clamp(d.dot(axis), -1.0, 1.0)));
    }
    return t;
}

/// The console summary (docs/calibrate.md, "Console summary"): RMS, K, distortion and views at
/// the default verbosity, each view's RMS with -v.
void print_summary(const Calibration& cal, size_t dropped, double fov_theta) {
    const CameraModel& c = cal.camera;
    const std::string tool = "calibrate";
    log::summary(tool, "RMS reprojection error", str(log::num(cal.rms_px, 4), " px over ",
                                                     log::count(int64_t(cal.views.size()), "view"),
                                                     " (", dropped, " dropped)"));
    log::summary(tool, "camera matrix K (px)",
                 str("[", log::num(c.fx, 6), ", ", log::num(c.skew, 6), ", ", log::num(c.cx, 6),
                     "; 0, ", log::num(c.fy, 6), ", ", log::num(c.cy, 6), "; 0, 0, 1]"));
    std::string d;
    for (size_t i = 0; i < c.distortion.size(); ++i)
        d += str(i ? ", " : "", log::num(c.distortion[i], 6));
    log::summary(tool, str("distortion (", to_string(c.type), ")"),
                 str(c.type == ModelType::kOmnidir ? str("xi ", log::num(c.xi, 6), ", ") : "", "[", d,
                     "]"));
    log::summary(tool, "field of view", str(log::num(2 * fov_theta * kDeg, 4), " deg"));
    for (const ViewError& e : cal.views)
        log::verbose(str("calibrate: view ", e.name, ": RMS ", log::num(e.rms_px, 4), " px, max ",
                         log::num(e.max_error_px, 4), " px over ", e.points, " points"));
}

/// Everything calibration.json states (see docs/calibrate.md for the contract).
nlohmann::json calibration_json(
    const GeometryOptions& o, const CalibrateOptions& co, const BoardSpec& board,
    const Calibration& cal, const std::vector<DroppedView>& dropped, int width, int height,
    int passes, const ImageCircle& circle, const std::string& circle_source,
    const Eigen::Matrix3d& device_from_camera, double fov_theta, const DirectionMaps& full,
    const std::vector<Eigen::Vector2i>& sizes, const std::vector<DirectionMaps>& small) {
    const bool from_images = !o.inputs.empty();
    const CameraModel& cam = cal.camera;
    nlohmann::json j;
    j["format"] = "inlight_calibration";
    j["version"] = 1;
    j["model"] = to_string(cam.type);
    j["image_width"] = width;
    j["image_height"] = height;
    j["pixel_convention"] =
        "opencv: the centre of the top-left pixel is (0, 0); add 0.5 for "
        "inlight's convention";
    nlohmann::json intr = nlohmann::json::object(), sd = nlohmann::json::object();
    nlohmann::json fixed = nlohmann::json::array();
    const Eigen::VectorXd params = cam.parameters();
    for (size_t i = 0; i < cal.parameter_names.size(); ++i) {
        const std::string& n = cal.parameter_names[i];
        intr[n] = params[static_cast<int>(i)];
        if (cal.fixed[i] && !(n == "fx" && co.fix_aspect_ratio)) {
            sd[n] = nullptr;
            fixed.push_back(n);
        } else {
            sd[n] = cal.std_dev[static_cast<int>(i)];
        }
    }
    j["intrinsics"] = intr;
    j["intrinsics_std"] = sd;
    j["fixed_parameters"] = fixed;
    Eigen::Matrix3d k;
    k << cam.fx, cam.skew, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1;
    j["camera_matrix"] = matrix_json(k);
    j["distortion_coefficients"] = cam.distortion;
    j["reproj_rms_px"] = cal.rms_px;
    nlohmann::json jv = nlohmann::json::array();
    for (const ViewError& e : cal.views) {
        jv.push_back({{"file", e.name},
                      {"points", e.points},
                      {"reproj_rms_px", e.rms_px},
                      {"max_error_px", e.max_error_px},
                      {"rvec", {e.rvec.x(), e.rvec.y(), e.rvec.z()}},
                      {"tvec_m", {e.tvec.x(), e.tvec.y(), e.tvec.z()}}});
    }
    j["views"] = jv;
    nlohmann::json jd = nlohmann::json::array();
    for (const DroppedView& d : dropped) jd.push_back({{"file", d.name}, {"reason", d.reason}});
    j["dropped_views"] = jd;
    j["views_used"] = cal.views.size();
    j["views_dropped"] = dropped.size();
    j["solver"] = cal.solver;
    j["detector"] = from_images ? o.detector : "corner_file";
    j["refine_iterations"] = passes;
    j["board"] = o.board.empty() ? nlohmann::json(nullptr)
                                 : nlohmann::json{{"cols", board.cols},
                                                  {"rows", board.rows},
                                                  {"square_size_m", board.square_size_m}};
    j["max_observed_theta_deg"] = cal.max_observed_theta * kDeg;
    j["model_limit_theta_deg"] = cam.max_theta() * kDeg;
    j["mask_max_theta_deg"] = full.max_theta * kDeg;
    j["fov_deg"] = 2 * fov_theta * kDeg;
    j["image_circle"] = {{"cx_px", circle.cx},
                         {"cy_px", circle.cy},
                         {"radius_px", circle.radius_px},
                         {"source", circle_source}};
    j["device_from_camera"] = matrix_json(device_from_camera);
    j["covered_solid_angle_sr"] = full.covered_solid_angle_sr;
    j["files"] = {
        {"directions", "directions.exr"}, {"solid_angle", "solid_angle.exr"}, {"mask", "mask.png"}};
    nlohmann::json maps = nlohmann::json::array();
    maps.push_back({{"dir", "."},
                    {"width", width},
                    {"height", height},
                    {"valid_pixels", full.valid_pixels},
                    {"covered_solid_angle_sr", full.covered_solid_angle_sr}});
    for (size_t i = 0; i < sizes.size(); ++i) {
        maps.push_back({{"dir", str(sizes[i].x(), "x", sizes[i].y())},
                        {"width", sizes[i].x()},
                        {"height", sizes[i].y()},
                        {"valid_pixels", small[i].valid_pixels},
                        {"covered_solid_angle_sr", small[i].covered_solid_angle_sr}});
    }
    j["maps"] = maps;

    return j;
}

}  // namespace

nlohmann::json run_geometry(const GeometryOptions& o, Report& report) {
    // Options first: every usage error before any work.
    if (o.output.empty()) throw UsageError("--output is required");
    const bool from_images = !o.inputs.empty();
    const bool from_corners = !o.image_points.empty();
    if (from_images == from_corners) {
        throw UsageError("give chessboard images (or folders), or --image-points, not both");
    }
    if (!o.object_points.empty() && !from_corners) {
        throw UsageError("--object-points needs --image-points");
    }
    BoardSpec board;
    if (!o.board.empty()) {
        board = parse_board(o.board, o.square_size_m);
    } else if (from_images || o.object_points.empty()) {
        throw UsageError(
            "--board COLSxROWS (inner corners) is required for images, and for "
            "corner files without --object-points");
    }
    CalibrateOptions co;
    co.model = model_type_from_string(o.model);
    co.fix_skew = !o.estimate_skew;
    co.fix_aspect_ratio = o.fix_aspect_ratio;
    co.pinhole_k3 = !o.fix_k3;
    co.outlier_factor = o.outlier_factor;
    co.outlier_min_px = o.outlier_min_px;
    // OpenCV's detectors assert on a pattern of 2 rows or columns ("Both width and height of the
    // pattern should have bigger than 2"): said before any image is read, naming the option.
    if (from_images && (board.cols < 3 || board.rows < 3)) {
        throw UsageError(str("--board ", board.cols, "x", board.rows, ": finding a chessboard in "
                             "images needs at least 3x3 inner corners (2 rows or columns only "
                             "suit corner files)"));
    }
    DetectOptions dopt;
    dopt.board = board;
    dopt.detector = detector_from_string(o.detector);
    if (o.refine_iterations < 0) throw UsageError("--refine-iterations must be >= 0");
    if (o.fov_deg < 0 || o.fov_deg > 360) throw UsageError("--fov-deg must lie in [0, 360]");
    const Eigen::Matrix3d device_from_camera =
        parse_rotation(o.device_from_camera) * default_device_from_camera();
    const bool circle_auto = o.image_circle == "auto";
    ImageCircle circle;
    std::string circle_source = "none";
    if (!circle_auto && o.image_circle != "none") {
        circle = parse_image_circle(o.image_circle);
        circle_source = "given";
    }
    std::vector<Eigen::Vector2i> sizes;
    if (!o.downscale.empty()) sizes = parse_sizes(o.downscale);
    Eigen::Vector2i given_size(0, 0);
    if (!o.image_size.empty()) given_size = parse_size(o.image_size, "--image-size");
    // Every output named before any work (no output may overwrite an input, e.g. a corner file
    // kept in the output folder).
    const std::filesystem::path out_dir(o.output);
    for (const char* f : {"calibration.json", "directions.exr", "solid_angle.exr", "mask.png",
                          "image_points.yml", "object_points.yml", "camera_info.yaml",
                          "opencv_camera.yml"}) {
        fs::declare_output((out_dir / f).string(), "-o");
    }
    for (const Eigen::Vector2i& s : sizes) {
        for (const char* f : {"directions.exr", "solid_angle.exr", "mask.png"}) {
            fs::declare_output((out_dir / str(s.x(), "x", s.y()) / f).string(), "--downscale");
        }
    }

    // 1. Corners.
    std::vector<View> views;
    std::vector<std::string> view_paths;
    std::vector<DroppedView> dropped;
    GrayImage brightest;
    int width = 0, height = 0;
    size_t inputs = 0;
    {
        ScopedStage stage(report, from_images ? "detect_corners" : "read_corners");
        if (from_images) {
            const auto paths = expand_image_inputs(o.inputs);
            inputs = paths.size();
            for (const auto& p : paths) report.add_input(p);
            Detections d = detect_boards(paths, dopt, circle_auto ? &brightest : nullptr);
            width = d.width;
            height = d.height;
            views = std::move(d.views);
            view_paths = std::move(d.view_paths);
            dropped = std::move(d.dropped);
        } else {
            report.add_input(o.image_points);
            if (!o.object_points.empty()) report.add_input(o.object_points);
            CornerSet cs = read_corner_files(o.image_points, o.object_points, board);
            width = given_size.x() > 0 ? given_size.x() : cs.width;
            height = given_size.y() > 0 ? given_size.y() : cs.height;
            if (width <= 0 || height <= 0) {
                throw UsageError(str(o.image_points,
                                     " does not state the image size: give "
                                     "--image-size WxH"));
            }
            views = std::move(cs.views);
            inputs = views.size();
        }
    }
    for (const Eigen::Vector2i& s : sizes) {  // before any long work
        if (s.x() > width || s.y() > height) {
            throw UsageError(str("--downscale ", s.x(), "x", s.y(), " exceeds the image size ",
                                 width, "x", height));
        }
    }
    if (views.empty()) {
        throw Error(str("no chessboard of ", board.cols, "x", board.rows,
                        " inner corners found in ", inputs == 1 ? "the one image" : str("any of the ", inputs, " images"),
                        list_dropped(dropped)));
    }
    if (static_cast<int>(views.size()) < co.min_views) {
        throw Error(str("only ", views.size(), " usable view", views.size() == 1 ? "" : "s", " of ",
                        inputs, ", need at least ", co.min_views, list_dropped(dropped)));
    }

    // 2. Calibration, then fronto-parallel refinement passes.
    Calibration cal;
    {
        ScopedStage stage(report, "calibrate");
        cal = calibrate_views(views, width, height, co, dropped);
    }
    std::vector<DroppedView> dropped_in_calibration = cal.dropped;
    const int passes = from_images ? o.refine_iterations : 0;
    for (int pass = 0; pass < passes; ++pass) {
        std::vector<View> refined(cal.views.size());
        std::vector<std::string> refined_paths(cal.views.size());
        {
            ScopedStage stage(report, "refine_corners");
            parallel::for_chunks(
                static_cast<int64_t>(cal.views.size()), 1, [&](int64_t b, int64_t e) {
                    for (int64_t k = b; k < e; ++k) {
                        const size_t i = cal.view_index[static_cast<size_t>(k)];
                        refined[k] = refine_view(load_gray(view_paths[i]), views[i], board,
                                                 cal.camera, cal.views[k].rvec, cal.views[k].tvec);
                        refined_paths[k] = view_paths[i];
                    }
                });
        }
        views = std::move(refined);
        view_paths = std::move(refined_paths);
        {
            ScopedStage stage(report, "calibrate");
            cal = calibrate_views(views, width, height, co, dropped);
        }
        dropped_in_calibration.insert(dropped_in_calibration.end(), cal.dropped.begin(),
                                      cal.dropped.end());
    }
    dropped.insert(dropped.end(), dropped_in_calibration.begin(), dropped_in_calibration.end());
    for (const DroppedView& d : dropped) log::warn(str("dropped ", d.name, ": ", d.reason));

    // 3. Maps.
    const CameraModel& cam = cal.camera;
    if (circle_auto && from_images) {
        circle = detect_image_circle(brightest, cam.cx, cam.cy);
        circle_source = circle.radius_px > 0 ? "auto" : "auto: none inside the frame";
    }
    MapOptions mo;
    mo.device_from_camera = device_from_camera;
    mo.max_theta = o.fov_deg > 0 ? 0.5 * o.fov_deg / kDeg : 0.0;
    mo.circle = circle;
    DirectionMaps full;
    {
        ScopedStage stage(report, "direction_maps");
        full = compute_maps(cam, mo);
    }
    if (full.valid_pixels == 0)
        throw Error("the validity mask is empty: check --fov-deg and --image-circle");
    const double fov_theta = largest_theta(full, device_from_camera * Eigen::Vector3d::UnitZ());
    if (fov_theta * kDeg > cal.max_observed_theta * kDeg + kExtrapolationWarnDeg) {
        log::warn(str("the mask reaches ", fov_theta * kDeg,
                      " deg off axis but corners were seen "
                      "only up to ",
                      cal.max_observed_theta * kDeg,
                      " deg: beyond that the model is extrapolated (limit it with --fov-deg)"));
    }
    if (sizes.empty()) {
        for (int div : {4, 8}) {
            sizes.emplace_back(std::max(1, static_cast<int>(std::lround(width / double(div)))),
                               std::max(1, static_cast<int>(std::lround(height / double(div)))));
        }
    }
    std::vector<DirectionMaps> small;
    {
        ScopedStage stage(report, "downscale");
        for (const Eigen::Vector2i& s : sizes) small.push_back(downscale_maps(full, s.x(), s.y()));
    }

    // 4. calibration.json.
    const nlohmann::json j =
        calibration_json(o, co, board, cal, dropped, width, height, passes, circle, circle_source,
                         device_from_camera, fov_theta, full, sizes, small);

    // 5. Files.
    {
        ScopedStage stage(report, "write_outputs");
        const std::filesystem::path out(o.output);
        for (const std::string& p : write_maps(out.string(), full)) {
            report.add_output(p, fs::extension(p) == "png" ? "mask" : "map", "data");
        }
        for (size_t i = 0; i < sizes.size(); ++i) {
            const std::string dir = (out / str(sizes[i].x(), "x", sizes[i].y())).string();
            for (const std::string& p : write_maps(dir, small[i])) {
                report.add_output(p, fs::extension(p) == "png" ? "mask" : "map", "data");
            }
        }
        std::vector<View> used;
        for (size_t i : cal.view_index) used.push_back(views[i]);
        const std::string ip = (out / "image_points.yml").string();
        const std::string op = (out / "object_points.yml").string();
        write_corner_files(ip, op, used, width, height);
        report.add_output(ip, "corners");
        report.add_output(op, "corners");
        const std::string cj = (out / "calibration.json").string();
        fs::write_text_atomic(cj, dump_finite(j, 2, cj));
        report.add_output(cj, "calibration");
        const std::string ocv = (out / "opencv_camera.yml").string();
        write_opencv_camera_yaml(ocv, cal.camera);
        report.add_output(ocv, "camera_opencv");
        if (has_ros_camera_info(cal.camera.type)) {
            const std::string ros = (out / "camera_info.yaml").string();
            const std::string name = o.camera_name.empty()
                                         ? default_camera_name(o.inputs, o.image_points)
                                         : o.camera_name;
            fs::write_text_atomic(ros, ros_camera_info_yaml(cal.camera, name));
            report.add_output(ros, "camera_info_ros");
        }
    }

    // 6. Metrics.
    nlohmann::json& m = report.metrics();
    m["model"] = to_string(cam.type);
    m["reproj_rms_px"] = cal.rms_px;
    double worst = 0;
    for (const ViewError& e : cal.views) worst = std::max(worst, e.rms_px);
    m["worst_view_rms_px"] = worst;
    nlohmann::json per_view = nlohmann::json::object();
    for (const ViewError& e : cal.views) per_view[e.name] = e.rms_px;
    m["view_rms_px"] = per_view;
    m["dropped_views"] = j["dropped_views"];
    m["views_used"] = cal.views.size();
    m["views_dropped"] = dropped.size();
    m["intrinsics"] = j["intrinsics"];
    m["intrinsics_std"] = j["intrinsics_std"];
    m["fov_deg"] = 2 * fov_theta * kDeg;
    m["max_observed_theta_deg"] = cal.max_observed_theta * kDeg;
    m["covered_solid_angle_sr"] = full.covered_solid_angle_sr;
    m["valid_pixels"] = full.valid_pixels;
    m["image_circle_radius_px"] = circle.radius_px;
    m["solver"] = cal.solver;

    print_summary(cal, dropped.size(), fov_theta);
    if (o.max_reproj_rms_px > 0 && cal.rms_px > o.max_reproj_rms_px) {
        throw app::QualityGateFailed(str("reprojection RMS ", cal.rms_px,
                                         " px > --max-reproj-rms-px ", o.max_reproj_rms_px));
    }
    return j;
}

void run_response(const ResponseToolOptions& o, uint64_t seed, Report& report) {
    if (o.output.empty()) throw UsageError("--output is required");
    if (o.images.size() < 2) throw UsageError("--images needs at least two exposures");
    if (o.images.size() != o.exposure_s.size()) {
        throw UsageError(
            str(log::count(int64_t(o.images.size()), "image"), " but ",
                log::count(int64_t(o.exposure_s.size()), "--exposure-s value")));
    }
    for (const std::string& p : o.images) fs::declare_input(p, "--images");
    fs::declare_output(o.output, "-o");
    if (!o.merged.empty()) fs::declare_output(o.merged, "--merged");
    std::vector<image::Image> codes;
    {
        ScopedStage stage(report, "read_images");
        for (const std::string& p : o.images) {
            report.add_input(p);
            codes.push_back(read_codes(p));
            if (codes.back().width != codes[0].width || codes.back().height != codes[0].height ||
                codes.back().channels != codes[0].channels) {
                throw Error(str(p, ": ", codes.back().width, "x", codes.back().height, "x",
                                codes.back().channels, " differs from ", o.images[0], "'s ",
                                codes[0].width, "x", codes[0].height, "x", codes[0].channels));
            }
        }
    }
    ResponseOptions ro;
    ro.lambda = o.lambda;
    ro.samples = o.samples;
    ro.seed = seed;
    ResponseFit fit;
    {
        ScopedStage stage(report, "recover_response");
        fit = recover_response(codes, o.exposure_s, ro);
    }
    MergeResult merged;
    if (!o.merged.empty()) {
        ScopedStage stage(report, "merge_radiance");
        merged = merge_radiance(codes, o.exposure_s, fit.curve);
    }
    {
        ScopedStage stage(report, "write_outputs");
        write_response(o.output, fit, o.lambda, o.exposure_s, o.images);
        report.add_output(o.output, "response_curve");
        if (!o.merged.empty()) {
            image::WriteOptions wo;
            wo.exr_half = false;
            image::write_image(o.merged, merged.radiance, wo);
            report.add_output(o.merged, "radiance", "raw_camera");
        }
    }
    nlohmann::json& m = report.metrics();
    m["channels"] = fit.curve.channel_names;
    m["samples_per_channel"] = fit.samples;
    m["fit_rms_log"] = fit.fit_rms_log;
    nlohmann::json range = nlohmann::json::array();
    for (const auto& g : fit.curve.log_exposure) range.push_back((g[254] - g[1]) / std::log(2.0));
    m["response_range_stops"] = range;  // codes 1..254
    if (!o.merged.empty()) m["merged_saturated_pixels"] = merged.saturated_pixels;
}

}  // namespace inlight::calib
