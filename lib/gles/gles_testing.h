// gles/gles_testing.h: the tables, materials and variants the gles tests share.
#pragma once

#include <array>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
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

/// Shader sources to check with glslangValidator, compiled in one run of it (a process per
/// file made the validator test take a minute on the 2-core machine). A source whose stage and
/// bytes equal an earlier one's is compiled once: the same bytes give the same verdict.
class GlslangBatch {
  public:
    explicit GlslangBatch(std::string dir) : dir_(std::move(dir)) {}

    /// Queues `bytes` as the stage named by `name`'s extension (.vert or .frag).
    void add(const std::string& name, const std::string& bytes) {
        const std::string stage = name.substr(name.rfind('.'));
        if (!seen_.insert(stage + '\n' + bytes).second) return;
        const std::string path = dir_ + "/" + name;
        std::ofstream(path) << bytes;
        paths_.push_back(path);
        sources_.push_back(bytes);
    }
    size_t unique_sources() const { return paths_.size(); }

    /// Compiles every queued source; returns (path, log, source) of each one that fails. A
    /// failed batch is rerun file by file, so each failure names its own source.
    std::vector<std::array<std::string, 3>> failures() const {
        std::vector<std::array<std::string, 3>> out;
        if (paths_.empty()) return out;
        std::string cmd = "glslangValidator";
        for (const std::string& p : paths_) cmd += " '" + p + "'";
        if (std::system((cmd + " > '" + dir_ + "/batch.log' 2>&1").c_str()) == 0) return out;
        for (size_t i = 0; i < paths_.size(); ++i) {
            std::string log;
            if (run_glslang(paths_[i], &log) != 0) out.push_back({paths_[i], log, sources_[i]});
        }
        if (out.empty()) out.push_back({dir_ + "/batch.log", "the batch failed, no file alone did", ""});
        return out;
    }

  private:
    std::string dir_;
    std::set<std::string> seen_;
    std::vector<std::string> paths_, sources_;
};

}  // namespace inlight::gles::testing
