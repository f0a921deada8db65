// btf/pca_run.h: what the btf-pca tool does, as one library call: compress a BTF group by group,
// store the components (btf/compressed.h), and measure the result the way the BTF thesis'
// Table 7.1 does, plus the streaming curve and the thesis' packing beside ours.
//
// Errors are measured on the stored (quantised) model against the images read:
//  - exactly over every sample: RMSE and MAE in linear_srgb, and the RMSE after each number of
//    components sent in stream order (the streaming curve);
//  - on a fixed, evenly strided subset of (pixel, light, view) colour triples (all of them when
//    there are at most `color_samples`): MAE in CIELAB (per channel, averaged over L, a, b, as
//    the thesis computes it), mean Delta E 2000, and MAE and RMSE of 8-bit sRGB codes (0..255,
//    the thesis' "RGB" units), for our storage and for the thesis' packing. Reconstructions are
//    clamped to [0, 1] for these display-referred figures.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "btf/compressed.h"
#include "btf/pca.h"
#include "core/report.h"

namespace inlight::btf {

/// What a run writes: this project's codec, or the BTF thesis' method as the baseline every
/// comparison shows beside it.
enum class Codec {
    /// Every option as given: groups of k neighbouring views, components on their own range,
    /// streamed by the energy they remove across groups.
    kInlight,
    /// The thesis' method as it describes it (sections 4.3 and 6.1): groups of k consecutive
    /// views (ViewGrouping::kConsecutive), the PCA of the images' 8-bit sRGB values / 255
    /// (FitSpace::kSrgb, least squares), C components per group, its packing (btf/quantize.h,
    /// pack_thesis: U and V as f(x) = (x + 1) / 2 after a power-of-ten factor per matrix, Sigma
    /// as four digits, the mean as an 8-bit image), V in weights.bin as uint8, and the stream
    /// component by component, each covering every group ("each principal component C_i ...
    /// covers all the angular domain"). The files are the folder format of btf/compressed.h
    /// (scale and offset express the packing exactly), so every decoder, table and shader reads
    /// them. Needs fit_space kSrgb, grouping kConsecutive, weights_format kUint8, encoding kPng8,
    /// quant_noise 0, least squares and no error budget (UsageError naming what differs).
    kThesis,
};
std::string to_string(Codec c);  ///< "inlight", "thesis"
/// Inverse of to_string; throws UsageError naming the value otherwise.
Codec codec_from_string(const std::string& name);

struct PcaRunOptions {
    Codec codec = Codec::kInlight;
    std::string input;   ///< BTF folder or zip file (FolderBtf::open)
    std::string output;  ///< output folder (created; files as in btf/compressed.h)
    OpenOptions open;
    PcaOptions pca;
    ComponentEncoding encoding = ComponentEncoding::kPng8;
    /// The values the PCA is fitted to (btf/compressed.h). With kSrgb the exact error figures
    /// (rmse_linear, mae_linear, the streaming curve, --max-rmse) are in sRGB-encoded units
    /// (metrics.error_space says which); the display-referred figures (CIELAB, dE2000, 8-bit)
    /// decode the model first and mean the same in both spaces.
    FitSpace fit_space = FitSpace::kLinear;
    /// Quantisation of the component images (kPng8) by one step per group instead of each
    /// column's range / 255: step^2 = 12 F E / (C P), E the group's unquantised residual energy
    /// after its C components, so the rounding of its C columns (P values each, a V column of
    /// unit norm) adds about F E to the error; a column whose range / 255 is larger keeps that.
    /// Small components then use few codes, which PNG stores in fewer bytes. 0 = off (every
    /// column on 256 levels). The mean image keeps its own range / 255. With weights_format
    /// kUint8Deflate, V's column c is rounded likewise with d^2 = 12 F E / (C N |b_c|^2), |b_c|
    /// the norm of its component image (adding about F E again), and deflate stores the few
    /// codes in few bytes.
    double quant_noise = 0;
    /// How V is stored (weights.bin); the errors are measured with the stored V.
    WeightsFormat weights_format = WeightsFormat::kFloat32;
    int64_t color_samples = int64_t(1) << 20;  ///< colour triples for the CIELAB/8-bit figures
    /// Also measure the stored model cut to each of these component counts (a prefix of every
    /// group's components, as a client holding that many has): the rows of the Table 7.1-style
    /// table ("table" in the metrics). Counts above a group's C use all of its components.
    /// A row's bytes are those of the files a run with that C writes: the means, its components'
    /// images, their V and the manifest listing only them ("manifest_bytes").
    /// Beside each row, "table_equal_bytes": the longest prefix of the stream (components by
    /// energy across groups, as a client receives them) whose bytes without the manifest (means,
    /// the sent components' images and their V columns) do not exceed that row's ("byte_budget"),
    /// i.e. C chosen per group by one global error budget at the row's byte count; with the
    /// components each group then has and the manifest of that model.
    std::vector<int> table_components;
    /// A second BTF of the same shape (e.g. an independent capture of the same fabric): the
    /// input and every table row are also measured against it on the same colour triples
    /// ("reference" and each row's "vs_reference" in the metrics). Against an independent
    /// capture with the same noise the input's error is the noise floor times sqrt(2) in RMSE.
    /// "" = none.
    std::string reference;
    /// Memory budget for one group (its fit and its measurement, btf::fit_memory_bytes plus
    /// the stored copies and a reference block), bytes: a group whose in-core estimate exceeds
    /// it is fitted out of core (fit_group_streamed) with the most views per block that fit, and
    /// measured by streaming its views once more. 0 = half the machine's physical memory. A
    /// budget that even one view per block exceeds is a UsageError naming --max-memory-mib.
    /// pca.stream_views > 0 forces that block size (the budget is still checked).
    uint64_t max_memory_bytes = 0;
    /// The irradiance the source's images were captured under (image = btf x E, W m^-2;
    /// `render capture-btf`'s capture.json), written to btf-pca.json as "irradiance_w_m2" so
    /// that what lights the compressed BTF later (btf-pca export-gles) divides by the same E;
    /// 0 = unknown (not written). run_pca reads it from the input folder's capture.json.
    double irradiance_w_m2 = 0;
};

/// Compresses `source` into options.output and returns the metrics (also the report's). Every
/// file goes through fs::write_atomic, so inside app::run the folder appears whole or not at
/// all. `input_stored_bytes` is the input's storage (0 when unknown): the ratio against it is
/// reported. `reference` (may be null): the BTF of options.reference, read one view group at a
/// time beside the input; its shape must equal the input's (Error naming options.reference).
/// Throws Error on failure.
nlohmann::json compress_to_folder(const BtfSource& source, const PcaRunOptions& options,
                                  uint64_t input_stored_bytes, Report* report = nullptr,
                                  const BtfSource* reference = nullptr);

/// The tool: declares input and outputs (an output folder that is the input, or inside a zip's
/// path, is a UsageError), opens the BTF, compress_to_folder, and fills the report's metrics.
void run_pca(const PcaRunOptions& options, Report& report);

}  // namespace inlight::btf
