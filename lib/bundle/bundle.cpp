#include "bundle/bundle.h"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>

#include "bundle/contents.h"
#include "core/json_in.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/json_out.h"
#include "core/report.h"
#include "core/sha256.h"
#include "image/image.h"

namespace inlight::bundle {

namespace stdfs = std::filesystem;

namespace {

const RoleSpec& role_spec(Kind kind, const std::string& role) {
    for (const RoleSpec& r : roles_for(kind)) {
        if (role == r.role) return r;
    }
    std::string known;
    for (const RoleSpec& r : roles_for(kind)) known += (known.empty() ? "" : ", ") + std::string(r.role);
    throw Error(str("role '", role, "' is not a ", to_string(kind), " role (known: ", known, ")"));
}

// True when `p` (canonical) is `root` (canonical) or inside it.
bool inside(const stdfs::path& p, const stdfs::path& root) {
    const std::string r = root.string(), s = p.string();
    return s.size() > r.size() && s.compare(0, r.size(), r) == 0 && s[r.size()] == '/';
}

// Moves the finished folder `tmp` onto `dest`: a plain rename when `dest` does not exist, an
// atomic exchange (renameat2 RENAME_EXCHANGE) when it does; the old content ends in `tmp` and
// is removed.
void commit_folder(const stdfs::path& tmp, const stdfs::path& dest) {
    std::error_code ec;
    if (!stdfs::exists(stdfs::symlink_status(dest, ec))) {
        stdfs::rename(tmp, dest, ec);
        if (ec) throw Error(str(dest.string(), ": cannot move the finished bundle into place: ", ec.message()));
        return;
    }
    if (::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, dest.c_str(), RENAME_EXCHANGE) != 0) {
        // A file system without RENAME_EXCHANGE: two renames (a reader may briefly miss it).
        const stdfs::path old = tmp.string() + ".old";
        stdfs::rename(dest, old, ec);
        if (ec) throw Error(str(dest.string(), ": cannot replace the old bundle: ", ec.message()));
        stdfs::rename(tmp, dest, ec);
        if (ec) {
            stdfs::rename(old, dest);
            throw Error(str(dest.string(), ": cannot move the finished bundle into place: ", ec.message()));
        }
        stdfs::remove_all(old, ec);
        return;
    }
    stdfs::remove_all(tmp, ec);
}

}  // namespace

Manifest write_bundle(const std::string& dest, const PackRequest& request) {
    Manifest m;
    m.kind = request.kind;
    m.id = request.id;
    m.name = request.name;
    m.created_by = str("inlight ", version_string());
    m.properties = request.properties;
    const stdfs::path dest_path(dest);
    if (dest_path.filename().empty()) throw Error(str(dest, ": bundle folder name is empty"));
    std::set<std::string> seen;
    for (const PackFile& f : request.files) {
        check_relative_path(f.path, str(dest, ": file for role '", f.role, "'"));
        role_spec(request.kind, f.role);
        if (!seen.insert(f.path).second) {
            throw Error(str(dest, ": two files would be written to '", f.path, "'"));
        }
        if (!stdfs::is_regular_file(f.source)) {
            throw Error(str(f.source, ": not found or not a regular file (role '", f.role, "')"));
        }
    }

    static std::atomic<int> counter{0};
    const stdfs::path parent = dest_path.parent_path();
    std::error_code ec;
    if (!parent.empty()) {
        stdfs::create_directories(parent, ec);
        if (ec) throw Error(str(dest, ": cannot create ", parent.string(), ": ", ec.message()));
    }
    // Hidden folders of this id left by a killed writer go first (one writer per id at a time).
    const std::string prefix = str(".", dest_path.filename().string(), ".tmp-");
    if (stdfs::is_directory(parent.empty() ? stdfs::path(".") : parent)) {
        for (const auto& e : stdfs::directory_iterator(parent.empty() ? stdfs::path(".") : parent)) {
            if (e.path().filename().string().rfind(prefix, 0) == 0) stdfs::remove_all(e.path(), ec);
        }
    }
    const stdfs::path tmp = parent / str(prefix, ::getpid(), "-", counter++);
    try {
        stdfs::create_directories(tmp);
        for (const PackFile& f : request.files) {
            const stdfs::path out = tmp / f.path;
            stdfs::create_directories(out.parent_path());
            stdfs::copy_file(f.source, out, stdfs::copy_options::overwrite_existing);
            const RoleSpec& spec = role_spec(request.kind, f.role);
            FileEntry e;
            e.path = f.path;
            e.role = f.role;
            e.media_type = media_type_for(f.path);
            e.color_space = spec.color_space;
            e.bytes = stdfs::file_size(out);
            e.sha256 = sha256_file(out.string());
            e.stream_index = f.stream_index;
            if (e.media_type == "image/png" || e.media_type == "image/x-exr") {
                const image::ImageInfo info = image::read_info(out.string());
                e.width_px = info.width;
                e.height_px = info.height;
            }
            m.files.push_back(std::move(e));
        }
        // Validate through the reader's own schema check before anything becomes visible.
        const nlohmann::json j = to_json(m);
        m = manifest_from_json(j, str(dest, "/", kManifestName));
        // Inside the private folder committed below: visible now, not with the run's outputs.
        fs::write_text_atomic((tmp / kManifestName).string(),
                             dump_finite(j, 2, str(dest, "/", kManifestName)), fs::Commit::kNow);
        read_bundle(tmp.string());
        commit_folder(tmp, dest_path);
    } catch (const stdfs::filesystem_error& e) {
        stdfs::remove_all(tmp, ec);
        throw Error(str(dest, ": ", e.what()));
    } catch (...) {
        stdfs::remove_all(tmp, ec);
        throw;
    }
    return m;
}

namespace {

// Where a folder sits in a bundle root: ROOT/fabrics/<name> or ROOT/devices/<name>, not a hidden
// staging folder (pack checks its ".<id>.tmp-..." folder before the swap); else kind_dir empty.
struct PlaceInRoot {
    std::string root, kind_dir, name;
};

PlaceInRoot place_in_root(const std::string& dir) {
    stdfs::path lexical = stdfs::path(dir).lexically_normal();
    if (!lexical.has_filename()) lexical = lexical.parent_path();
    const std::string parent = lexical.parent_path().filename().string();
    const std::string name = lexical.filename().string();
    if ((parent != "fabrics" && parent != "devices") || name.empty() || name[0] == '.') return {};
    const stdfs::path root = lexical.parent_path().parent_path();
    return {root.empty() ? "." : root.string(), parent, name};
}

Manifest read_bundle_once(const std::string& dir) {
    std::error_code ec;
    const PlaceInRoot place = place_in_root(dir);
    // First, so that nothing is read through a link out of the root.
    if (!place.kind_dir.empty()) check_in_root(place.root, place.kind_dir + "/" + place.name);
    if (!stdfs::is_directory(dir, ec)) throw Error(str(dir, ": not a bundle folder (not found)"));
    const stdfs::path root = stdfs::canonical(dir);
    const std::string manifest_path = (stdfs::path(dir) / kManifestName).string();
    const stdfs::path manifest_real = stdfs::weakly_canonical(root / kManifestName, ec);
    if (!stdfs::exists(root / kManifestName)) {
        throw Error(str(manifest_path, ": missing (not a bundle folder, or an unfinished one)"));
    }
    if (ec || !inside(manifest_real, root)) {
        throw Error(str(manifest_path, ": is a symlink to ", manifest_real.string(),
                        ", outside the bundle"));
    }
    const nlohmann::json j = json_in::read_file(manifest_path);
    Manifest m = manifest_from_json(j, manifest_path);
    std::set<std::string> listed = {kManifestName};
    for (const FileEntry& f : m.files) {
        const std::string shown = str(dir, "/", f.path);
        const stdfs::path p = root / f.path;
        // Every component, symlinks resolved, must stay inside the folder.
        const stdfs::path real = stdfs::weakly_canonical(p, ec);
        if (ec) throw Error(str(shown, ": cannot resolve: ", ec.message()));
        if (!inside(real, root)) {
            throw Error(str(shown, ": resolves to ", real.string(),
                            ", outside the bundle (symlink out of the bundle)"));
        }
        const stdfs::file_status st = stdfs::status(real, ec);
        if (!stdfs::exists(st)) throw Error(str(shown, ": missing (listed in the manifest)"));
        if (!stdfs::is_regular_file(st)) throw Error(str(shown, ": not a regular file"));
        const uint64_t size = stdfs::file_size(real);
        if (size < f.bytes) {
            throw Error(str(shown, ": truncated: ", size, " of ", f.bytes, " bytes"));
        }
        if (size > f.bytes) {
            throw Error(str(shown, ": ", size, " bytes, the manifest says ", f.bytes));
        }
        const std::string hash = sha256_file(real.string());
        if (hash != f.sha256) {
            throw Error(str(shown, ": sha256 mismatch: the manifest says ", f.sha256,
                            ", the file has ", hash));
        }
        listed.insert(f.path);
    }
    check_contents(m, dir);
    for (auto it = stdfs::recursive_directory_iterator(root); it != stdfs::recursive_directory_iterator(); ++it) {
        if (it->is_directory() && !it->is_symlink()) continue;
        const std::string rel = stdfs::relative(it->path(), root).generic_string();
        if (!listed.count(rel)) {
            throw Error(str(dir, "/", rel, ": not listed in the manifest (stray or partial file)"));
        }
    }
    // In a bundle root, the folder is named by the id and sits under its kind's folder.
    if (!place.kind_dir.empty()) {
        if (m.id != place.name) {
            throw Error(str(dir, ": folder name differs from the manifest's id '", m.id, "'"));
        }
        if (place.kind_dir != to_string(m.kind) + "s") {
            throw Error(str(dir, ": a ", to_string(m.kind), " bundle in ", place.kind_dir, "/"));
        }
    }
    return m;
}

}  // namespace

Manifest read_bundle(const std::string& dir) {
    const std::string manifest_path = (stdfs::path(dir) / kManifestName).string();
    for (int attempt = 1;; ++attempt) {
        std::string before;
        try {
            before = fs::read_file(manifest_path);
        } catch (const Error&) {
        }
        try {
            return read_bundle_once(dir);
        } catch (const Error&) {
            // Replaced while it was read (pack swaps the whole folder in): read it again.
            std::string after;
            try {
                after = fs::read_file(manifest_path);
            } catch (const Error&) {
            }
            if (attempt >= 5 || before.empty() || after == before) throw;
        }
    }
}

void check_in_root(const std::string& root, const std::string& rel) {
    std::error_code ec;
    const stdfs::path path = stdfs::path(root) / rel;
    if (!stdfs::exists(stdfs::symlink_status(path, ec))) return;
    const stdfs::path root_real = stdfs::weakly_canonical(root, ec);
    const stdfs::path real = stdfs::weakly_canonical(path, ec);
    if (!ec && real == (root_real / rel).lexically_normal()) return;
    const std::string where = inside(real, root_real)
                                  ? str(", elsewhere in the bundle root ", root)
                                  : str(", outside the bundle root ", root);
    throw Error(str(path.string(), ": resolves through a symlink to ", real.string(), where,
                    " (a bundle root holds its bundles and what is written there, not links "
                    "to them: replace the link by the folder)"));
}

std::string manifest_sha256(const std::string& dir) {
    return sha256_file((stdfs::path(dir) / kManifestName).string());
}

}  // namespace inlight::bundle
