// calib/corner_file.h: detected corners in OpenCV FileStorage files (XML, YAML or JSON, chosen
// by extension), so a calibration can be reproduced without its images. The layout is the one
// of OpenCV's fisheye test data (calib-3_stereo_from_JY/left.xml, object.xml).
#pragma once

#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/detect.h"

namespace inlight::calib {

/// Views and, when the file states it, the image size.
struct CornerSet {
    std::vector<View> views;
    int width = 0;   ///< from the node image_width, 0 if absent
    int height = 0;  ///< from the node image_height, 0 if absent
};

/// Reads views: `image_points_path` holds nodes image_0, image_1, ... (consecutive from 0), each
/// one view's corners in pixels (OpenCV convention) as a flat sequence x y x y ..., a sequence
/// of [x, y] pairs, or an opencv-matrix of 2 channels or 2 columns. `object_points_path` holds
/// the same node names with x y z in metres; when it is empty every view gets
/// board_object_points(board) (then board.cols * board.rows must match, checked). Optional
/// nodes in the image file: image_width, image_height, and files (view names; otherwise views
/// are named "image_<i>"). Throws Error naming the file and node on any mismatch.
CornerSet read_corner_files(const std::string& image_points_path,
                            const std::string& object_points_path, const BoardSpec& board);

/// Writes views in the layout read_corner_files reads (with image_width, image_height and
/// files), atomically.
void write_corner_files(const std::string& image_points_path, const std::string& object_points_path,
                        const std::vector<View>& views, int width, int height);

}  // namespace inlight::calib
