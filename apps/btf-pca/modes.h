// apps/btf-pca/modes.h: btf-pca's modes (docs/btf.md), each a thin function over one
// library call in its own file: compress.cpp (btf::run_pca), interpolate.cpp
// (btf::run_interpolation), export_gles.cpp (gles::export_btf_gles); main.cpp dispatches and
// refuses the old spelling.
#pragma once

#include <CLI/CLI.hpp>

#include "btf/pca_run.h"

namespace inlight::btf_pca_cli {

inline constexpr const char* kCompressPurpose =
    "btf-pca compress: PCA compression of a bidirectional texture function per group of k "
    "neighbouring views, components as 8-bit PNG (or EXR) ordered for streaming";
inline constexpr const char* kCompressExample =
    "btf-pca compress wool_btf.zip -o out/wool -k 3 -c 8 --report wool.json";
inline constexpr const char* kInterpolatePurpose =
    "btf-pca interpolate: evaluate a BTF or a btf-pca output folder at each (light, view) pair of "
    "a file by angular interpolation, one EXR per pair (docs/btf-interpolation.md)";
inline constexpr const char* kInterpolateExample =
    "btf-pca interpolate out/wool --pairs pairs.txt -o out/wool_interp --scheme delaunay";

inline constexpr const char* kExportGlesPurpose =
    "btf-pca export-gles: OpenGL ES 3.00 / 1.00 shaders, texture atlases and per-view lighting matrices "
    "that draw a btf-pca folder under SH lighting (docs/btf-gles.md)";
inline constexpr const char* kExportGlesExample = "btf-pca export-gles out/wool -o out/wool-gles --bands 3";

/// The options compress and interpolate read a raw BTF with; `linear` is --linear-input (interpolate.cpp).
void add_open_options(CLI::App& app, btf::OpenOptions& open, bool& linear);

/// The modes: argv[1] is the mode's name; return the process exit code.
int compress(int argc, char** argv);
int interpolate(int argc, char** argv);
/// Built with the gles module (Embree builds): INLIGHT_BTF_PCA_GLES.
int export_gles(int argc, char** argv);

}  // namespace inlight::btf_pca_cli
