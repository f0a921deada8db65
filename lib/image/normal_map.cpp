#include "image/normal_map.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/error.h"

namespace inlight::image {

namespace {

void check_finite(const Image& img, const char* what) {
    if (img.width <= 0 || img.height <= 0 || img.channels <= 0) {
        throw Error(str(what, ": empty image"));
    }
    for (float v : img.pixels) {
        if (!std::isfinite(v)) throw Error(str(what, ": holds a NaN or Inf value"));
    }
}

}  // namespace

Image normal_map_from_height(const Image& height, Border border) {
    check_finite(height, "normal_map_from_height");
    const int w = height.width, h = height.height;
    auto at = [&](int x, int y) -> double {
        if (border == Border::kWrap) {
            x = ((x % w) + w) % w;
            y = ((y % h) + h) % h;
        } else {
            x = std::clamp(x, 0, w - 1);
            y = std::clamp(y, 0, h - 1);
        }
        return height.at(x, y, 0);
    };
    Image out(w, h, 3, ColorSpace::kData);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            // Central differences; with kClamp a border texel uses the one-sided difference
            // over the single step it has.
            const int x0 = border == Border::kClamp ? std::max(x - 1, 0) : x - 1;
            const int x1 = border == Border::kClamp ? std::min(x + 1, w - 1) : x + 1;
            const int y0 = border == Border::kClamp ? std::max(y - 1, 0) : y - 1;
            const int y1 = border == Border::kClamp ? std::min(y + 1, h - 1) : y + 1;
            const double dh_dx = x1 > x0 ? (at(x1, y) - at(x0, y)) / (x1 - x0) : 0.0;
            const double dh_drow = y1 > y0 ? (at(x, y1) - at(x, y0)) / (y1 - y0) : 0.0;
            const double nx = -dh_dx, ny = dh_drow, nz = 1.0;
            const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
            out.at(x, y, 0) = static_cast<float>(nx / len);
            out.at(x, y, 1) = static_cast<float>(ny / len);
            out.at(x, y, 2) = static_cast<float>(nz / len);
        }
    }
    return out;
}

Image height_from_albedo(const Image& albedo, double relief_texels, int blur_px) {
    check_finite(albedo, "height_from_albedo");
    if (!std::isfinite(relief_texels) || relief_texels < 0) {
        throw Error(str("height_from_albedo: relief ", relief_texels, " texels: must be >= 0"));
    }
    if (blur_px < 0) throw Error(str("height_from_albedo: blur ", blur_px, " px: must be >= 0"));
    const int w = albedo.width, h = albedo.height;
    std::vector<double> lum(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const double r = albedo.at(x, y, 0);
            const double g = albedo.channels >= 3 ? albedo.at(x, y, 1) : r;
            const double b = albedo.channels >= 3 ? albedo.at(x, y, 2) : r;
            lum[static_cast<size_t>(y) * w + x] = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        }
    }
    Image out(w, h, 1, ColorSpace::kData);
    const double n = (2.0 * blur_px + 1) * (2.0 * blur_px + 1);
    double lo = INFINITY, hi = -INFINITY;
    std::vector<double> blurred(lum.size());
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            double sum = 0;
            for (int dy = -blur_px; dy <= blur_px; ++dy) {
                for (int dx = -blur_px; dx <= blur_px; ++dx) {
                    const int xx = ((x + dx) % w + w) % w, yy = ((y + dy) % h + h) % h;
                    sum += lum[static_cast<size_t>(yy) * w + xx];
                }
            }
            const double v = sum / n;
            blurred[static_cast<size_t>(y) * w + x] = v;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    const double scale = hi > lo ? relief_texels / (hi - lo) : 0.0;
    for (size_t i = 0; i < blurred.size(); ++i) {
        out.pixels[i] = static_cast<float>((blurred[i] - lo) * scale);
    }
    return out;
}

Image encode_normal_map(const Image& normals) {
    INLIGHT_CHECK_EQ(normals.channels, 3);
    Image out(normals.width, normals.height, 3, ColorSpace::kData);
    for (size_t i = 0; i < normals.pixels.size(); ++i) {
        out.pixels[i] = 0.5f * (normals.pixels[i] + 1.0f);
    }
    return out;
}

Image resize_box(const Image& img, int width, int height) {
    INLIGHT_CHECK(width > 0 && height > 0) << "resize_box to " << width << "x" << height;
    Image out(width, height, img.channels, img.color_space);
    for (int oy = 0; oy < height; ++oy) {
        // Input rows whose centres (y + 0.5) fall in [oy, oy + 1) * img.height / height.
        const double a = static_cast<double>(oy) * img.height / height;
        const double b = static_cast<double>(oy + 1) * img.height / height;
        int y0 = static_cast<int>(std::ceil(a - 0.5)), y1 = static_cast<int>(std::ceil(b - 0.5));
        if (y1 <= y0) {  // enlarging: the nearest input row
            y0 = std::min(static_cast<int>(std::floor((a + b) / 2)), img.height - 1);
            y1 = y0 + 1;
        }
        for (int ox = 0; ox < width; ++ox) {
            const double c = static_cast<double>(ox) * img.width / width;
            const double d = static_cast<double>(ox + 1) * img.width / width;
            int x0 = static_cast<int>(std::ceil(c - 0.5)), x1 = static_cast<int>(std::ceil(d - 0.5));
            if (x1 <= x0) {
                x0 = std::min(static_cast<int>(std::floor((c + d) / 2)), img.width - 1);
                x1 = x0 + 1;
            }
            for (int ch = 0; ch < img.channels; ++ch) {
                double sum = 0;
                for (int y = y0; y < y1; ++y) {
                    for (int x = x0; x < x1; ++x) sum += img.at(x, y, ch);
                }
                out.at(ox, oy, ch) = static_cast<float>(sum / ((y1 - y0) * (x1 - x0)));
            }
        }
    }
    return out;
}

}  // namespace inlight::image
