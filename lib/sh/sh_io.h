// sh/sh_io.h: SH coefficient files (JSON with the convention stated, and a compact binary).
//
// Binary layout (little-endian), see docs/formats.md:
//   char[8] magic "INLSH\0\0\1"; uint32 sh_bands; uint32 channels; uint32 reserved (0);
//   float32 coeffs[count(sh_bands)][channels]  (coefficient-major: k outer, channel inner).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace inlight::sh {

/// Coefficients of one environment, with their provenance.
struct CoefficientSet {
    int sh_bands = 0;
    Eigen::MatrixXd coeffs;                 ///< count(sh_bands) x channels, radiance units
    std::vector<std::string> channel_names = {"r", "g", "b"};
    std::string color_space = "linear_srgb";
    nlohmann::json metadata = nlohmann::json::object();  ///< source, options, fit statistics
};

/// The convention block written into every JSON file (basis, index, frame, units).
nlohmann::json convention_json();

/// JSON document: convention, sh_bands, channel names, coefficients[k][channel],
/// irradiance_matrices (per channel, R&H eq. 12, when sh_bands >= 3), metadata.
nlohmann::json to_json(const CoefficientSet& set);
/// Parses a document written by to_json. Throws Error naming `source` on a malformed file.
CoefficientSet from_json(const nlohmann::json& doc, const std::string& source);

/// Writes/reads the binary form atomically. Errors name the file.
void write_binary(const std::string& path, const CoefficientSet& set);
CoefficientSet read_binary(const std::string& path);

/// Reads either form by extension (.json or .bin).
CoefficientSet read_coefficients(const std::string& path);

}  // namespace inlight::sh
