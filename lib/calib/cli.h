// calib/cli.h: the command-line options of `calibrate geometry` and `calibrate response`
// (CLI11), kept here so apps/calibrate/main.cpp stays a thin dispatcher. Flags are kebab-case
// long names of the GeometryOptions / ResponseToolOptions fields; defaults live in those structs.
#pragma once

#include <CLI/CLI.hpp>

#include "calib/pipeline.h"

namespace inlight::calib {

/// Registers the options of `calibrate geometry` on `app`, bound to `options`.
void add_geometry_options(CLI::App& app, GeometryOptions& options);

/// Registers the options of `calibrate response` on `app`, bound to `options`.
void add_response_options(CLI::App& app, ResponseToolOptions& options);

/// Example lines for the two modes' --help footers.
extern const char* const kGeometryExample;
extern const char* const kResponseExample;

}  // namespace inlight::calib
