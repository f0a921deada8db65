// bundle/manifest.h: the manifest of an asset bundle for the app (docs/bundle-format.md): what
// a fabric's or a device's folder holds, each file with its role, size and SHA-256. The JSON
// form is versioned and validated on read: every key, type and value range is checked, and
// anything the schema does not name is rejected.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace inlight::bundle {

/// "format" of every manifest.
inline constexpr const char* kFormatName = "inlight_bundle";
/// The manifest version this code writes. Version 2 added the roles that carry the exported
/// GLES variants whole (shader_index, shader_data) and a compressed BTF whole (btf_weights,
/// btf_mean); a version-1 manifest naming one of them is rejected. Version 3 added
/// shader_texture (the textures the exported shaders bind); a version-1 or 2 manifest naming it
/// is rejected. Version 4 added the compressed BTF's GLES shaders (btf_gles_manifest,
/// btf_gles_vertex, btf_gles_fragment, btf_gles_matrices).
inline constexpr int kFormatVersion = 4;
/// The oldest manifest version this code reads (1 .. kFormatVersion are accepted).
inline constexpr int kOldestReadVersion = 1;
/// File name of the manifest at the root of a bundle folder.
inline constexpr const char* kManifestName = "manifest.json";

/// What a bundle describes: one fabric (textures, BRDF table, shaders, BTF components) or one
/// device (a camera and lens: direction, solid-angle and mask maps, calibration).
enum class Kind { kFabric, kDevice };

/// "fabric" | "device".
/// Whether `id` is a bundle id: 1-64 characters of a-z, 0-9, '_', '-', starting with a letter
/// or digit (the folder name and the catalogue key).
bool is_valid_id(const std::string& id);

std::string to_string(Kind kind);
/// Inverse of to_string; throws Error naming the accepted names.
Kind kind_from_string(const std::string& name);

/// One file of a bundle.
struct FileEntry {
    /// Relative to the bundle folder, '/'-separated; never absolute, never "." or ".."
    /// components, never empty components (checked by check_relative_path).
    std::string path;
    /// What the file is to the app; one of roles_for(kind) (checked).
    std::string role;
    /// "image/png", "image/x-exr", "application/json", "application/toml",
    /// "application/octet-stream", "text/x-glsl", "application/x-yaml" (from the extension).
    std::string media_type;
    /// "srgb" (8-bit encoded colour), "linear_srgb", "data" (not colour), or "" (not an image).
    std::string color_space;
    uint64_t bytes = 0;   ///< exact file size
    std::string sha256;   ///< lower-case hex, 64 characters
    int width_px = 0;     ///< images: size in pixels (0 = not an image)
    int height_px = 0;
    /// Streamed files (BTF components): 0-based position in the order the app downloads and
    /// applies them; -1 = not streamed. Unique within a bundle, and 0..n-1 without gaps.
    int stream_index = -1;
};

/// A bundle's manifest. Free of time stamps and absolute paths, so the same inputs give a
/// byte-identical manifest (content-addressed rebuilds depend on it).
struct Manifest {
    int version = kFormatVersion;
    Kind kind = Kind::kFabric;
    /// Folder name and catalogue key: 1-64 characters of [a-z0-9_-], starting with a letter or
    /// digit (checked).
    std::string id;
    std::string name;         ///< human-readable name for the catalogue screen (non-empty)
    std::string created_by;   ///< "inlight <version>"
    /// Kind-specific facts (e.g. a fabric's tile_size_m, sh_bands): a JSON object of
    /// snake_case keys, values of any JSON type. Numbers must be finite.
    nlohmann::json properties = nlohmann::json::object();
    std::vector<FileEntry> files;  ///< sorted by path

    /// Sum of the files' sizes, bytes.
    uint64_t total_bytes() const;
    /// The first file with this role, or nullptr.
    const FileEntry* find_role(const std::string& role) const;
};

/// Roles a bundle of this kind may hold, and whether each is required.
struct RoleSpec {
    const char* role;
    bool required;
    bool repeatable;   ///< may appear more than once (downscaled maps, BTF components, shaders)
    bool streamed;     ///< carries a stream_index
    const char* color_space;  ///< what the file must be tagged with ("" = not an image)
    const char* extensions;   ///< allowed extensions, '|'-separated ("png", "png|exr")
    int since_version = 1;    ///< the first manifest version that has this role
};
const std::vector<RoleSpec>& roles_for(Kind kind);

/// Throws Error "<what>: '<path>' ..." when `path` is not a safe relative bundle path: empty,
/// absolute, containing a backslash, NUL, or an empty, "." or ".." component.
void check_relative_path(const std::string& path, const std::string& what);

/// Media type from the file name's extension; throws Error for an extension a bundle may not
/// hold.
std::string media_type_for(const std::string& path);

/// The manifest as JSON (keys in a fixed order, files sorted by path).
nlohmann::json to_json(const Manifest& manifest);
/// Parses and validates a manifest; `source` names it in errors ("<source>: files[2].sha256:
/// expected 64 lower-case hex digits"). Throws Error on any schema violation, on an unknown
/// format or version, and on unsafe paths.
Manifest manifest_from_json(const nlohmann::json& json, const std::string& source);

}  // namespace inlight::bundle
