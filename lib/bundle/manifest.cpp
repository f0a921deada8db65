#include "bundle/manifest.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::bundle {

namespace {

const std::vector<RoleSpec> kFabricRoles = {
    // role, required, repeatable, streamed, colour space, extensions, since version
    {"albedo", true, false, false, "srgb", "png"},
    {"thumbnail", true, false, false, "srgb", "png"},
    {"material", true, false, false, "", "toml"},
    {"normal", false, false, false, "data", "png"},
    {"brdf_sh_table", false, false, false, "", "bin"},
    {"brdf_sh_table_json", false, false, false, "", "json"},
    {"brdf_sh_texture", false, false, false, "data", "exr"},
    {"shader_lookup", false, false, false, "", "glsl"},
    {"shader_vertex", false, true, false, "", "glsl|vert"},
    {"shader_fragment", false, true, false, "", "glsl|frag"},
    {"shader_manifest", false, true, false, "", "json"},
    {"shader_index", false, false, false, "", "json", 2},
    {"shader_data", false, true, false, "", "bin", 2},
    // The shaders' own textures (gles/export.h: the material's albedo and normal map as the
    // variants bind them, named by the manifests' files.albedo_texture / normal_texture).
    {"shader_texture", false, true, false, "", "png", 3},
    {"btf_manifest", false, false, false, "", "json"},
    {"btf_weights", false, false, false, "", "bin", 2},
    {"btf_mean", false, true, false, "data", "png|exr", 2},
    {"btf_component", false, true, true, "data", "png|exr"},
    // The compressed BTF's GLES shaders (gles/btf_export.h, btf-pca export-gles --atlases none):
    // btf-gles.json beside btf-pca.json, whose channel files name the btf_mean/btf_component
    // PNGs the app assembles the atlases from.
    {"btf_gles_manifest", false, false, false, "", "json", 4},
    {"btf_gles_vertex", false, true, false, "", "vert", 4},
    {"btf_gles_fragment", false, true, false, "", "frag", 4},
    {"btf_gles_matrices", false, false, false, "", "bin", 4},
};

const std::vector<RoleSpec> kDeviceRoles = {
    {"calibration", true, false, false, "", "json"},
    {"directions", true, true, false, "data", "exr"},
    {"solid_angle", true, true, false, "data", "exr"},
    {"mask", true, true, false, "data", "png"},
    {"response", false, false, false, "", "json"},
};

const std::map<std::string, std::string> kMediaTypes = {
    {"png", "image/png"},
    {"exr", "image/x-exr"},
    {"json", "application/json"},
    {"toml", "application/toml"},
    {"bin", "application/octet-stream"},
    {"glsl", "text/x-glsl"},
    {"vert", "text/x-glsl"},
    {"frag", "text/x-glsl"},
    {"yml", "application/x-yaml"},
};

const std::set<std::string> kColorSpaces = {"", "srgb", "linear_srgb", "data"};

bool is_id_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

bool is_hex64(const std::string& s) {
    return s.size() == 64 && std::all_of(s.begin(), s.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

// Typed access to one JSON object, naming the key path in errors and rejecting unknown keys.
class ObjectReader {
  public:
    ObjectReader(const nlohmann::json& j, std::string where) : m_j(j), m_where(std::move(where)) {
        if (!m_j.is_object()) throw Error(str(m_where, ": expected a JSON object"));
    }
    const nlohmann::json* find(const std::string& key) {
        m_read.insert(key);
        auto it = m_j.find(key);
        return it == m_j.end() ? nullptr : &*it;
    }
    const nlohmann::json& require(const std::string& key) {
        const nlohmann::json* v = find(key);
        if (!v) throw Error(str(m_where, ": missing key '", key, "'"));
        return *v;
    }
    std::string string(const std::string& key, bool required = true) {
        const nlohmann::json* v = required ? &require(key) : find(key);
        if (!v) return "";
        if (!v->is_string()) throw Error(str(where(key), ": expected a string"));
        return v->get<std::string>();
    }
    int64_t integer(const std::string& key, int64_t lo, int64_t hi, bool required,
                    int64_t fallback) {
        const nlohmann::json* v = required ? &require(key) : find(key);
        if (!v) return fallback;
        if (!v->is_number_integer()) throw Error(str(where(key), ": expected an integer"));
        // is_number_integer covers unsigned too; compare in a wide type.
        const long double x = v->is_number_unsigned()
                                  ? static_cast<long double>(v->get<uint64_t>())
                                  : static_cast<long double>(v->get<int64_t>());
        if (x < lo || x > hi) {
            throw Error(str(where(key), ": ", v->dump(), " is outside [", lo, ", ", hi, "]"));
        }
        return static_cast<int64_t>(x);
    }
    void finish() const {
        for (auto it = m_j.begin(); it != m_j.end(); ++it) {
            if (!m_read.count(it.key())) {
                throw Error(str(m_where, ": unknown key '", it.key(), "'"));
            }
        }
    }
    std::string where(const std::string& key) const { return str(m_where, ".", key); }

  private:
    const nlohmann::json& m_j;
    std::string m_where;
    std::set<std::string> m_read;
};

void check_finite_numbers(const nlohmann::json& j, const std::string& where) {
    if (j.is_number_float() && !std::isfinite(j.get<double>())) {
        throw Error(str(where, ": not a finite number"));
    }
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            check_finite_numbers(*it, str(where, ".", it.key()));
        }
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) check_finite_numbers(j[i], str(where, "[", i, "]"));
    }
}

const RoleSpec* find_role_spec(Kind kind, const std::string& role) {
    for (const RoleSpec& r : roles_for(kind)) {
        if (role == r.role) return &r;
    }
    return nullptr;
}

}  // namespace

constexpr EnumName<Kind> kKindNames[] = {
    {Kind::kFabric, "fabric"},
    {Kind::kDevice, "device"},
};

bool is_valid_id(const std::string& id) {
    return !id.empty() && id.size() <= 64 && id[0] != '-' && id[0] != '_' &&
           std::all_of(id.begin(), id.end(), is_id_char);
}

std::string to_string(Kind kind) { return enum_to_string(kKindNames, kind); }

Kind kind_from_string(const std::string& name) {
    return enum_from_string<Error>(kKindNames, name, "bundle kind");
}

uint64_t Manifest::total_bytes() const {
    uint64_t sum = 0;
    for (const FileEntry& f : files) {
        if (__builtin_add_overflow(sum, f.bytes, &sum)) {
            throw Error(str("bundle '", id, "': its files' sizes add up past 2^64 bytes"));
        }
    }
    return sum;
}

const FileEntry* Manifest::find_role(const std::string& role) const {
    for (const FileEntry& f : files) {
        if (f.role == role) return &f;
    }
    return nullptr;
}

const std::vector<RoleSpec>& roles_for(Kind kind) {
    return kind == Kind::kFabric ? kFabricRoles : kDeviceRoles;
}

void check_relative_path(const std::string& path, const std::string& what) {
    if (path.empty()) throw Error(str(what, ": empty path"));
    if (path.find('\0') != std::string::npos) throw Error(str(what, ": path contains NUL"));
    if (path.find('\\') != std::string::npos) {
        throw Error(str(what, ": '", path, "' contains a backslash (paths use '/')"));
    }
    if (path[0] == '/') {
        throw Error(str(what, ": '", path, "' is an absolute path (must be inside the bundle)"));
    }
    size_t start = 0;
    while (start <= path.size()) {
        const size_t end = std::min(path.find('/', start), path.size());
        const std::string part = path.substr(start, end - start);
        if (part == "..") {
            throw Error(str(what, ": '", path, "' leaves the bundle ('..' component)"));
        }
        if (part.empty() || part == ".") {
            throw Error(str(what, ": '", path, "' has an empty or '.' component"));
        }
        start = end + 1;
    }
}

std::string media_type_for(const std::string& path) {
    const auto it = kMediaTypes.find(fs::extension(path));
    if (it == kMediaTypes.end()) {
        std::string known;
        for (const auto& [ext, type] : kMediaTypes) known += (known.empty() ? "." : ", .") + ext;
        throw Error(str(path, ": a bundle cannot hold this file type (known: ", known, ")"));
    }
    return it->second;
}

nlohmann::json to_json(const Manifest& m) {
    nlohmann::json files = nlohmann::json::array();
    std::vector<const FileEntry*> sorted;
    for (const FileEntry& f : m.files) sorted.push_back(&f);
    std::sort(sorted.begin(), sorted.end(),
              [](const FileEntry* a, const FileEntry* b) { return a->path < b->path; });
    for (const FileEntry* f : sorted) {
        nlohmann::json j = {{"path", f->path},          {"role", f->role},
                            {"media_type", f->media_type}, {"bytes", f->bytes},
                            {"sha256", f->sha256}};
        if (!f->color_space.empty()) j["color_space"] = f->color_space;
        if (f->width_px > 0) {
            j["width_px"] = f->width_px;
            j["height_px"] = f->height_px;
        }
        if (f->stream_index >= 0) j["stream_index"] = f->stream_index;
        files.push_back(j);
    }
    return {{"format", kFormatName},
            {"version", m.version},
            {"kind", to_string(m.kind)},
            {"id", m.id},
            {"name", m.name},
            {"created_by", m.created_by},
            {"properties", m.properties},
            {"total_bytes", m.total_bytes()},
            {"files", files}};
}

Manifest manifest_from_json(const nlohmann::json& json, const std::string& source) {
    ObjectReader top(json, source);
    // Format and version first: a newer manifest must fail on its version, not on a key this
    // reader does not know.
    const std::string format = top.string("format");
    if (format != kFormatName) {
        throw Error(str(source, ": format '", format, "' is not an inlight bundle manifest ",
                        "(expected '", kFormatName, "')"));
    }
    const nlohmann::json& version = top.require("version");
    if (!version.is_number_integer() || version.get<int64_t>() < kOldestReadVersion ||
        version.get<int64_t>() > kFormatVersion) {
        throw Error(str(source, ": unknown manifest version ", version.dump(),
                        " (this reader knows versions ", kOldestReadVersion, " to ",
                        kFormatVersion, ")"));
    }
    Manifest m;
    m.version = static_cast<int>(version.get<int64_t>());
    m.kind = kind_from_string(top.string("kind"));
    m.id = top.string("id");
    if (!is_valid_id(m.id)) {
        throw Error(str(source, ": id '", m.id,
                        "': expected 1-64 characters of a-z, 0-9, '_', '-', starting with a "
                        "letter or digit"));
    }
    m.name = top.string("name");
    if (m.name.empty()) throw Error(str(source, ": name: must not be empty"));
    m.created_by = top.string("created_by");
    m.properties = top.require("properties");
    if (!m.properties.is_object()) throw Error(str(source, ": properties: expected an object"));
    check_finite_numbers(m.properties, str(source, ": properties"));
    const int64_t total = top.integer("total_bytes", 0, INT64_MAX, true, 0);
    const nlohmann::json& files = top.require("files");
    if (!files.is_array()) throw Error(str(source, ": files: expected an array"));
    top.finish();

    std::set<std::string> paths;
    std::map<std::string, int> role_count;
    std::vector<int> stream;
    for (size_t i = 0; i < files.size(); ++i) {
        const std::string where = str(source, ": files[", i, "]");
        ObjectReader r(files[i], where);
        FileEntry f;
        f.path = r.string("path");
        check_relative_path(f.path, r.where("path"));
        if (f.path == kManifestName) {
            throw Error(str(r.where("path"), ": the manifest cannot list itself"));
        }
        if (!paths.insert(f.path).second) {
            throw Error(str(r.where("path"), ": '", f.path, "' is listed twice"));
        }
        f.role = r.string("role");
        const RoleSpec* spec = find_role_spec(m.kind, f.role);
        if (!spec) {
            std::string known;
            for (const RoleSpec& s : roles_for(m.kind)) known += (known.empty() ? "" : ", ") + std::string(s.role);
            throw Error(str(r.where("role"), ": '", f.role, "' is not a ", to_string(m.kind),
                            " role (known: ", known, ")"));
        }
        if (spec->since_version > m.version) {
            throw Error(str(r.where("role"), ": role '", f.role, "' needs manifest version ",
                            spec->since_version, " (this manifest is version ", m.version, ")"));
        }
        if (++role_count[f.role] > 1 && !spec->repeatable) {
            throw Error(str(r.where("role"), ": role '", f.role, "' may appear only once"));
        }
        f.media_type = r.string("media_type");
        if (f.media_type != media_type_for(f.path)) {
            throw Error(str(r.where("media_type"), ": '", f.media_type, "' does not match '",
                            f.path, "' (expected ", media_type_for(f.path), ")"));
        }
        const std::string ext = "|" + std::string(spec->extensions) + "|";
        if (ext.find("|" + fs::extension(f.path) + "|") == std::string::npos) {
            throw Error(str(r.where("path"), ": '", f.path, "': role '", f.role, "' takes .",
                            spec->extensions, " files"));
        }
        f.color_space = r.string("color_space", false);
        if (f.color_space != spec->color_space) {
            throw Error(str(r.where("color_space"), ": '", f.color_space, "' for role '", f.role,
                            "' (expected '", spec->color_space, "')"));
        }
        f.bytes = static_cast<uint64_t>(r.integer("bytes", 0, INT64_MAX, true, 0));
        f.sha256 = r.string("sha256");
        if (!is_hex64(f.sha256)) {
            throw Error(str(r.where("sha256"), ": expected 64 lower-case hex digits"));
        }
        f.width_px = static_cast<int>(r.integer("width_px", 1, 1 << 20, false, 0));
        f.height_px = static_cast<int>(r.integer("height_px", 1, 1 << 20, false, 0));
        if ((f.width_px > 0) != (f.height_px > 0)) {
            throw Error(str(where, ": width_px and height_px go together"));
        }
        f.stream_index = static_cast<int>(r.integer("stream_index", 0, 1 << 24, false, -1));
        if ((f.stream_index >= 0) != spec->streamed) {
            throw Error(str(where, ": stream_index is ", spec->streamed ? "required" : "not allowed",
                            " for role '", f.role, "'"));
        }
        if (f.stream_index >= 0) stream.push_back(f.stream_index);
        r.finish();
        m.files.push_back(std::move(f));
    }
    for (const RoleSpec& s : roles_for(m.kind)) {
        if (s.required && !role_count.count(s.role)) {
            throw Error(str(source, ": a ", to_string(m.kind), " bundle needs a file with role '",
                            s.role, "'"));
        }
    }
    std::sort(stream.begin(), stream.end());
    for (size_t i = 0; i < stream.size(); ++i) {
        if (stream[i] != static_cast<int>(i)) {
            throw Error(str(source, ": stream_index values must be 0..", stream.size() - 1,
                            " each once (found ", stream[i], " at position ", i, ")"));
        }
    }
    if (static_cast<uint64_t>(total) != m.total_bytes()) {
        throw Error(str(source, ": total_bytes ", total, " is not the sum of the files' bytes (",
                        m.total_bytes(), ")"));
    }
    return m;
}

}  // namespace inlight::bundle
