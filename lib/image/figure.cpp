#include "image/figure.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "image/color.h"
#include "image/metrics.h"

namespace inlight::image {
namespace {

// Layout in output pixels, font sizes as cv::FONT_HERSHEY_SIMPLEX scales (0.5 ~ 13 px caps).
constexpr int kMarginPx = 10, kGapPx = 10, kBarWidthPx = 22, kTitleBandPx = 34,
              kCaptionBandPx = 26;
constexpr double kTitleFont = 0.6, kCaptionFont = 0.45, kTickFont = 0.45;
const cv::Scalar kBackground(32, 32, 32), kText(235, 235, 235);

uint8_t code_of(float linear) {
    const float e = std::clamp(srgb_encode(linear), 0.0f, 1.0f);
    return static_cast<uint8_t>(std::lround(e * 255.0f));
}

int text_width(const std::string& s, double font) {
    int baseline = 0;
    return cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, font, 1, &baseline).width;
}

// Text with its baseline at y, shrunk (down to 60%) to fit max_width when it must.
void put_text(cv::Mat& canvas, const std::string& s, int x, int y, double font, int max_width) {
    const int w = text_width(s, font);
    if (w > max_width && max_width > 0) font *= std::max(0.6, double(max_width) / w);
    cv::putText(canvas, s, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, font, kText, 1, cv::LINE_AA);
}

std::string tick(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

}  // namespace

int figure_scale(int height_px) {
    if (height_px <= 0) throw Error(str("figure: panel height must be > 0, got ", height_px));
    return std::max(1, (kFigureMinPanelPx + height_px - 1) / height_px);
}

Image figure(const std::string& title, const std::vector<FigurePanel>& panels, const ColorBar* bar,
             FigureLayout* layout_out) {
    if (panels.empty()) throw Error("figure: no panels");
    const int h = panels.front().image->height;
    for (const FigurePanel& p : panels) {
        if (p.image->height != h)
            throw Error(str("figure: panels of different heights (", h, ", ", p.image->height, ")"));
        if (p.image->channels < 3)
            throw Error(str("figure: panel '", p.caption, "' has ", p.image->channels, " channels"));
    }
    FigureLayout L;
    L.scale = figure_scale(h);
    L.title_height_px = kTitleBandPx;
    L.panels_top_px = kTitleBandPx + kCaptionBandPx;
    L.panel_height_px = h * L.scale;
    int x = kMarginPx;
    for (const FigurePanel& p : panels) {
        L.panel_left_px.push_back(x);
        x += p.image->width * L.scale + kGapPx;
    }
    std::string top_label, unit;
    int tick_w = 0;
    if (bar) {
        if (!(bar->max_value > 0)) throw Error(str("figure: colour bar max must be > 0, got ", bar->max_value));
        top_label = ">= " + tick(bar->max_value);  // heat_map clamps larger values to the top
        unit = bar->unit;
        tick_w = std::max(text_width(top_label, kTickFont), text_width("0", kTickFont));
        L.bar_left_px = x + kGapPx;
        L.bar_width_px = kBarWidthPx;
        x = L.bar_left_px + kBarWidthPx + 6 + tick_w + kGapPx;
        x = std::max(x, L.bar_left_px + text_width(unit, kCaptionFont) + kMarginPx);
    }
    const int width = std::max(x - kGapPx + kMarginPx, text_width(title, kTitleFont) + 2 * kMarginPx);
    const int height = L.panels_top_px + L.panel_height_px + kMarginPx;
    cv::Mat canvas(height, width, CV_8UC3, kBackground);

    put_text(canvas, title, kMarginPx, kTitleBandPx - 12, kTitleFont, width - 2 * kMarginPx);
    for (size_t i = 0; i < panels.size(); ++i) {
        const Image& im = *panels[i].image;
        const int left = L.panel_left_px[i], pw = im.width * L.scale;
        put_text(canvas, panels[i].caption, left, L.panels_top_px - 8, kCaptionFont, pw);
        for (int y = 0; y < L.panel_height_px; ++y) {
            auto* row = canvas.ptr<cv::Vec3b>(L.panels_top_px + y);
            for (int xx = 0; xx < pw; ++xx)
                for (int c = 0; c < 3; ++c)
                    row[left + xx][c] = code_of(im.at(xx / L.scale, y / L.scale, c));
        }
    }
    if (bar) {
        // Row y shows the value at its centre, t = 1 - (y + 0.5) / H of max_value, in the
        // heat map's own colours (heat_map of that ramp).
        Image ramp(1, L.panel_height_px, 1, ColorSpace::kData);
        for (int y = 0; y < L.panel_height_px; ++y)
            ramp.at(0, y, 0) = static_cast<float>(
                (1.0 - (y + 0.5) / L.panel_height_px) * bar->max_value);
        const Image colours = heat_map(ramp, bar->max_value);
        for (int y = 0; y < L.panel_height_px; ++y) {
            auto* row = canvas.ptr<cv::Vec3b>(L.panels_top_px + y);
            for (int xx = 0; xx < kBarWidthPx; ++xx)
                for (int c = 0; c < 3; ++c) row[L.bar_left_px + xx][c] = code_of(colours.at(0, y, c));
        }
        const int tx = L.bar_left_px + kBarWidthPx + 6;
        put_text(canvas, top_label, tx, L.panels_top_px + 12, kTickFont, 0);
        put_text(canvas, "0", tx, L.panels_top_px + L.panel_height_px, kTickFont, 0);
        put_text(canvas, unit, L.bar_left_px, L.panels_top_px - 8, kCaptionFont, width - L.bar_left_px - 2);
    }

    Image out(width, height, 3, ColorSpace::kLinearSrgb);
    for (int y = 0; y < height; ++y) {
        const auto* row = canvas.ptr<cv::Vec3b>(y);
        for (int xx = 0; xx < width; ++xx)
            for (int c = 0; c < 3; ++c) out.at(xx, y, c) = srgb_decode(row[xx][c] / 255.0f);
    }
    if (layout_out) *layout_out = L;
    return out;
}

}  // namespace inlight::image
