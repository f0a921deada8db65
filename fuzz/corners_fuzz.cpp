// Harness: OpenCV corner files (calib::read_corner_files): image points and object points, the
// input holding both files split at its first NUL byte. Each pair is read twice: with its object
// points file, and with the board's own object points (an empty object file name).
#include "calib/corner_file.h"
#include "fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto [image_text, object_text] = inlight::fuzz::split_pair(data, size);
    const auto bytes = [](const std::string& s) { return reinterpret_cast<const uint8_t*>(s.data()); };
    const std::string image_path =
        inlight::fuzz::write_temp("image_points.yml", bytes(image_text), image_text.size());
    const std::string object_path =
        inlight::fuzz::write_temp("object_points.yml", bytes(object_text), object_text.size());
    inlight::calib::BoardSpec board;
    board.cols = 3;
    board.rows = 2;
    board.square_size_m = 0.025;
    inlight::fuzz::expect_error_or_success(
        [&] { inlight::calib::read_corner_files(image_path, object_path, board); });
    inlight::fuzz::expect_error_or_success(
        [&] { inlight::calib::read_corner_files(image_path, "", board); });
    return 0;
}
