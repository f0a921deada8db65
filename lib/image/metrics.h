// image/metrics.h: error metrics between a test image and a reference, and error heat maps.
#pragma once

#include <string>

#include "image/image.h"

namespace inlight::image {

/// Summary of the difference between `test` and `ref` over all pixels and channels.
struct Metrics {
    double mae = 0;          ///< mean absolute error
    double rmse = 0;         ///< root mean square error
    double psnr_db = 0;      ///< 20 log10(peak / rmse), peak = max of ref (inf when rmse = 0)
    double mean_rel = 0;     ///< mean of |t - r| / max(|r|, rel_floor)
    double max_rel = 0;      ///< max of the same
    double mean_de76 = 0;    ///< only when supports_delta_e(ref), after `exposure`; else 0
    double mean_de2000 = 0;  ///< "
    double max_de2000 = 0;   ///< "
};

/// Options for compare().
struct CompareOptions {
    /// Relative errors divide by max(|ref|, rel_floor) so that black pixels do not explode.
    double rel_floor = 1e-3;
    /// Linear scale applied to both images before the Lab conversion for dE (a stated
    /// exposure: 1 maps linear 1.0 to the sRGB white).
    double exposure = 1.0;
};

/// True when compare() and delta_e2000_map() can compute CIELAB differences for `img`: 3+
/// channels (the first three are the colour, a 4th is alpha and ignored) in linear_srgb,
/// linear_rec2020 or xyz_d65. Other spaces (ACES: D60 white; raw_camera; data) get no dE.
bool supports_delta_e(const Image& img);

/// Compares two images. Throws Error when sizes, channel counts or colour spaces differ,
/// naming both values.
Metrics compare(const Image& test, const Image& ref, const CompareOptions& options = {});

/// Per-pixel relative error (max over the colour channels; alpha, the last of 2 or 4 channels,
/// is left out), one channel, tagged data. Throws Error like compare() on mismatches.
Image relative_error_map(const Image& test, const Image& ref, double rel_floor = 1e-3);
/// Per-pixel CIEDE2000 after `exposure`, one channel, tagged data. Throws Error unless
/// supports_delta_e() (3+ channels in a colour space with a known XYZ conversion).
Image delta_e2000_map(const Image& test, const Image& ref, double exposure = 1.0);

/// Colours a one-channel image with a perceptual colour map (0 -> dark, max_value -> bright),
/// as linear_srgb RGB, ready for write_image to PNG. The map is matplotlib's viridis sampled at
/// 9 points, interpolated linearly in sRGB-encoded values; values are clamped to [0, max_value]
/// and NaN shows as the top colour. Throws Error unless `scalar` has 1 channel and
/// max_value > 0.
Image heat_map(const Image& scalar, double max_value);

}  // namespace inlight::image
