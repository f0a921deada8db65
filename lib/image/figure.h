// image/figure.h: images for people to look at: panels side by side, each with a caption, a
// title above them, and a colour bar giving a heat map's scale (its 0 and top value, and the
// unit), drawn with OpenCV (cv::putText). Small panels are enlarged by an integer factor
// (nearest neighbour, so no pixel is invented) until they are at least kFigureMinPanelPx tall.
#pragma once

#include <string>
#include <vector>

#include "image/image.h"

namespace inlight::image {

/// Panels shorter than this (pixels) are enlarged: 128 px panels with 13 px text are hard to read.
constexpr int kFigureMinPanelPx = 256;

/// The integer factor a panel `height_px` tall is enlarged by: ceil(kFigureMinPanelPx /
/// height_px), at least 1. Throws Error unless height_px > 0.
int figure_scale(int height_px);

/// One panel: a linear_srgb image of 3 channels (alpha, a 4th, is ignored) and its caption.
struct FigurePanel {
    const Image* image = nullptr;
    std::string caption;
};

/// The colour bar of heat_map(scalar, max_value): 0 at the bottom, max_value at the top, printed
/// beside it as "0" and ">= max" (heat_map shows larger values in the top colour), `unit`
/// printed above it (e.g. "rel. error").
struct ColorBar {
    double max_value = 1;
    std::string unit;
};

/// Where figure() put its parts, in output pixels (for tests and for callers that add more).
struct FigureLayout {
    int scale = 1;                  ///< figure_scale of the panels' height
    int title_height_px = 0;        ///< rows [0, title_height_px) hold the title
    int panels_top_px = 0;          ///< first row of the (enlarged) panels and of the bar
    int panel_height_px = 0;        ///< enlarged panel height = bar height
    std::vector<int> panel_left_px; ///< first column of each enlarged panel
    int bar_left_px = -1;           ///< first column of the bar (-1: no bar)
    int bar_width_px = 0;
};

/// The figure: `title` on top, then the panels left to right (all of one height; Error if not,
/// or if a panel has fewer than 3 channels), each under its caption, and `bar` (when not null)
/// right of them. Dark grey background, light text; linear_srgb, ready for write_image to PNG.
Image figure(const std::string& title, const std::vector<FigurePanel>& panels,
             const ColorBar* bar, FigureLayout* layout = nullptr);

}  // namespace inlight::image
