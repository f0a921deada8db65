#include "bundle/contents.h"

#include "image/image.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <vector>

#include "core/json_in.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::bundle {

namespace {

namespace stdfs = std::filesystem;

// j[key] when j is an object holding key, else null (const access that cannot assert).
const nlohmann::json& member(const nlohmann::json& j, const char* key) {
    static const nlohmann::json kNull;
    if (!j.is_object()) return kNull;
    const auto it = j.find(key);
    return it == j.end() ? kNull : *it;
}

// The bundle's files by path, and the inner manifests' view of them.
class Listing {
  public:
    Listing(const Manifest& m, std::string dir) : m_dir(std::move(dir)) {
        for (const FileEntry& f : m.files) m_by_path[f.path] = &f;
    }

    // Parses the inner manifest `f` (already hash-checked) and checks its "format".
    nlohmann::json read_json(const FileEntry& f, const std::string& format) const {
        const std::string shown = where(f);
        const nlohmann::json j =
            json_in::parse(fs::read_file((stdfs::path(m_dir) / f.path).string()), shown);
        if (member(j, "format") != format) {
            throw Error(str(shown, ": not a '", format, "' manifest"));
        }
        return j;
    }

    // The bundle file that `name` (a string in the inner manifest `from`, relative to its
    // folder) refers to; it must exist with role `role`. `key` names the entry in errors.
    const FileEntry& resolve(const FileEntry& from, const nlohmann::json& name,
                             const std::string& key, const std::string& role) const {
        return resolve(from, name, key, std::vector<std::string>{role});
    }
    // As above, with one of `roles`.
    const FileEntry& resolve(const FileEntry& from, const nlohmann::json& name,
                             const std::string& key, const std::vector<std::string>& roles) const {
        const std::string shown = str(where(from), ": ", key);
        if (!name.is_string()) throw Error(str(shown, ": expected a file name"));
        const std::string rel = name.get<std::string>();
        check_relative_path(rel, shown);
        const std::string folder = stdfs::path(from.path).parent_path().generic_string();
        const std::string path = folder.empty() ? rel : folder + "/" + rel;
        const auto it = m_by_path.find(path);
        if (it == m_by_path.end()) {
            throw Error(str(shown, ": '", path, "' is not in the bundle"));
        }
        if (std::find(roles.begin(), roles.end(), it->second->role) == roles.end()) {
            std::string expected;
            for (size_t i = 0; i < roles.size(); ++i)
                expected += (i == 0 ? "'" : "' or '") + roles[i];
            throw Error(str(shown, ": '", path, "' has role '", it->second->role,
                            "' in the bundle (expected ", expected, "')"));
        }
        return *it->second;
    }

    std::string where(const FileEntry& f) const { return str(m_dir, "/", f.path); }
    const std::string& dir() const { return m_dir; }

  private:
    std::string m_dir;
    std::map<std::string, const FileEntry*> m_by_path;
};

const std::map<std::string, std::string> kShaderFileRoles = {
    {"vertex", "shader_vertex"},     {"fragment", "shader_fragment"},
    {"brdf_data", "shader_data"},    {"albedo_texture", "shader_texture"},
    {"normal_texture", "shader_texture"}};

// A raw RGBA8 texture the shader manifest `f` lists holds exactly its width x height texels:
// a texture of the wrong size would be bound as garbage (glTexImage2D reads width x height x 4
// bytes whatever the file holds).
void check_shader_textures(const FileEntry& f, const nlohmann::json& j, const Listing& listing) {
    const nlohmann::json& textures = member(j, "textures");
    if (!textures.is_array()) return;  // a manifest written before the textures were listed
    for (size_t i = 0; i < textures.size(); ++i) {
        const nlohmann::json& t = textures[i];
        const nlohmann::json& file = member(t, "file");
        if (!file.is_string()) continue;
        const std::string key = str("textures[", i, "].file");
        const bool table = member(t, "uniform") == "u_brdf_texture";  // the BRDF table's data
        const FileEntry* target =
            &listing.resolve(f, file, key, table ? "shader_data" : "shader_texture");
        const nlohmann::json& format = member(t, "file_format");
        const std::string fmt = format.is_string() ? format.get<std::string>() : "";
        const nlohmann::json &w = member(t, "width"), &h = member(t, "height");
        if (!w.is_number_integer() || !h.is_number_integer()) continue;
        const uint64_t width = w.get<uint64_t>(), height = h.get<uint64_t>();
        if (fmt.rfind("raw RGBA8", 0) == 0 && target->bytes != width * height * 4) {
            throw Error(str(listing.where(f), ": ", key, ": '", target->path, "' holds ",
                            target->bytes, " bytes; its ", width, "x", height,
                            " RGBA8 texels need ", width * height * 4));
        }
        if (fmt.rfind("PNG, 8-bit RGBA", 0) == 0) {
            const image::ImageInfo info =
                image::read_info((stdfs::path(listing.dir()) / target->path).string());
            if (static_cast<uint64_t>(info.width) != width ||
                static_cast<uint64_t>(info.height) != height || info.channels != 4 ||
                info.bits_per_channel != 8 || info.is_float) {
                throw Error(str(listing.where(f), ": ", key, ": '", target->path, "' is ",
                                info.width, "x", info.height, " with ", info.channels, " ",
                                info.bits_per_channel, "-bit channels; the manifest binds ",
                                width, "x", height, " 8-bit RGBA"));
            }
        }
    }
}

void check_shaders(const Manifest& m, const Listing& listing) {
    for (const FileEntry& f : m.files) {
        if (f.role == "shader_manifest") {
            const nlohmann::json j = listing.read_json(f, "inlight_gles_export");
            if (!member(j, "files").is_object()) {
                throw Error(str(listing.where(f), ": files: expected an object"));
            }
            for (auto it = j["files"].begin(); it != j["files"].end(); ++it) {
                if (it.value().is_null()) continue;  // e.g. brdf_data of a Lambert material
                const auto role = kShaderFileRoles.find(it.key());
                if (role == kShaderFileRoles.end()) {
                    throw Error(str(listing.where(f), ": files.", it.key(),
                                    ": unknown entry (known: vertex, fragment, brdf_data, albedo_texture, normal_texture)"));
                }
                listing.resolve(f, it.value(), "files." + it.key(), role->second);
            }
            check_shader_textures(f, j, listing);
        } else if (f.role == "shader_index") {
            const nlohmann::json j = listing.read_json(f, "inlight_gles_export_index");
            if (!member(j, "variants").is_array()) {
                throw Error(str(listing.where(f), ": variants: expected an array"));
            }
            for (size_t i = 0; i < j["variants"].size(); ++i) {
                const nlohmann::json& v = j["variants"][i];
                const std::string key = str("variants[", i, "].manifest");
                listing.resolve(f, member(v, "manifest"), key, "shader_manifest");
            }
        }
    }
}

void check_btf(const Manifest& m, const Listing& listing) {
    const FileEntry* manifest = m.find_role("btf_manifest");
    std::map<int, const FileEntry*> streamed;
    int means = 0;
    for (const FileEntry& f : m.files) {
        if (f.role == "btf_component") streamed[f.stream_index] = &f;
        means += f.role == "btf_mean";
    }
    if (!manifest) {
        if (!streamed.empty() || means > 0 || m.find_role("btf_weights")) {
            throw Error(str(listing.dir(), ": btf_component, btf_mean or btf_weights files without a "
                            "btf_manifest"));
        }
        return;
    }
    if (m.version < 2) return;  // version 1 carried the BTF's manifest without checking it
    const nlohmann::json j = listing.read_json(*manifest, "inlight-btf-pca");
    const std::string shown = listing.where(*manifest);
    if (!member(j, "groups").is_array() || !member(j, "stream").is_array()) {
        throw Error(str(shown, ": expected 'groups' and 'stream' arrays"));
    }
    const nlohmann::json& groups = j["groups"];
    int used_means = 0;
    for (size_t g = 0; g < groups.size(); ++g) {
        listing.resolve(*manifest, member(member(groups[g], "mean"), "file"),
                        str("groups[", g, "].mean.file"), "btf_mean");
        ++used_means;
    }
    if (used_means != means) {
        throw Error(str(shown, ": names ", used_means, " mean images, the bundle holds ", means));
    }
    const nlohmann::json& stream = j["stream"];
    if (stream.size() != streamed.size()) {
        throw Error(str(shown, ": the stream has ", stream.size(),
                        " components, the bundle holds ", streamed.size(), " btf_component files"));
    }
    for (size_t k = 0; k < stream.size(); ++k) {
        const nlohmann::json& e = stream[k];
        const std::string key = str("stream[", k, "]");
        if (!e.is_array() || e.size() != 2 || !e[0].is_number_unsigned() ||
            !e[1].is_number_unsigned() || e[0].get<size_t>() >= groups.size()) {
            throw Error(str(shown, ": ", key, ": expected [group, component] of an existing group"));
        }
        const nlohmann::json& comps = member(groups[e[0].get<size_t>()], "components");
        const size_t c = e[1].get<size_t>();
        if (!comps.is_array() || c >= comps.size() || !comps[c].is_object()) {
            throw Error(str(shown, ": ", key, ": no component ", c, " in group ", e[0]));
        }
        const FileEntry& file =
            listing.resolve(*manifest, member(comps[c], "file"), key + " file", "btf_component");
        if (file.stream_index != static_cast<int>(k)) {
            throw Error(str(listing.where(file), ": stream_index ", file.stream_index,
                            ", but it is entry ", k, " of ", manifest->path, "'s stream order"));
        }
    }
    if (!streamed.empty()) {
        listing.resolve(*manifest, member(member(j, "weights"), "file"), "weights.file",
                        "btf_weights");
    }
}

// The BTF's GLES export (btf-gles.json, gles/btf_export.h): its shaders and matrices are in the
// bundle with their roles, it ships no atlases, every atlas channel's source is one of the
// bundle's btf_mean / btf_component PNGs (beside it), and "load" names only its variants.
void check_btf_gles(const Manifest& m, const Listing& listing) {
    const FileEntry* f = m.find_role("btf_gles_manifest");
    const char* parts[] = {"btf_gles_vertex", "btf_gles_fragment", "btf_gles_matrices"};
    if (!f) {
        for (const char* role : parts) {
            if (m.find_role(role)) {
                throw Error(str(listing.dir(), ": ", role, " files without a btf_gles_manifest"));
            }
        }
        return;
    }
    const std::string shown = listing.where(*f);
    if (!m.find_role("btf_manifest")) {
        throw Error(str(shown, ": the BTF's GLES shaders without the BTF (no btf_manifest)"));
    }
    const nlohmann::json j = listing.read_json(*f, "inlight_btf_gles_export");
    const nlohmann::json& variants = member(j, "variants");
    if (!variants.is_array()) throw Error(str(shown, ": variants: expected an array"));
    std::vector<std::string> names;
    for (size_t i = 0; i < variants.size(); ++i) {
        const std::string key = str("variants[", i, "].");
        listing.resolve(*f, member(variants[i], "vertex_shader"), key + "vertex_shader", "btf_gles_vertex");
        listing.resolve(*f, member(variants[i], "fragment_shader"), key + "fragment_shader",
                        "btf_gles_fragment");
        if (member(variants[i], "name").is_string()) names.push_back(variants[i]["name"]);
    }
    const nlohmann::json& matrices = member(j, "matrices");
    const FileEntry& bin = listing.resolve(*f, member(matrices, "file"), "matrices.file", "btf_gles_matrices");
    if (!member(matrices, "bytes").is_number_unsigned() || matrices["bytes"].get<uint64_t>() != bin.bytes) {
        throw Error(str(shown, ": matrices.bytes: ", member(matrices, "bytes").dump(), ", but '", bin.path,
                        "' holds ", bin.bytes));
    }
    const nlohmann::json& textures = member(j, "textures");
    if (member(textures, "atlas_files") != false) {
        throw Error(str(shown, ": textures.atlas_files: a bundle ships no atlases (the app assembles them "
                               "from the BTF's PNGs: btf-pca export-gles --atlases none)"));
    }
    const nlohmann::json& groups = member(textures, "groups");
    if (!groups.is_array()) throw Error(str(shown, ": textures.groups: expected an array"));
    for (size_t g = 0; g < groups.size(); ++g) {
        const nlohmann::json& channels = member(groups[g], "channels");
        if (!channels.is_array()) throw Error(str(shown, ": textures.groups[", g, "].channels: expected an array"));
        for (size_t k = 0; k < channels.size(); ++k) {
            const nlohmann::json& file = member(channels[k], "file");
            if (file.is_null()) continue;  // an unused channel
            listing.resolve(*f, file, str("textures.groups[", g, "].channels[", k, "].file"),
                            std::vector<std::string>{"btf_mean", "btf_component"});
        }
    }
    const nlohmann::json& load = member(j, "load");
    if (!load.is_array()) throw Error(str(shown, ": load: expected an array"));
    for (size_t i = 0; i < load.size(); ++i) {
        const nlohmann::json& v = member(load[i], "variant");
        if (v.is_null()) continue;
        if (!v.is_string() || std::find(names.begin(), names.end(), v.get<std::string>()) == names.end()) {
            throw Error(str(shown, ": load[", i, "].variant: ", v.dump(), " is not one of its variants"));
        }
    }
}

}  // namespace

void check_contents(const Manifest& manifest, const std::string& dir) {
    if (manifest.kind != Kind::kFabric) return;
    const Listing listing(manifest, dir);
    check_shaders(manifest, listing);
    check_btf(manifest, listing);
    check_btf_gles(manifest, listing);
}

}  // namespace inlight::bundle
