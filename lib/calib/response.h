// calib/response.h: radiometric calibration of an 8-bit camera. Debevec and Malik 1997,
// "Recovering high dynamic range radiance maps from photographs": the response curve g(z) =
// ln(exposure) of each code z is recovered from a bracket of exposures of a still scene by
// weighted least squares with a smoothness term (section 2.1, eq. 3, hat weighting eq. 4), and
// the bracket is merged to radiance (eq. 6). For a single 8-bit frame (what the app sees) the
// curve gives linear radiance, and saturated pixels are marked with a lower bound of the light
// they hide (a lamp clipped at 255 is the common case).
//
// Units: radiance is relative: exp(g(z)) = radiance * exposure_s, and g(128) = 0 for every
// channel, so code 128 at 1 s is radiance 1 in each channel. The channels' relative scale (white
// balance) is therefore the camera's own at mid grey; Debevec-Malik cannot recover it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace inlight::calib {

/// Number of codes of an 8-bit camera.
inline constexpr int kCodes = 256;
/// The code whose log exposure is fixed at 0.
inline constexpr int kReferenceCode = 128;

/// A response curve per channel.
struct ResponseCurve {
    std::vector<std::string> channel_names;                ///< "r", "g", "b" (or "y" for grey)
    std::vector<std::array<double, kCodes>> log_exposure;  ///< g per channel, natural log

    int channels() const { return static_cast<int>(log_exposure.size()); }
    /// Relative radiance of `code` in `channel` at `exposure_s`: exp(g(code)) / exposure_s.
    double radiance(int channel, int code, double exposure_s) const;
};

/// Debevec-Malik weighting: w(z) = z for z <= 127, 255 - z above (eq. 4 with Zmin = 0,
/// Zmax = 255), so the end codes, clipped or black, carry no weight.
double hat_weight(int code);

struct ResponseOptions {
    /// Weight of the smoothness term (lambda in eq. 3; the hat weights reach 128).
    double lambda = 50;
    /// Pixel samples per channel; 0 = automatic: 4 x 256 / (exposures - 1), within [64, 1024]
    /// (eq. 3 needs samples x (exposures - 1) > 255).
    int samples = 0;
    /// Seed for choosing samples among pixels of equal code (deterministic).
    uint64_t seed = 1;
};

struct ResponseFit {
    ResponseCurve curve;
    int samples = 0;                  ///< per channel
    std::vector<double> fit_rms_log;  ///< per channel: weighted RMS of g(Z) - ln E - ln dt
};

/// Recovers g from `codes` (one image per exposure, values 0..255 integers, all the same size
/// and channel count) and their exposure times (seconds, positive, at least two distinct).
/// Samples are stratified by the code in the middle exposure so every code range is
/// represented. Throws Error on bad input (naming what is wrong).
ResponseFit recover_response(const std::vector<image::Image>& codes,
                             const std::vector<double>& exposures_s,
                             const ResponseOptions& options = {});

/// Radiance of a bracket (eq. 6): per pixel and channel the hat-weighted mean of
/// g(Z) - ln dt over exposures. Where every exposure is clipped (weight 0 at code 255) the
/// shortest exposure's code-255 value is used and the pixel is marked saturated; where every
/// exposure is black, the longest exposure's code-0 value.
struct MergeResult {
    image::Image radiance;   ///< linear, relative units, ColorSpace::kRawCamera
    image::Image saturated;  ///< 1 channel, 1 where clipped in every exposure
    int64_t saturated_pixels = 0;
};
MergeResult merge_radiance(const std::vector<image::Image>& codes,
                           const std::vector<double>& exposures_s, const ResponseCurve& curve);

/// One 8-bit frame to radiance, for envmap-project.
struct FrameRadiance {
    image::Image radiance;   ///< linear, relative units (see top), ColorSpace::kRawCamera
    image::Image saturated;  ///< 1 channel: 1 where any channel's code >= saturation_code
    int64_t saturated_pixels = 0;
    double saturated_fraction = 0;  ///< of the counted pixels (inside the mask, if given)
    /// Per channel, sum over saturated pixels of radiance(saturation code) x solid angle (sr;
    /// 1 per pixel without a solid-angle map): the least light the clipped pixels hide, since
    /// their true radiance is at least that of the code they clipped at.
    std::vector<double> clipped_light_lower_bound;
    /// Per channel, the same sum over the unsaturated pixels.
    std::vector<double> unclipped_light;
};

/// Converts `codes` (values 0..255, as many channels as the curve) taken at `exposure_s`.
/// Pixels where `mask` (optional, 1 channel) is 0 are skipped (radiance 0, not counted).
/// `solid_angle_sr` (optional, 1 channel) weights the light sums. Pixels with a channel at or
/// above `saturation_code` are saturated; their radiance is the lower bound radiance(255).
/// Throws Error on size or channel mismatches or codes outside 0..255.
FrameRadiance radiance_from_frame(const image::Image& codes, const ResponseCurve& curve,
                                  double exposure_s, const image::Image* solid_angle_sr = nullptr,
                                  const image::Image* mask = nullptr, int saturation_code = 255);

/// Reads 8-bit images as codes (0..255, not sRGB-decoded). Throws Error naming the file if it
/// is not 8 bits per channel.
image::Image read_codes(const std::string& path);

/// Response file: JSON {"format": "inlight_response", "version": 1, "method":
/// "debevec_malik_1997", "channels": [...], "g": [[256 values] per channel], "reference_code":
/// 128, "lambda", "samples", "exposures_s", "images", "fit_rms_log"}. Written atomically.
void write_response(const std::string& path, const ResponseFit& fit, double lambda,
                    const std::vector<double>& exposures_s, const std::vector<std::string>& images);
/// Reads a response file. Throws Error naming the file on a bad format.
ResponseCurve read_response(const std::string& path);

}  // namespace inlight::calib
