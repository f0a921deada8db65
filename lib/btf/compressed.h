// btf/compressed.h: the files of a PCA-compressed BTF (written by btf-pca) and their decoder.
//
// A folder holds:
//   btf-pca.json  the manifest: image size, colour space of the model ("linear_srgb", or
//                 "srgb_encoded" for a model fitted to sRGB-encoded values, FitSpace::kSrgb:
//                 the sum below is then an encoded value, decoded with the sRGB curve after the
//                 sum; "cielab_d65" for a model fitted to CIELAB, FitSpace::kLab: the three
//                 channels' sums are L*, a*, b*, converted to linear_srgb after the sum), light
//                 and view directions
//                 (degrees), and per view group its views, its mean image and component images
//                 (file, scale, offset, bytes, energy), and where its V sits in weights.bin; then
//                 "stream": the components [group, component] in order of importance across
//                 groups (energy removed, largest first), the order a server sends them in after
//                 the manifest, weights.bin and the mean images ("codec": "thesis", the BTF
//                 thesis' method: component 0 of every group, then component 1, ...; each group
//                 then has "thesis": its factor_u, factor_v and sigma_digits, which its scales
//                 and offsets already hold; "view_grouping": "neighbours" or "consecutive").
//   weights.bin   per group its V (N x C, column-major), N = 3 * n_lights * views with column =
//                 (view_in_group * n_lights + light) * 3 + channel; "weights"."dtype" says how:
//                 float32_le (default), float16_le, or uint8 with value = v_offset + v_scale *
//                 code per component (its manifest entry's "v_scale", "v_offset"); uint8_deflate:
//                 those codes, each column one zlib stream of its entry's "v_bytes".
//   g###-mean.png, g###-c##.png  one grey image (width x height) per column of L = [m | U Sigma]:
//                 8-bit codes with value = offset + scale * code, or half/float EXR (scale 1,
//                 offset 0) with --format exr-half / exr-float.
// A pixel's value for (light, view, channel) is mean[p] + sum_c basis_c[p] * V[column, c]
// (for "srgb_encoded": srgb_decode of that sum clamped to [0, 1]; for "cielab_d65": the
// channels' sums are one Lab triple, converted by image::linear_srgb_from_lab and clamped to
// [0, 1]).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "btf/dataset.h"

namespace inlight::btf {

/// How component images are stored.
enum class ComponentEncoding { kPng8, kExrHalf, kExrFloat };
std::string to_string(ComponentEncoding e);  ///< "png", "exr-half", "exr-float"
/// Inverse of to_string; throws UsageError naming the value otherwise.
ComponentEncoding component_encoding_from_string(const std::string& name);
/// The file extension of an encoding ("png" or "exr").
std::string extension_of(ComponentEncoding e);

/// The values the PCA is fitted to (and the manifest's "color_space").
enum class FitSpace {
    /// linear_srgb (default): the model is linear in radiance, so a weighted sum of images
    /// (angular interpolation, environment shading) folds into C coefficients per group.
    kLinear,
    /// sRGB-encoded values in [0, 1] (the 8-bit files' codes / 255, what the thesis' PCA sees):
    /// squared error weighs dark and bright regions more as they look. The decoder applies the
    /// sRGB curve per image after the sum, so weighted sums no longer fold (combine decodes
    /// every image it sums).
    kSrgb,
    /// CIELAB (D65 white, L* in [0, 100]) of each colour: the three channel columns of an image
    /// hold L*, a*, b*, so squared error is Delta E 1976 squared, the metric of the thesis'
    /// Table 7.1 (MAE per Lab channel). The decoder converts each pixel's Lab sum to linear_srgb
    /// (clamped to [0, 1]); weighted sums do not fold (as kSrgb).
    kLab,
};
std::string to_string(FitSpace f);            ///< "linear", "srgb", "lab"
/// Inverse of to_string; throws UsageError naming the value otherwise.
FitSpace fit_space_from_string(const std::string& name);
/// The manifest's "color_space" of a model fitted in `f`: "linear_srgb", "srgb_encoded" or
/// "cielab_d65".
std::string manifest_color_space(FitSpace f);

/// How V is stored in weights.bin (WeightsFormat::kUint8: each column's own offset and scale, as
/// the components' images; kUint8Deflate: the same codes, each column one zlib stream (RFC 1950)
/// of "v_bytes" bytes, the columns of a group one after another from its weights_offset_bytes).
enum class WeightsFormat { kFloat32, kFloat16, kUint8, kUint8Deflate };
std::string to_string(WeightsFormat f);  ///< "float32", "float16", "uint8", "uint8-deflate"
/// Inverse of to_string; throws UsageError naming the value otherwise.
WeightsFormat weights_format_from_string(const std::string& name);
int bytes_per_weight(WeightsFormat f);          ///< decoded: 4, 2, 1, 1
/// The manifest's dtype: float32_le, float16_le, uint8, uint8_deflate.
std::string weights_dtype(WeightsFormat f);
/// True for the 8-bit formats (a scale and offset per column).
inline bool is_uint8(WeightsFormat f) { return f == WeightsFormat::kUint8 || f == WeightsFormat::kUint8Deflate; }

/// Appends one column of V (n finite values) to `out` in format `f`, writes the values a decoder
/// will read to `decoded` and the column's scale and offset (value = offset + scale * code;
/// 1 and 0 unless 8-bit) to `scale` and `offset`. 8-bit: codes of step range / 255, or
/// `min_step` when larger (quantize8). Returns the bytes appended.
uint64_t encode_weights_column(const float* values, int64_t n, WeightsFormat f, std::string& out, float* decoded,
                               float& scale, float& offset, float min_step = 0);

/// One stored column of L.
struct StoredImage {
    std::string file;  ///< file name inside the folder
    float scale = 1;   ///< value = offset + scale * stored (stored: code / 255 for PNG)
    float offset = 0;
    uint64_t bytes = 0;  ///< file size
};

/// Encodes one column of P = width * height values (finite) as an image file's bytes named
/// `file`; fills `meta` (not `bytes`) and writes the values a decoder will read to `decoded`.
/// kPng8: codes of step range / 255, or `min_step` when larger (quantize8).
std::string encode_column(const float* values, int width, int height, ComponentEncoding e,
                          const std::string& file, StoredImage& meta, float* decoded, float min_step = 0);

/// Encodes P = width * height given 8-bit codes as a grey PNG named `file` that stands for the
/// values offset + scale * code (meta.scale = 255 scale, the PNG's stored value being code / 255);
/// fills `meta` (not `bytes`) and writes those values to `decoded`. encode_column's kPng8 after
/// its quantisation, and the BTF thesis' packing (btf/quantize.h) with its own codes.
std::string encode_codes(const uint8_t* codes, int width, int height, float scale, float offset,
                         const std::string& file, StoredImage& meta, float* decoded);

/// Appends n given uint8 codes of a column of V to `out` (WeightsFormat::kUint8: value = offset +
/// scale * code) and writes those values to `decoded`.
void append_weight_codes(const uint8_t* codes, int64_t n, float scale, float offset, std::string& out,
                         float* decoded);

/// A compressed BTF read back: every group's mean, basis and V in memory (float).
class CompressedBtf : public BtfSource {
  public:
    /// Reads the manifest and every file it names. Throws Error naming the file for a missing
    /// or malformed manifest, a missing, truncated or wrongly sized image, or a short weights.bin.
    static std::unique_ptr<CompressedBtf> open(const std::string& dir);

    const BtfShape& shape() const override { return m_shape; }
    /// The decompressed image with every component.
    image::Image read_image(int light, int view) const override;
    /// The image as a client has it after the first `sent` components of the stream (the means
    /// always): the progressive preview. sent >= stream_length() gives read_image.
    image::Image read_image_streamed(int light, int view, int64_t sent) const;
    /// The weighted sum of images (BtfSource::combine) computed in the compressed domain: per
    /// group and channel the terms' weights fold into C coefficients (sum_t w_t V[row_t]), so
    /// each pixel costs C multiply-adds per group touched, whatever the number of terms. With
    /// `sent` only the first `sent` components of the stream are used (read_image_streamed).
    image::Image combine(const std::vector<ImageTerm>& terms) const override;
    image::Image combine_streamed(const std::vector<ImageTerm>& terms, int64_t sent) const;
    int64_t stream_length() const { return static_cast<int64_t>(m_stream.size()); }
    int group_of_view(int view) const { return m_group_of_view[static_cast<size_t>(view)]; }
    int components(int group) const { return static_cast<int>(m_groups[static_cast<size_t>(group)].basis.cols()); }
    const nlohmann::json& manifest() const { return m_manifest; }
    FitSpace fit_space() const { return m_fit_space; }
    /// Group g's mean (pixel_count values) and basis (pixel_count x C): an image channel is
    /// mean x m_0 + basis x m for coefficients from lighting_matrix().
    const Eigen::VectorXf& group_mean(int g) const { return m_groups[static_cast<size_t>(g)].mean; }
    const Eigen::MatrixXf& group_basis(int g) const { return m_groups[static_cast<size_t>(g)].basis; }

    /// The app's per-frame lighting folded into view `view`'s group (btf/sh_lighting.h): with
    /// light weights W = A c of one channel (A: n_lights x J, e.g. sh_light_weight_matrix),
    /// channel `channel` of the shaded image is group_mean x (M.row(0) c) + group_basis x
    /// (M.bottomRows(C) c) for the returned M = [1^T; V_view,channel^T] A / irradiance_w_m2,
    /// (1 + C) x J. So a frame costs (1 + C) x J multiply-adds per colour and view (a stream
    /// prefix of N components uses the first 1 + N rows). Linear fit space only (the sRGB and
    /// Lab models do not fold: Error); A's rows must be n_lights and irradiance > 0 (Error).
    Eigen::MatrixXd lighting_matrix(int view, int channel, const Eigen::MatrixXd& a,
                                    double irradiance_w_m2) const;

  private:
    struct Group {
        std::vector<int> views;
        Eigen::VectorXf mean;
        Eigen::MatrixXf basis;    // P x C
        Eigen::MatrixXf weights;  // N x C
    };
    /// Row of the red channel of image (light, view) in its group's V (green and blue follow).
    int64_t weights_row(int light, int view) const {
        return (int64_t(m_index_in_group[static_cast<size_t>(view)]) * m_shape.n_lights() + light) * 3;
    }
    image::Image decode(int light, int view, const std::vector<int>& components_per_group) const;
    std::vector<int> components_after(int64_t sent) const;
    image::Image combine_with(const std::vector<ImageTerm>& terms, const std::vector<int>& per_group) const;

    BtfShape m_shape;
    FitSpace m_fit_space = FitSpace::kLinear;
    nlohmann::json m_manifest;
    std::vector<Group> m_groups;
    std::vector<int> m_group_of_view, m_index_in_group;
    std::vector<std::pair<int, int>> m_stream;
};

}  // namespace inlight::btf
