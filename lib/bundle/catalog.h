// bundle/catalog.h: the catalogue index the app's catalogue screen reads: an SQLite database
// (Debian's libsqlite3) listing every fabric and device bundle under a bundle root, with names,
// thumbnails, sizes and bundle paths (schema in docs/bundle-format.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace inlight::bundle {

/// Version of the catalogue's table layout, stored in catalog_info. Version 2 added the
/// fabrics' btf_bytes, shader_variants and shader_bytes columns.
inline constexpr int kCatalogVersion = 2;

/// One row of the catalogue as written.
struct CatalogRow {
    std::string kind;            ///< "fabric" | "device"
    std::string id;
    std::string name;
    std::string bundle_path;     ///< relative to the bundle root, '/'-separated
    std::string manifest_sha256;
    uint64_t total_bytes = 0;    ///< files of the bundle, manifest excluded
    int file_count = 0;
};

/// Verifies every bundle in `root`/fabrics/* and `root`/devices/* with read_bundle (folders
/// whose names start with '.' are unfinished writes and are skipped), then writes the SQLite
/// catalogue `db_path` atomically (built in a temporary file, renamed into place). Rows are
/// inserted in id order, so the same bundles give a byte-identical file. Throws Error naming
/// the bundle when any bundle fails verification (nothing is written then), when two
/// bundles of one kind share an id, or when fabrics/, devices/ or a bundle folder is a symlink
/// out of its place in the root (check_in_root). Returns the rows.
std::vector<CatalogRow> write_catalog(const std::string& root, const std::string& db_path);

/// Reads the rows back (kind, id order). Throws Error naming the file when it is not a
/// catalogue of kCatalogVersion.
std::vector<CatalogRow> read_catalog(const std::string& db_path);

}  // namespace inlight::bundle
