// gles/cli.h: the --export-gles options shared by render and brdf-sh-bake, so both tools spell
// and validate them alike.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "gles/export.h"

namespace inlight::gles {

struct ExportArgs {
    std::string dir;  ///< --export-gles; empty = no export
    std::string versions = "100,300", modes = "consistent,seed", precisions = "highp,mediump";
    int max_sh_bands = 3;
    /// The parsed set (the options' validators have already checked every list).
    ExportSet set() const;
};

/// Adds --export-gles DIR, --gles-versions, --gles-modes, --gles-precisions, --gles-max-bands.
void add_export_options(CLI::App& app, ExportArgs& args);

}  // namespace inlight::gles
