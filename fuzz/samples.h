// fuzz/samples.h: small valid inputs made by the project's own writers, for the seed corpora
// (make_seeds) and for the harnesses that need fixed files beside the fuzzed one.
#pragma once

#include <string>

#include "image/image.h"

namespace inlight::fuzz {

/// A deterministic w x h x 3 image (smooth gradients in [0, 1]), so seeds are reproducible.
image::Image gradient_image(int width, int height);

/// Writes the source files of a small fabric bundle into `src` and packs them with
/// bundle::write_bundle into `dest` (same bytes every time, so a manifest written once matches
/// a folder made again).
void make_fabric_bundle(const std::string& src, const std::string& dest);

/// Compresses a small analytic BTF (4 x 3 pixels, 3 lights, 4 views in 2 groups of 2, 2
/// components, 8-bit PNG) with btf::compress_to_folder into `dir` (same bytes every time).
void make_compressed_btf(const std::string& dir);

}  // namespace inlight::fuzz
