#include "bundle/cli.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "bundle/bundle.h"
#include "bundle/catalog.h"
#include "core/json_in.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/validators.h"
#include "core/log.h"

namespace inlight::bundle {

namespace stdfs = std::filesystem;

void add_fabric_maps_options(CLI::App& app, FabricMapsToolOptions& o) {
    app.add_option("--albedo-texture", o.maps.albedo_texture,
                   "Albedo texture (PNG/JPEG sRGB-decoded, EXR linear)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--normal-texture", o.maps.normal_texture,
                   "Tangent-space normal map (read as data); default: derived from the albedo")
        ->check(CLI::ExistingFile);
    app.add_option("--relief-texels", o.maps.relief_texels,
                   "Derived normals: height range of the weave, in texel pitches")
        ->check(app::finite_range(0.0, 1e3))
        ->capture_default_str();
    app.add_option("--blur-px", o.maps.blur_px, "Derived normals: box blur radius, pixels")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    app.add_option("--max-size-px", o.maps.max_size_px,
                   "Longer side of the bundled textures, pixels (larger sources are filtered down)")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--thumbnail-px", o.maps.thumbnail_px, "Longer side of the thumbnail, pixels")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    app.add_option("--name", o.maps.name, "The fabric's name for the catalogue (echoed)");
    app.add_option("--tile-size-m", o.maps.tile_size_m,
                   "Physical width of one texture tile, metres (echoed for the bundle)")
        ->check(app::finite_positive())
        ->capture_default_str();
    app.add_option("-o,--output", o.output, "Folder for albedo.png, normal.png, thumbnail.png")
        ->required();
}

void add_pack_options(CLI::App& app, PackToolOptions& o) {
    app.add_option("--kind", o.kind, "Bundle kind: fabric | device")
        ->required()
        ->check(CLI::IsMember({"fabric", "device"}));
    app.add_option("--id", o.id, "Bundle id: folder name and catalogue key ([a-z0-9_-])")
        ->required()
        ->check(CLI::Validator(  // before any work: a bad id failed after the folders were made
            [](std::string& id) {
                return is_valid_id(id) ? std::string()
                                       : str("'", id, "': expected 1-64 characters of a-z, 0-9, "
                                                      "'_', '-', starting with a letter or digit");
            },
            "ID"));
    app.add_option("--name", o.name, "Human-readable name (default: the id)");
    app.add_option("--file", o.files,
                   "ROLE=SOURCE[@PATH_IN_BUNDLE][#STREAM_INDEX], repeatable (roles: "
                   "docs/bundle-format.md)")
        ->required();
    app.add_option("--property", o.properties,
                   "KEY=VALUE for the manifest's properties (VALUE parsed as JSON, else a string)");
    app.add_option("-o,--output", o.root, "Bundle root: writes ROOT/<kind>s/<id>/")->required();
}

void add_verify_options(CLI::App& app, VerifyToolOptions& o) {
    app.add_option("bundles", o.bundles,
                   "Bundle folders, or bundle roots (every bundle in fabrics/ and devices/)")
        ->required()
        ->check(CLI::ExistingDirectory);
}

void add_index_options(CLI::App& app, IndexToolOptions& o) {
    app.add_option("root", o.root, "Bundle root (fabrics/, devices/)")
        ->required()
        ->check(CLI::ExistingDirectory);
    app.add_option("-o,--output", o.output, "Catalogue database (default ROOT/catalog.sqlite)");
}

FileSpec parse_file_spec(const std::string& spec) {
    FileSpec f;
    const size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
        throw UsageError(str("--file '", spec, "': expected ROLE=SOURCE[@PATH][#N]"));
    }
    f.role = spec.substr(0, eq);
    std::string rest = spec.substr(eq + 1);
    const size_t hash = rest.rfind('#');
    if (hash != std::string::npos) {
        const std::string n = rest.substr(hash + 1);
        if (n.empty() || n.size() > 7 || n.find_first_not_of("0123456789") != std::string::npos) {
            throw UsageError(str("--file '", spec, "': stream index '", n, "' is not an integer"));
        }
        f.stream_index = std::stoi(n);
        rest = rest.substr(0, hash);
    }
    const size_t at = rest.rfind('@');
    if (at != std::string::npos) {
        f.path = rest.substr(at + 1);
        rest = rest.substr(0, at);
    }
    f.source = rest;
    if (f.source.empty()) throw UsageError(str("--file '", spec, "': empty SOURCE"));
    if (f.path.empty()) f.path = stdfs::path(f.source).filename().string();
    return f;
}

void run_fabric_maps(const FabricMapsToolOptions& o, Report& report) {
    ScopedStage stage(report, "fabric maps");
    write_fabric_maps(o.maps, o.output, report);
}

void run_pack(const PackToolOptions& o, Report& report) {
    PackRequest req;
    req.kind = kind_from_string(o.kind);
    req.id = o.id;
    req.name = o.name.empty() ? o.id : o.name;
    for (const std::string& p : o.properties) {
        const size_t eq = p.find('=');
        if (eq == std::string::npos || eq == 0) {
            throw UsageError(str("--property '", p, "': expected KEY=VALUE"));
        }
        const std::string key = p.substr(0, eq), value = p.substr(eq + 1);
        if (json_in::nesting_depth(value) > json_in::kMaxDepth) {
            throw UsageError(str("--property '", key, "': nested deeper than ",
                                 json_in::kMaxDepth, " levels"));
        }
        nlohmann::json v = nlohmann::json::parse(value, nullptr, false);
        // Not JSON: kept as a string, unless it is a number JSON cannot hold ("nan", "inf",
        // "1e999"), which would otherwise become the string "nan".
        char* end = nullptr;
        const double d = std::strtod(value.c_str(), &end);
        if (v.is_discarded() && !value.empty() && *end == '\0' && !std::isfinite(d)) {
            throw UsageError(str("--property '", p, "': not a finite number"));
        }
        if (v.is_discarded()) v = value;
        if (v.is_number_float() && !std::isfinite(v.get<double>())) {
            throw UsageError(str("--property '", p, "': not a finite number"));
        }
        req.properties[key] = v;
    }
    for (const std::string& spec : o.files) {
        const FileSpec f = parse_file_spec(spec);
        std::error_code dir_ec;
        if (stdfs::is_directory(f.source, dir_ec)) {
            throw UsageError(str("--file '", spec, "': ", f.source,
                                 " is a folder; a bundle lists files, one --file each"));
        }
        // An unknown role is the caller's mistake, found before any work: a usage error.
        const auto& roles = roles_for(req.kind);
        if (std::none_of(roles.begin(), roles.end(),
                         [&](const RoleSpec& r) { return f.role == r.role; })) {
            std::string known;
            for (const RoleSpec& r : roles) known += str(known.empty() ? "" : ", ", r.role);
            throw UsageError(str("--file '", spec, "': '", f.role, "' is not a ", o.kind,
                                 " role (roles: ", known, ")"));
        }
        req.files.push_back({f.source, f.path, f.role, f.stream_index});
    }
    const std::string dest =
        (stdfs::path(o.root) / (o.kind + "s") / o.id).string();
    // Nothing is written out of the root through a link (the kind folder, or the bundle's own
    // folder, which pack would replace): refused before any work.
    check_in_root(o.root, o.kind + "s");
    check_in_root(o.root, o.kind + "s/" + o.id);
    // The sources are inputs, declared before any work; one inside the bundle folder would be
    // removed or replaced with the folder (a repack from the bundle's own files).
    std::error_code ec;
    const std::string inside = stdfs::weakly_canonical(dest, ec).string() + "/";
    for (const PackFile& f : req.files) {
        fs::declare_input(f.source, "--file");
        if (stdfs::weakly_canonical(f.source, ec).string().compare(0, inside.size(), inside) == 0) {
            throw UsageError(str("--file ", f.source, ": lies inside the bundle folder ", dest,
                                 ", which pack replaces; copy it out first"));
        }
    }
    Manifest m;
    {
        ScopedStage stage(report, "pack");
        m = write_bundle(dest, req);
    }
    for (const PackFile& f : req.files) report.add_input(f.source);
    report.add_output(dest, "bundle");
    auto& j = report.metrics();
    j["bundle"] = dest;
    j["kind"] = o.kind;
    j["id"] = m.id;
    j["file_count"] = m.files.size();
    j["total_bytes"] = m.total_bytes();
    j["manifest_sha256"] = manifest_sha256(dest);
    log::summary("bundle", "packed", str(o.kind, " ", m.id, ": ", log::count(int64_t(m.files.size()), "file"),
                                          ", ", log::count(int64_t(m.total_bytes()), "byte"), ", in ", dest));
}

void run_verify(const VerifyToolOptions& o, Report& report) {
    std::vector<std::string> dirs;
    for (const std::string& b : o.bundles) {
        if (stdfs::exists(stdfs::path(b) / kManifestName)) {
            dirs.push_back(b);
            continue;
        }
        const size_t before = dirs.size();
        for (const char* k : {"devices", "fabrics"}) {
            const stdfs::path sub = stdfs::path(b) / k;
            if (!stdfs::is_directory(sub)) continue;
            check_in_root(b, k);  // each bundle folder is checked by read_bundle
            std::vector<std::string> found;
            for (const auto& e : stdfs::directory_iterator(sub)) {
                const std::string name = e.path().filename().string();
                if (e.is_directory() && !name.empty() && name[0] != '.') found.push_back(e.path().string());
            }
            std::sort(found.begin(), found.end());
            dirs.insert(dirs.end(), found.begin(), found.end());
        }
        if (dirs.size() == before) {
            dirs.push_back(b);  // neither a bundle nor a root: read_bundle says what is missing
        }
    }
    ScopedStage stage(report, "verify");
    nlohmann::json list = nlohmann::json::array();
    std::vector<std::string> failures;
    uint64_t bytes = 0;
    for (const std::string& d : dirs) {
        try {
            const Manifest m = read_bundle(d);
            bytes += m.total_bytes();
            list.push_back({{"path", d}, {"status", "ok"}, {"kind", to_string(m.kind)},
                            {"id", m.id}, {"file_count", m.files.size()},
                            {"total_bytes", m.total_bytes()},
                            {"manifest_sha256", manifest_sha256(d)}});
            log::verbose(str("bundle: ", d, ": ok"));
        } catch (const Error& e) {
            list.push_back({{"path", d}, {"status", "failed"}, {"error", e.what()}});
            failures.push_back(e.what());
        }
    }
    auto& j = report.metrics();
    j["bundles"] = list;
    j["verified"] = dirs.size() - failures.size();
    j["failed"] = failures.size();
    j["total_bytes"] = bytes;
    if (!failures.empty()) {
        std::string msg = str(failures.size(), " of ", log::count(int64_t(dirs.size()), "bundle"),
                              " failed verification:");
        for (const auto& f : failures) msg += "\n  " + f;
        throw Error(msg);
    }
    log::summary("bundle", "verified", str("OK, ", log::count(int64_t(dirs.size()), "bundle"), ", ",
                                            log::count(int64_t(bytes), "byte")));
}

void run_index(const IndexToolOptions& o, Report& report) {
    const std::string out =
        o.output.empty() ? (stdfs::path(o.root) / "catalog.sqlite").string() : o.output;
    // The catalogue never lands inside a bundle: pack would not list it, and verify would find
    // it a stray file there.
    {
        std::error_code ec;
        const stdfs::path root = stdfs::weakly_canonical(o.root, ec);
        const stdfs::path rel = stdfs::weakly_canonical(out, ec).lexically_relative(root);
        // As written too: through a link out of the root, the resolved path is not below it.
        const stdfs::path lexical = stdfs::absolute(out, ec).lexically_normal().lexically_relative(
            stdfs::absolute(o.root, ec).lexically_normal());
        for (const stdfs::path& r : {rel, lexical}) {
            const std::string first = r.empty() ? "" : r.begin()->string();
            if ((first == "fabrics" || first == "devices") && std::distance(r.begin(), r.end()) > 1) {
                throw UsageError(str("-o ", out, ": inside ", o.root, "/", first,
                                     "/, where the bundles are; write the catalogue beside them"));
            }
        }
        // A catalogue written in the root stays there: not out through a linked folder.
        if (!lexical.empty() && *lexical.begin() != ".." && lexical.has_parent_path()) {
            check_in_root(o.root, lexical.parent_path().string());
        }
    }
    // Declared before the bundles are read: write_catalog declares every bundle file an input,
    // so -o naming one is a usage error, not a bundle overwritten by the catalogue.
    fs::declare_output(out, "-o");
    std::vector<CatalogRow> rows;
    {
        ScopedStage stage(report, "index");
        rows = write_catalog(o.root, out);
    }
    report.add_output(out, "catalog_sqlite");
    nlohmann::json list = nlohmann::json::array();
    int fabrics = 0, devices = 0;
    for (const CatalogRow& r : rows) {
        list.push_back({{"kind", r.kind}, {"id", r.id}, {"name", r.name},
                        {"bundle_path", r.bundle_path}, {"total_bytes", r.total_bytes},
                        {"file_count", r.file_count}});
        (r.kind == "fabric" ? fabrics : devices)++;
    }
    auto& j = report.metrics();
    j["catalog"] = out;
    j["fabrics"] = fabrics;
    j["devices"] = devices;
    j["entries"] = list;
    log::summary("bundle", "catalogue", str(log::count(int64_t(rows.size()), "bundle"), " (",
                                             log::count(fabrics, "fabric"), ", ",
                                             log::count(devices, "device"), ") in ", out));
}

}  // namespace inlight::bundle
