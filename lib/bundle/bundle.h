// bundle/bundle.h: writing and verifying asset bundle folders (docs/bundle-format.md).
//
// A bundle is one folder holding manifest.json and the files it lists. write_bundle builds
// the whole folder next to its destination and moves it into place with one rename, so a
// reader sees the old bundle or the new one, never a mixture. read_bundle trusts nothing: it
// validates the manifest, keeps every path inside the folder (no "..", no absolute path, no
// symlink out), and checks each file's size and SHA-256.
#pragma once

#include <string>
#include <vector>

#include "bundle/manifest.h"

namespace inlight::bundle {

/// One file to put into a bundle.
struct PackFile {
    std::string source;     ///< file to copy (read, never modified)
    std::string path;       ///< destination inside the bundle (check_relative_path)
    std::string role;       ///< one of roles_for(kind)
    int stream_index = -1;  ///< for streamed roles (btf_component), else -1
};

/// What write_bundle writes.
struct PackRequest {
    Kind kind = Kind::kFabric;
    std::string id;
    std::string name;
    nlohmann::json properties = nlohmann::json::object();
    std::vector<PackFile> files;
};

/// Writes the bundle folder `dest` (e.g. "out/bundles/fabrics/satin") atomically: copies every
/// source into a temporary sibling folder, hashes the copies (core/sha256), reads image sizes,
/// writes manifest.json, validates the result with read_bundle, then renames the folder into
/// place (an existing bundle at `dest` is exchanged atomically, then removed). Hidden folders
/// ".<id>.tmp-*" beside `dest`, left by a killed writer, are removed first. Throws Error naming the file or role on any problem; `dest` is then untouched.
Manifest write_bundle(const std::string& dest, const PackRequest& request);

/// Reads and fully verifies the bundle folder `dir`. Throws Error, naming the bundle and the
/// file, when:
///   - manifest.json is missing, not JSON, or breaks the schema (manifest_from_json), or has
///     an unknown format or version;
///   - a listed path is absolute or has a ".." component (path traversal), or resolves through
///     a symlink to somewhere outside `dir`;
///   - a listed file is missing, not a regular file, shorter than its listed size ("truncated")
///     or longer, or its SHA-256 differs from the manifest's;
///   - the folder holds a file the manifest does not list (stray or partial files);
///   - an inner manifest (exported shaders, compressed BTF) names a file the bundle does not
///     hold, or the BTF's stream order differs from the bundle's (check_contents).
///   - the folder sits in a bundle root's fabrics/ or devices/ and its name is not the
///     manifest's id, or its kind is not the folder's (one rule for verify and index), or it
///     is a symlink (or lies under one) resolving out of that place (check_in_root; checked
///     first, so nothing is read through the link).
/// A bundle replaced by `bundle pack` while it is read (its manifest changed meanwhile) is read
/// again, up to 5 times, so a reader never reports a mixture of the old and the new bundle.
Manifest read_bundle(const std::string& dir);

/// Throws Error naming the path when `root`/`rel` (e.g. "fabrics" or "fabrics/<id>" in a bundle
/// root, or the folder of an output written there) exists but resolves, through a symlink
/// anywhere along `rel`, to another place than `rel` in the root: a bundle root holds its
/// bundles, not links to them, so nothing read or written there leaves the root through a link.
/// A path that does not exist yet passes (nothing to follow).
void check_in_root(const std::string& root, const std::string& rel);

/// The SHA-256 of the bundle's manifest.json (identifies the bundle's whole content, since the
/// manifest lists every file's hash).
std::string manifest_sha256(const std::string& dir);

}  // namespace inlight::bundle
