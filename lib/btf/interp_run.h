// btf/interp_run.h: `btf-pca interpolate INPUT --pairs PAIRS -o DIR`: a BTF, raw (folder or Bonn zip)
// or compressed (a btf-pca output folder), evaluated at arbitrary (light, view) pairs by angular
// interpolation (btf/interp.h), written as images in UBO2003 naming, and, given a capture of the
// same pairs (`render capture-btf FABRIC --btf-pairs PAIRS`), compared with that truth.
//
// Errors per pair, then averaged over the pairs (each pair weighs the same):
//  - rmse: linear_srgb values (the images' units: radiance at the capture's irradiance, or btf);
//    rel_rmse = rmse / mean of the truth; mean_rel_diff = |mean(test) - mean(truth)| / mean(truth),
//    the error of the image's mean (what per-pixel noise and parallax leave out);
//  - mae_lab (per channel, averaged over L, a, b, as the thesis' Table 7.1), delta_e2000_mean and
//    rmse_rgb8 (8-bit sRGB codes) on values clamped to [0, 1] (display-referred, as Table 7.1).
#pragma once

#include <memory>
#include <string>

#include "btf/dataset.h"
#include "btf/interp.h"
#include "core/report.h"
#include "image/image.h"

namespace inlight::btf {

/// A btf-pca output folder (it holds btf-pca.json) as a CompressedBtf, anything else through
/// FolderBtf::open with `options`.
std::unique_ptr<BtfSource> open_raw_or_compressed(const std::string& path, const OpenOptions& options);

/// Table 7.1-style errors of `test` against `truth` (same size, 3 channels; Error otherwise).
struct ImageErrors {
    double rmse = 0, rel_rmse = 0, mean_rel_diff = 0, mae_lab = 0, delta_e2000_mean = 0, rmse_rgb8 = 0;
};
ImageErrors image_errors(const image::Image& test, const image::Image& truth);

struct InterpRunOptions {
    std::string input;   ///< raw BTF folder or zip, or a btf-pca output folder
    OpenOptions open;    ///< how a raw BTF is read
    std::string pairs;   ///< (light, view) pairs (dome.h read_direction_pairs)
    std::string output;  ///< folder: one float EXR per pair, UBO2003 names, a folder per view
    InterpScheme scheme = InterpScheme::kDelaunay;
    /// "" or a folder holding every pair's image in UBO2003 naming (EXR or PNG; a capture of
    /// the pairs), to compare with.
    std::string truth;
};

/// The tool: reads the pairs (Error naming the file and line), opens the BTF, interpolates
/// every pair, writes the images and, with a truth, the errors (report metrics "interpolation":
/// per pair the measured directions used, their weights and how far a query outside the
/// measured region was moved; the mean errors over the pairs).
void run_interpolation(const InterpRunOptions& options, Report& report);

}  // namespace inlight::btf
