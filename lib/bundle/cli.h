// bundle/cli.h: the modes of the `bundle` tool (docs/bundle-format.md): options, their CLI11
// registration and one run function each, so apps/bundle/main.cpp stays a dispatcher and a
// pipeline or test can call what a user calls.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bundle/fabric_maps.h"
#include "core/report.h"

namespace inlight::bundle {

/// `bundle fabric-maps`: a fabric's textures in the app's formats.
struct FabricMapsToolOptions {
    FabricMapsOptions maps;
    std::string output;  ///< folder for albedo.png, normal.png, thumbnail.png
};

/// `bundle pack`: files into a verified bundle folder ROOT/<kind>s/<id>.
struct PackToolOptions {
    std::string kind;                     ///< "fabric" | "device"
    std::string id;
    std::string name;                     ///< default: the id
    std::vector<std::string> files;       ///< ROLE=SOURCE[@PATH_IN_BUNDLE][#STREAM_INDEX]
    std::vector<std::string> properties;  ///< KEY=VALUE (VALUE as JSON, else a string)
    std::string root;                     ///< bundle root
};

/// `bundle verify`: read_bundle on each folder.
struct VerifyToolOptions {
    std::vector<std::string> bundles;  ///< bundle folders, or bundle roots (with fabrics/, devices/)
};

/// `bundle index`: the SQLite catalogue of a bundle root.
struct IndexToolOptions {
    std::string root;
    std::string output;  ///< default ROOT/catalog.sqlite
};

void add_fabric_maps_options(CLI::App& app, FabricMapsToolOptions& options);
void add_pack_options(CLI::App& app, PackToolOptions& options);
void add_verify_options(CLI::App& app, VerifyToolOptions& options);
void add_index_options(CLI::App& app, IndexToolOptions& options);

void run_fabric_maps(const FabricMapsToolOptions& options, Report& report);
void run_pack(const PackToolOptions& options, Report& report);
/// Verifies every bundle; throws Error listing each failure after checking all of them.
void run_verify(const VerifyToolOptions& options, Report& report);
void run_index(const IndexToolOptions& options, Report& report);

/// Parses one --file value "ROLE=SOURCE[@PATH][#N]"; PATH defaults to SOURCE's file name.
/// Throws UsageError naming the value when malformed.
struct FileSpec {
    std::string role, source, path;
    int stream_index = -1;
};
FileSpec parse_file_spec(const std::string& spec);

}  // namespace inlight::bundle
