// calibrate: camera calibration for lighting from a (fisheye) camera frame.
//   calibrate geometry: chessboard photographs (or corner files) -> intrinsics, direction,
//                       solid-angle and mask maps (docs/calibrate.md).
//   calibrate response: an exposure bracket -> the camera's response curve (Debevec-Malik).
#include <string>

#include "calib/cli.h"
#include "core/app.h"
#include "core/modes.h"

namespace {

constexpr const char* kGeometryPurpose =
    "calibrate geometry: chessboard photographs (or corner files) -> camera intrinsics, a "
    "direction map (unit vector per pixel, device frame), a solid-angle map (sr per pixel), a "
    "validity mask, and downscaled versions";
constexpr const char* kResponsePurpose =
    "calibrate response: recover an 8-bit camera's response curve (Debevec-Malik 1997) from a "
    "bracket of exposures of a still scene";

}  // namespace

int main(int argc, char** argv) {
    using namespace inlight;
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "geometry" || mode == "response") {
        const bool geometry = mode == "geometry";
        CLI::App app{geometry ? kGeometryPurpose : kResponsePurpose, "calibrate " + mode};
        app::CommonArgs common;
        calib::GeometryOptions gopt;
        calib::ResponseToolOptions ropt;
        if (geometry) {
            calib::add_geometry_options(app, gopt);
        } else {
            calib::add_response_options(app, ropt);
        }
        app::setup(app, common, geometry ? calib::kGeometryExample : calib::kResponseExample);
        if (auto code = app::parse(app, argc, argv, 1)) return *code;
        return app::run("calibrate", app, common, argc, argv, [&](Report& report) {
            report.metrics()["mode"] = mode;
            if (geometry) {
                calib::run_geometry(gopt, report);
            } else {
                calib::run_response(ropt, common.seed, report);
            }
        });
    }

    // No mode (or an unknown one): list the modes.
    return app::list_modes(
        "calibrate", "calibrate: camera calibration for lighting from a camera frame",
        {{"geometry", kGeometryPurpose, calib::kGeometryExample},
         {"response", kResponsePurpose, calib::kResponseExample}},
        "0 ok, 1 runtime error, 2 usage error, 3 quality gate failed.", argc, argv);
}
