// btf/synthetic.h: an analytic BTF of known rank, for tests and benchmarks (truth at any light
// and view direction, any size, no files), and a writer of any BTF source as a UBO2003 folder.
//
// The analytic BTF is a spatially varying BRDF times the light's cosine, a sum of `rank`
// separable terms: btf(x, l, v, c) = sum_r a_r(x) b_r(l, v, c), with smooth, tileable spatial
// maps a_r in [0.1, 0.9] and angular lobes b_r: Lambert, a Blinn-Phong highlight, a grazing sheen,
// a retro-reflection and two tilted lobes, each with its own colour. The full BTF matrix (pixels x
// light-view-channel) therefore has rank <= rank, and mean-centring rows keeps it so. Values are
// reflectance-like, below 0.95 at scale 1; `scale` > 1 pushes highlights past 1 (8-bit
// saturation).
#pragma once

#include <string>

#include "btf/dataset.h"

namespace inlight::btf {

struct AnalyticBtfOptions {
    int width = 32;   ///< pixels, >= 1
    int height = 32;  ///< pixels, >= 1
    std::vector<Direction> lights = ubo2003_dome();
    std::vector<Direction> views = ubo2003_dome();
    int rank = 4;        ///< separable terms, 1..6
    double scale = 1.0;  ///< multiplies every value, > 0
    uint64_t seed = 1;   ///< spatial maps' phases and frequencies
};

/// An analytic BTF (see the file comment). Thread-safe.
class AnalyticBtf : public BtfSource {
  public:
    /// Precondition: options in range (checked).
    explicit AnalyticBtf(const AnalyticBtfOptions& options);
    const BtfShape& shape() const override { return m_shape; }
    image::Image read_image(int light, int view) const override;
    /// The image at any light and view direction (unit vectors in the sample frame, z >= 0).
    image::Image render(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;
    /// One value: pixel (x, y), channel c.
    double value(int x, int y, const Eigen::Vector3d& light, const Eigen::Vector3d& view,
                 int c) const;
    /// The angular lobe b_r(l, v, c) and the spatial map a_r at pixel (x, y).
    double lobe(int r, const Eigen::Vector3d& light, const Eigen::Vector3d& view, int c) const;
    double spatial(int r, int x, int y) const;

  private:
    AnalyticBtfOptions m_options;
    BtfShape m_shape;
    std::vector<float> m_maps;  // rank x height x width
    double m_norm = 1;          // keeps values below 0.95 at scale 1
};

/// How write_ubo2003 stores images.
struct UboWriteOptions {
    std::string extension = "png";  ///< "png", "jpg" or "exr"
    int bits = 8;                   ///< png: 8 or 16; exr: 16 (half) or 32
    bool per_view_folders = true;   ///< one folder per view ("tv030_pv090/"), as Bonn ships
    std::string prefix;             ///< put before each stem ("wool " -> "wool tl015 ...png")
};

/// The path of one image under `dir`: [<view folder>/]<prefix><stem>.<extension>.
std::string ubo2003_path(const std::string& dir, const Direction& light, const Direction& view,
                         const UboWriteOptions& options);

/// Writes every image of `source` under `dir` in UBO2003 naming: integer files sRGB-encoded,
/// EXR linear. Images are written in parallel, each atomically. Throws Error on failure.
void write_ubo2003(const BtfSource& source, const std::string& dir,
                   const UboWriteOptions& options = {});

}  // namespace inlight::btf
