#include "bundle/catalog.h"

#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "bundle/bundle.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::bundle {

namespace stdfs = std::filesystem;

namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE catalog_info (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE fabrics (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    bundle_path TEXT NOT NULL,
    manifest_sha256 TEXT NOT NULL,
    total_bytes INTEGER NOT NULL,
    file_count INTEGER NOT NULL,
    thumbnail_path TEXT NOT NULL,
    thumbnail_width_px INTEGER NOT NULL,
    thumbnail_height_px INTEGER NOT NULL,
    thumbnail_png BLOB NOT NULL,
    sh_bands INTEGER,
    btf_components INTEGER NOT NULL,
    btf_bytes INTEGER NOT NULL,
    shader_variants INTEGER NOT NULL,
    shader_bytes INTEGER NOT NULL,
    properties_json TEXT NOT NULL
);
CREATE TABLE devices (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    bundle_path TEXT NOT NULL,
    manifest_sha256 TEXT NOT NULL,
    total_bytes INTEGER NOT NULL,
    file_count INTEGER NOT NULL,
    properties_json TEXT NOT NULL
);
CREATE TABLE files (
    kind TEXT NOT NULL,
    bundle_id TEXT NOT NULL,
    path TEXT NOT NULL,
    role TEXT NOT NULL,
    bytes INTEGER NOT NULL,
    sha256 TEXT NOT NULL,
    width_px INTEGER,
    height_px INTEGER,
    stream_index INTEGER,
    PRIMARY KEY (kind, bundle_id, path)
);
)sql";

struct DbCloser {
    void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StmtFinalizer {
    void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, DbCloser>;
using Stmt = std::unique_ptr<sqlite3_stmt, StmtFinalizer>;

Db open_db(const std::string& path, int flags) {
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
    Db db(raw);
    if (rc != SQLITE_OK) {
        throw Error(str(path, ": cannot open SQLite database: ",
                        raw ? sqlite3_errmsg(raw) : sqlite3_errstr(rc)));
    }
    return db;
}

void exec(sqlite3* db, const std::string& sql, const std::string& where) {
    char* msg = nullptr;
    if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &msg) != SQLITE_OK) {
        const std::string m = msg ? msg : "unknown error";
        sqlite3_free(msg);
        throw Error(str(where, ": SQLite: ", m));
    }
}

Stmt prepare(sqlite3* db, const std::string& sql, const std::string& where) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
        throw Error(str(where, ": SQLite: ", sqlite3_errmsg(db)));
    }
    return Stmt(s);
}

// Binds values 1..n in order: strings as TEXT, integers as INTEGER, std::nullptr_t as NULL.
struct Binder {
    sqlite3_stmt* s;
    int i = 1;
    Binder& operator<<(const std::string& v) {
        sqlite3_bind_text(s, i++, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
        return *this;
    }
    Binder& operator<<(int64_t v) {
        sqlite3_bind_int64(s, i++, v);
        return *this;
    }
    Binder& operator<<(std::nullptr_t) {
        sqlite3_bind_null(s, i++);
        return *this;
    }
};

void step_done(sqlite3* db, sqlite3_stmt* s, const std::string& where) {
    if (sqlite3_step(s) != SQLITE_DONE) throw Error(str(where, ": SQLite: ", sqlite3_errmsg(db)));
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
}

std::vector<std::string> bundle_dirs(const stdfs::path& folder) {
    std::vector<std::string> out;
    if (!stdfs::is_directory(folder)) return out;
    for (const auto& e : stdfs::directory_iterator(folder)) {
        const std::string name = e.path().filename().string();
        if (name.empty() || name[0] == '.' || !e.is_directory()) continue;
        out.push_back(name);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

std::vector<CatalogRow> write_catalog(const std::string& root, const std::string& db_path) {
    struct Loaded {
        std::string folder;
        Manifest manifest;
        std::string sha;
    };
    std::vector<Loaded> bundles;
    for (const char* kind_dir : {"fabrics", "devices"}) {
        check_in_root(root, kind_dir);  // each bundle is checked by read_bundle
        for (const std::string& name : bundle_dirs(stdfs::path(root) / kind_dir)) {
            const std::string rel = str(kind_dir, "/", name);
            const std::string dir = (stdfs::path(root) / rel).string();
            Manifest m = read_bundle(dir);
            // Inputs of the run (fs::declare_input): no output may land on a bundle's file.
            fs::declare_input((stdfs::path(dir) / kManifestName).string(), "bundle manifest");
            for (const FileEntry& f : m.files) {
                fs::declare_input((stdfs::path(dir) / f.path).string(), "bundle file");
            }
            // read_bundle checked the id against the folder and the kind against kind_dir.
            bundles.push_back({rel, std::move(m), manifest_sha256(dir)});
        }
    }

    std::vector<CatalogRow> rows;
    fs::write_atomic(db_path, [&](const std::string& tmp) {
        Db db = open_db(tmp, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
        exec(db.get(), "PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF;", db_path);
        exec(db.get(), kSchema, db_path);
        exec(db.get(), "BEGIN", db_path);
        {
            Stmt info = prepare(db.get(), "INSERT INTO catalog_info VALUES (?, ?)", db_path);
            for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{
                     {"format", "inlight_catalog"},
                     {"version", std::to_string(kCatalogVersion)},
                     {"bundle_format", kFormatName},
                     {"bundle_version", std::to_string(kFormatVersion)}}) {
                Binder{info.get()} << k << v;
                step_done(db.get(), info.get(), db_path);
            }
        }
        Stmt fabric = prepare(db.get(),
                              "INSERT INTO fabrics VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                              db_path);
        Stmt device = prepare(db.get(), "INSERT INTO devices VALUES (?, ?, ?, ?, ?, ?, ?)",
                              db_path);
        Stmt file = prepare(db.get(), "INSERT INTO files VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                            db_path);
        for (const Loaded& b : bundles) {
            const Manifest& m = b.manifest;
            const std::string kind = to_string(m.kind);
            const std::string where = str(db_path, ": ", b.folder);
            if (m.kind == Kind::kFabric) {
                const FileEntry* thumb = m.find_role("thumbnail");
                const std::string png =
                    fs::read_file((stdfs::path(root) / b.folder / thumb->path).string());
                // What the catalogue screen shows before a download: the BTF's and the
                // shaders' share of the bundle (roles btf_*, shader_*).
                int64_t btf = 0, btf_bytes = 0, variants = 0, shader_bytes = 0;
                for (const FileEntry& f : m.files) {
                    btf += f.role == "btf_component";
                    variants += f.role == "shader_manifest";
                    if (f.role.rfind("btf_", 0) == 0) btf_bytes += static_cast<int64_t>(f.bytes);
                    if (f.role.rfind("shader_", 0) == 0) {
                        shader_bytes += static_cast<int64_t>(f.bytes);
                    }
                }
                Binder bind{fabric.get()};
                bind << m.id << m.name << b.folder << b.sha
                     << static_cast<int64_t>(m.total_bytes())
                     << static_cast<int64_t>(m.files.size()) << thumb->path
                     << static_cast<int64_t>(thumb->width_px)
                     << static_cast<int64_t>(thumb->height_px);
                sqlite3_bind_blob(fabric.get(), bind.i++, png.data(), static_cast<int>(png.size()),
                                  SQLITE_TRANSIENT);
                const auto sh = m.properties.find("sh_bands");
                if (sh != m.properties.end() && sh->is_number_integer()) {
                    bind << sh->get<int64_t>();
                } else {
                    bind << nullptr;
                }
                bind << btf << btf_bytes << variants << shader_bytes << m.properties.dump();
                step_done(db.get(), fabric.get(), where);
            } else {
                Binder{device.get()} << m.id << m.name << b.folder << b.sha
                                     << static_cast<int64_t>(m.total_bytes())
                                     << static_cast<int64_t>(m.files.size())
                                     << m.properties.dump();
                step_done(db.get(), device.get(), where);
            }
            for (const FileEntry& f : m.files) {
                Binder bind{file.get()};
                bind << kind << m.id << f.path << f.role << static_cast<int64_t>(f.bytes)
                     << f.sha256;
                if (f.width_px > 0) {
                    bind << static_cast<int64_t>(f.width_px) << static_cast<int64_t>(f.height_px);
                } else {
                    bind << nullptr << nullptr;
                }
                if (f.stream_index >= 0) {
                    bind << static_cast<int64_t>(f.stream_index);
                } else {
                    bind << nullptr;
                }
                step_done(db.get(), file.get(), where);
            }
            rows.push_back({kind, m.id, m.name, b.folder, b.sha, m.total_bytes(),
                            static_cast<int>(m.files.size())});
        }
        exec(db.get(), "COMMIT", db_path);
    });
    return rows;
}

std::vector<CatalogRow> read_catalog(const std::string& db_path) {
    if (!stdfs::is_regular_file(db_path)) throw Error(str(db_path, ": not found"));
    Db db = open_db(db_path, SQLITE_OPEN_READONLY);
    std::string version;
    try {
        Stmt s = prepare(db.get(), "SELECT value FROM catalog_info WHERE key = 'version'", db_path);
        if (sqlite3_step(s.get()) == SQLITE_ROW) {
            version = reinterpret_cast<const char*>(sqlite3_column_text(s.get(), 0));
        }
    } catch (const Error&) {
        throw Error(str(db_path, ": not an inlight catalogue (no catalog_info table)"));
    }
    if (version != std::to_string(kCatalogVersion)) {
        throw Error(str(db_path, ": catalogue version '", version, "' (this reader knows ",
                        kCatalogVersion, ")"));
    }
    std::vector<CatalogRow> rows;
    Stmt s = prepare(db.get(),
                     "SELECT 'device', id, name, bundle_path, manifest_sha256, total_bytes, "
                     "file_count FROM devices UNION ALL SELECT 'fabric', id, name, bundle_path, "
                     "manifest_sha256, total_bytes, file_count FROM fabrics ORDER BY 1, 2",
                     db_path);
    while (sqlite3_step(s.get()) == SQLITE_ROW) {
        auto text = [&](int c) {
            return std::string(reinterpret_cast<const char*>(sqlite3_column_text(s.get(), c)));
        };
        rows.push_back({text(0), text(1), text(2), text(3), text(4),
                        static_cast<uint64_t>(sqlite3_column_int64(s.get(), 5)),
                        sqlite3_column_int(s.get(), 6)});
    }
    return rows;
}

}  // namespace inlight::bundle
