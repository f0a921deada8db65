#include "calib/cli.h"

#include "calib/board.h"
#include "calib/camera_yaml.h"
#include "core/validators.h"

namespace inlight::calib {

const char* const kGeometryExample =
    "calibrate geometry ../shared/data/fisheye-ros-mono --board 8x6 --square-size-m 0.108 "
    "-o out/ros --report out/ros/report.json\n"
    "  calibrate geometry --image-points left.xml --object-points object.xml "
    "--image-size 1280x800 -o out/jy";
const char* const kResponseExample =
    "calibrate response --images a.png b.png c.png --exposure-s 0.01 0.04 0.16 "
    "-o response.json";

void add_geometry_options(CLI::App& app, GeometryOptions& o) {
    app.add_option("inputs", o.inputs,
                   "Chessboard photographs and/or folders of them (any format OpenCV or "
                   "OpenImageIO reads, 8 or 16 bit); all must share one size");
    app.add_option("--image-points", o.image_points,
                   "Instead of images: corner file (OpenCV FileStorage XML/YAML, nodes "
                   "image_0.. of x y pixels)");
    app.add_option("--object-points", o.object_points,
                   "Object points for --image-points (nodes image_0.. of x y z metres); "
                   "default: from --board");
    app.add_option("--image-size", o.image_size,
                   "Image size WxH for corner files that do not state it")
        ->check(app::parses_with([](const std::string& s) { parse_sizes(s, "--image-size"); },
                                 "WxH"));
    app.add_option("--board", o.board, "Chessboard inner corners COLSxROWS, e.g. 8x6")
        ->check(app::parses_with([](const std::string& s) { parse_board(s, 1.0); }, "COLSxROWS"));
    app.add_option("--square-size-m", o.square_size_m,
                   "Square side, metres (scales only the reported poses)")
        ->check(app::finite_positive())
        ->capture_default_str();
    app.add_option("--model", o.model,
                   "Camera model: fisheye (Kannala-Brandt k1..k4), pinhole (k1 k2 p1 p2 k3), "
                   "omnidir (Mei: xi, k1 k2 p1 p2)")
        ->check(CLI::IsMember({"fisheye", "pinhole", "omnidir"}))
        ->capture_default_str();
    app.add_option("--detector", o.detector,
                   "Corner detector: auto (classic, sb where classic fails), classic "
                   "(findChessboardCorners + cornerSubPix), sb (findChessboardCornersSB), ros "
                   "(ROS camera_calibration's procedure, to reproduce its results)")
        ->check(CLI::IsMember({"auto", "classic", "sb", "ros"}))
        ->capture_default_str();
    app.add_option("--refine-iterations", o.refine_iterations,
                   "Fronto-parallel corner refinement passes (Datta et al. 2009); 0 = off")
        ->check(CLI::Range(0, 10))
        ->capture_default_str();
    app.add_flag("--estimate-skew", o.estimate_skew, "Estimate skew (fisheye, omnidir)");
    app.add_flag("--fix-aspect-ratio", o.fix_aspect_ratio, "Pinhole: fx = fy");
    app.add_flag("--fix-k3", o.fix_k3, "Pinhole: k3 = 0");
    app.add_option("--outlier-factor", o.outlier_factor,
                   "Drop a view whose RMS exceeds this x the median view RMS (and "
                   "--outlier-min-px); 0 = keep all")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("--outlier-min-px", o.outlier_min_px,
                   "Never drop a view whose RMS is below this, pixels")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("--fov-deg", o.fov_deg,
                   "Mask: full field of view, degrees (0 = up to where the model stops being "
                   "one-to-one)")
        ->check(app::finite_range(0, 360))
        ->capture_default_str();
    app.add_option("--image-circle", o.image_circle,
                   "Mask: the lens' image circle: auto (from the images), none, or CX,CY,R in "
                   "pixels")
        ->check(app::parses_with(
            [](const std::string& s) {
                if (s != "auto" && s != "none") parse_image_circle(s);
            },
            "auto|none|CX,CY,R"))
        ->capture_default_str();
    app.add_option("--device-from-camera", o.device_from_camera,
                   "Rotation applied after the default front-camera mapping diag(-1,-1,1): "
                   "none, or axis=degrees list, e.g. z=90")
        ->check(app::rotation())
        ->capture_default_str();
    app.add_option("--downscale", o.downscale,
                   "Downscaled map sizes WxH,WxH... (default: 1/4 and 1/8 of the image)")
        ->check(app::parses_with([](const std::string& s) { parse_sizes(s, "--downscale"); },
                                 "WxH[,WxH...]"));
    app.add_option("--max-reproj-rms-px", o.max_reproj_rms_px,
                   "Quality gate: exit 3 if the RMS reprojection error exceeds this, pixels "
                   "(0 = off)")
        ->check(app::finite_non_negative())
        ->capture_default_str();
    app.add_option("-o,--output", o.output,
                   "Output folder: calibration.json, directions.exr, solid_angle.exr, mask.png, "
                   "<W>x<H>/ downscaled maps, image_points.yml, object_points.yml")
        ->required();
    app.add_option("--camera-name", o.camera_name,
                   "camera_name in camera_info.yaml (ROS: letters, digits and '_'); default: the "
                   "input folder's name, or the one input file's stem, other characters as '_'")
        ->check(CLI::Validator(
            [](std::string& v) {
                return is_ros_camera_name(v)
                           ? std::string()
                           : "'" + v + "' is not a ROS camera name (only letters, digits and '_')";
            },
            ""))
        ->type_name("NAME");
}

void add_response_options(CLI::App& app, ResponseToolOptions& o) {
    app.add_option("--images", o.images, "8-bit bracket of a still scene, one image per exposure")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--exposure-s", o.exposure_s, "Exposure time of each image, seconds")
        ->required()
        ->check(app::finite_positive());
    app.add_option("--lambda", o.lambda, "Smoothness weight (Debevec-Malik lambda)")
        ->check(app::finite_positive())
        ->capture_default_str();
    app.add_option("--samples", o.samples,
                   "Pixel samples per channel (0 = 4 x 256 / (exposures - 1), within 64..1024)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    app.add_option("--merged", o.merged, "Also write the merged radiance here (float EXR)");
    app.add_option("-o,--output", o.output, "Response curve (JSON)")->required();
}

}  // namespace inlight::calib
