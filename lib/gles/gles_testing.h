// gles/gles_testing.h: the tables, materials and variants the gles tests share.
#pragma once

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "brdf/table.h"
#include "gles/export.h"

namespace inlight::gles::testing {

/// A table on `grid` with coefficients uniform in [lo, hi) from a fixed seed: the shader must
/// reproduce whatever the table holds, so its values need not come from a bake (tested there).
inline brdf::Table random_table(const std::string& grid, int sh_bands, int channels,
                                unsigned seed, float lo = -0.2f, float hi = 0.6f) {
    brdf::Table t;
    t.grid = brdf::parse_grid(grid);
    t.sh_bands = sh_bands;
    t.channels = channels;
    t.resize();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    for (float& c : t.coeffs) c = u(rng);
    return t;
}

/// Every variant of a table with `table_bands` bands: both versions, both modes, bands 3 ..
/// table_bands (seed: 3), both precisions.
inline std::vector<Variant> all_variants(int table_bands) {
    std::vector<Variant> out;
    for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        for (Precision prec : {Precision::kHighp, Precision::kMediump}) {
            for (int b = 3; b <= table_bands; ++b) {
                out.push_back({ver, ShaderMode::kConsistent, b, prec});
            }
            out.push_back({ver, ShaderMode::kSeed, 3, prec});
        }
    }
    return out;
}

/// Limits large enough for every variant the tests export (llvmpipe offers 4096 vectors).
inline Limits roomy_limits() {
    Limits l;
    l.max_fragment_uniform_vectors = 4096;
    l.max_texture_size = 8192;
    l.max_texture_image_units = 16;
    return l;
}

/// Runs glslangValidator on `path` (the stage from its extension); its output goes to *log.
/// Returns the exit status (0: valid).
inline int run_glslang(const std::string& path, std::string* log) {
    const std::string out = path + ".log";
    const int rc = std::system(("glslangValidator '" + path + "' > '" + out + "' 2>&1").c_str());
    std::ifstream in(out);
    *log = std::string(std::istreambuf_iterator<char>(in), {});
    return rc;
}

}  // namespace inlight::gles::testing
