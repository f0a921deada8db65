#include "render/mip.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "image/color.h"
#include "render/material.h"

namespace inlight::render {

std::vector<Eigen::Vector2i> mip_sizes(int width, int height) {
    std::vector<Eigen::Vector2i> sizes{{width, height}};
    while (sizes.back().x() > 1 || sizes.back().y() > 1) {
        const Eigen::Vector2i& s = sizes.back();
        sizes.push_back({std::max(1, s.x() / 2), std::max(1, s.y() / 2)});
    }
    return sizes;
}

std::vector<MipRect> mip_atlas_levels(int width, int height) {
    const std::vector<Eigen::Vector2i> sizes = mip_sizes(width, height);
    std::vector<MipRect> rects;
    int column_y = 0;
    for (size_t k = 0; k < sizes.size(); ++k) {
        rects.push_back({k == 0 ? 0 : width, k == 0 ? 0 : column_y, sizes[k].x(), sizes[k].y()});
        if (k > 0) column_y += sizes[k].y();
    }
    return rects;
}

Eigen::Vector2i mip_atlas_size(const std::vector<MipRect>& levels) {
    Eigen::Vector2i size(0, 0);
    for (const MipRect& r : levels) size = size.cwiseMax(Eigen::Vector2i(r.x + r.width, r.y + r.height));
    return size;
}

namespace {

/// Weights of the level-0 texels under texel i of a level of n texels over n0, footprint
/// [i n0 / n, (i + 1) n0 / n), normalised by its length: kBox, the covered length of [j, j +
/// 1); kBilinear, the integral over the footprint of texel j's tent (its share of the bilinear
/// reconstruction, centre j + 0.5, half-width 1), wrapping.
struct Footprint {
    std::vector<int> texels;  ///< level-0 indices, wrapped into [0, n0)
    std::vector<double> weights;
};

/// Integral of the unit tent from -inf to u.
double tent_cdf(double u) {
    if (u <= -1) return 0;
    if (u < 0) return 0.5 * (u + 1) * (u + 1);
    if (u < 1) return 1 - 0.5 * (1 - u) * (1 - u);
    return 1;
}

std::vector<Footprint> footprints(int n0, int n, MipFilter filter) {
    std::vector<Footprint> out(static_cast<size_t>(n));
    const double s = static_cast<double>(n0) / n;
    for (int i = 0; i < n; ++i) {
        const double a = i * s, b = (i + 1) * s;
        const bool tent = filter == MipFilter::kBilinear;
        const int j0 = static_cast<int>(std::floor(a)) - (tent ? 1 : 0);
        const int j1 = static_cast<int>(std::ceil(b)) + (tent ? 1 : 0);
        for (int j = j0; j < j1; ++j) {
            const double w = tent ? tent_cdf(b - j - 0.5) - tent_cdf(a - j - 0.5)
                                  : std::min<double>(b, j + 1) - std::max<double>(a, j);
            if (w <= 0) continue;
            out[i].texels.push_back(((j % n0) + n0) % n0);
            out[i].weights.push_back(w / s);
        }
    }
    return out;
}

float quantize(float v, TextureKind kind) {
    const float e = kind == TextureKind::kColor ? image::srgb_encode(v) : v;
    const float q = static_cast<float>(std::clamp(std::lround(e * 255.0f), 0L, 255L)) / 255.0f;
    return kind == TextureKind::kColor ? image::srgb_decode(q) : q;
}

}  // namespace

MipAtlas build_mip_atlas(const image::Image& src, TextureKind kind, bool quantize_8bit,
                         MipFilter filter) {
    if (src.width < 1 || src.height < 1 || src.channels < 1)
        throw Error("mip chain: the texture is empty");
    MipAtlas mip;
    mip.levels = mip_atlas_levels(src.width, src.height);
    const Eigen::Vector2i size = mip_atlas_size(mip.levels);
    mip.atlas = image::Image(size.x(), size.y(), 3, src.color_space);
    for (size_t k = 0; k < mip.levels.size(); ++k) {
        const MipRect& r = mip.levels[k];
        const Eigen::Vector2i s(r.width, r.height);
        const std::vector<Footprint> fx = footprints(src.width, s.x(), filter);
        const std::vector<Footprint> fy = footprints(src.height, s.y(), filter);
        // Separable box: rows first (h0 x w_k), then columns.
        std::vector<double> rows(static_cast<size_t>(src.height) * s.x() * 3, 0.0);
        for (int y = 0; y < src.height; ++y) {
            for (int i = 0; i < s.x(); ++i) {
                for (size_t q = 0; q < fx[i].weights.size(); ++q) {
                    const int x = fx[i].texels[q];
                    for (int c = 0; c < 3; ++c) {
                        rows[(static_cast<size_t>(y) * s.x() + i) * 3 + c] +=
                            fx[i].weights[q] * src.at(x, y, std::min(c, src.channels - 1));
                    }
                }
            }
        }
        for (int j = 0; j < s.y(); ++j) {
            for (int i = 0; i < s.x(); ++i) {
                for (int c = 0; c < 3; ++c) {
                    double v = 0;
                    for (size_t q = 0; q < fy[j].weights.size(); ++q) {
                        const int y = fy[j].texels[q];
                        v += fy[j].weights[q] * rows[(static_cast<size_t>(y) * s.x() + i) * 3 + c];
                    }
                    float f = static_cast<float>(v);
                    if (k == 0) f = src.at(i, j, std::min(c, src.channels - 1));  // the source, exact
                    else if (quantize_8bit) f = quantize(f, kind);
                    mip.atlas.at(r.x + i, r.y + j, c) = f;
                }
            }
        }
    }
    return mip;
}

Eigen::Vector3d sample_level(const MipAtlas& mip, int level, const Eigen::Vector2d& uv) {
    const MipRect& r = mip.levels.at(static_cast<size_t>(level));
    return sample_texture_rect(mip.atlas, r.x, r.y, r.width, r.height, uv);
}

double mip_lod(const Eigen::Vector2d& duv_dx, const Eigen::Vector2d& duv_dy,
               const Eigen::Vector2i& size) {
    const Eigen::Vector2d s = size.cast<double>();
    const double rho = std::max(duv_dx.cwiseProduct(s).norm(), duv_dy.cwiseProduct(s).norm());
    return rho > 0 ? std::log2(rho) : -std::numeric_limits<double>::infinity();
}

double box_matched_lod(double gl_lod) {
    const double rho2 = std::exp2(2 * gl_lod);  // 0 for -inf
    return 0.5 * std::log2(rho2 / 3 + 2.0 / 3);
}

Eigen::Vector3d sample_trilinear(const MipAtlas& mip, const Eigen::Vector2d& uv, double lod) {
    const int last = static_cast<int>(mip.levels.size()) - 1;
    const double l = std::clamp(lod, 0.0, static_cast<double>(last));
    const int l0 = std::min(static_cast<int>(std::floor(l)), last);
    const double f = l - l0;
    const Eigen::Vector3d a = sample_level(mip, l0, uv);
    if (f <= 0 || l0 == last) return a;
    return (1 - f) * a + f * sample_level(mip, l0 + 1, uv);
}

double vmf_inv_kappa(double r) {
    r = std::clamp(r, 0.0, 1.0);
    if (r <= 0) return std::numeric_limits<double>::infinity();
    return (1 - r * r) / (r * (3 - r * r));
}

double vmf_band_factor(int l, double inv_kappa) {
    if (!std::isfinite(inv_kappa)) return l == 0 ? 1.0 : 0.0;
    return std::exp(-0.5 * l * (l + 1) * inv_kappa);
}

}  // namespace inlight::render
