// calib/pipeline.h: the two things the `calibrate` tool does, end to end, with their stages
// timed in the run report: geometric calibration (chessboard photographs or corner files ->
// intrinsics, direction / solid-angle / mask maps) and radiometric calibration (an exposure
// bracket -> response curve). The output file contract is in docs/calibrate.md.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "calib/maps.h"
#include "calib/solve.h"
#include "core/report.h"

namespace inlight::calib {

/// Options of `calibrate geometry` (the CLI's long flags, snake_case).
struct GeometryOptions {
    std::vector<std::string> inputs;  ///< chessboard images and/or folders of them
    std::string image_points;         ///< or: corner file (OpenCV FileStorage), see corner_file.h
    std::string object_points;        ///< its object points ("" = from --board)
    std::string image_size;           ///< "WxH" for corner files that do not state it
    std::string board;                ///< "COLSxROWS" inner corners
    double square_size_m = 1.0;       ///< scales only the reported poses, never the intrinsics
    std::string model = "fisheye";
    std::string detector = "auto";
    int refine_iterations = 2;  ///< fronto-parallel refinement passes (images only)
    bool estimate_skew = false;
    bool fix_aspect_ratio = false;  ///< pinhole
    bool fix_k3 = false;            ///< pinhole
    double outlier_factor = 3.0;
    double outlier_min_px = 1.0;
    double fov_deg = 0;                       ///< mask: full field of view; 0 = the model's limit
    std::string image_circle = "auto";        ///< "auto", "none" or "CX,CY,R" (pixels)
    std::string device_from_camera = "none";  ///< rotation applied after the default
    std::string downscale;                    ///< "WxH,..."; "" = 1/4 and 1/8 of the full size
    double max_reproj_rms_px = 0;             ///< quality gate (0 = none)
    std::string output;                       ///< output folder
    /// camera_info.yaml's camera_name (ROS: letters, digits, '_'); "" = default_camera_name().
    std::string camera_name;
};

/// Parses --image-circle "CX,CY,R" (pixels; finite, R > 0). Throws UsageError naming the option.
ImageCircle parse_image_circle(const std::string& spec);

/// Runs geometric calibration and writes everything into options.output. Throws Error on bad
/// input (exit 1), UsageError on bad options (exit 2), QualityGateFailed after writing when
/// the RMS exceeds max_reproj_rms_px (exit 3). Returns calibration.json's content.
nlohmann::json run_geometry(const GeometryOptions& options, Report& report);

/// Options of `calibrate response`.
struct ResponseToolOptions {
    std::vector<std::string> images;  ///< 8-bit bracket, one image per exposure
    std::vector<double> exposure_s;   ///< their exposure times, seconds
    double lambda = 50;
    int samples = 0;
    std::string output;  ///< response JSON
    std::string merged;  ///< optional: merged radiance EXR
};

/// Recovers the response, writes it (and the merged radiance if asked). Same error contract.
void run_response(const ResponseToolOptions& options, uint64_t seed, Report& report);

}  // namespace inlight::calib
