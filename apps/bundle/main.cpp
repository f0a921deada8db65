// bundle: asset bundles for the app (docs/bundle-format.md).
//   bundle fabric-maps: a fabric's textures in the app's formats (albedo, normal map, thumbnail)
//   bundle pack:        files into a bundle folder with a versioned, hashed manifest
//   bundle verify:      check bundles (schema, paths, sizes, SHA-256); exit 1 on any failure
//   bundle index:       the SQLite catalogue of a bundle root
#include <string>
#include <vector>

#include "bundle/cli.h"
#include "core/app.h"
#include "core/modes.h"

namespace {

struct Mode {
    const char* name;
    const char* purpose;
    const char* example;
};

constexpr Mode kModes[] = {
    {"fabric-maps",
     "bundle fabric-maps: a fabric's albedo as 8-bit sRGB PNG, its normal map as linear PNG "
     "(given, or derived from the weave in the albedo) and a catalogue thumbnail",
     "bundle fabric-maps --albedo-texture fabric_diffuse.png --relief-texels 1.5 -o out/maps"},
    {"pack",
     "bundle pack: copy files into ROOT/<kind>s/<id>/ with a versioned manifest listing each "
     "file's role, size and SHA-256; written atomically and verified",
     "bundle pack --kind fabric --id satin --file albedo=out/maps/albedo.png "
     "--file thumbnail=out/maps/thumbnail.png --file material=satin.toml -o out/bundles"},
    {"verify",
     "bundle verify: check bundle folders (manifest schema and version, paths inside the "
     "bundle, every file's size and SHA-256, no unlisted file)",
     "bundle verify out/bundles/fabrics/satin out/bundles --report verify.json"},
    {"index",
     "bundle index: verify every bundle of a root and write the SQLite catalogue the app's "
     "catalogue screen reads",
     "bundle index out/bundles -o out/bundles/catalog.sqlite"},
};

}  // namespace

int main(int argc, char** argv) {
    using namespace inlight;
    const std::string mode = argc > 1 ? argv[1] : "";
    for (const Mode& md : kModes) {
        if (mode != md.name) continue;
        CLI::App app{md.purpose, "bundle " + mode};
        app::CommonArgs common;
        bundle::FabricMapsToolOptions maps;
        bundle::PackToolOptions pack;
        bundle::VerifyToolOptions verify;
        bundle::IndexToolOptions index;
        if (mode == "fabric-maps") bundle::add_fabric_maps_options(app, maps);
        if (mode == "pack") bundle::add_pack_options(app, pack);
        if (mode == "verify") bundle::add_verify_options(app, verify);
        if (mode == "index") bundle::add_index_options(app, index);
        app::setup(app, common, md.example);
        if (auto code = app::parse(app, argc, argv, 1)) return *code;
        return app::run("bundle", app, common, argc, argv, [&](Report& report) {
            report.metrics()["mode"] = mode;
            if (mode == "fabric-maps") bundle::run_fabric_maps(maps, report);
            if (mode == "pack") bundle::run_pack(pack, report);
            if (mode == "verify") bundle::run_verify(verify, report);
            if (mode == "index") bundle::run_index(index, report);
        });
    }

    std::vector<app::ModeHelp> modes;
    for (const Mode& md : kModes) modes.push_back({md.name, md.purpose, md.example});
    return app::list_modes("bundle", "bundle: asset bundles and the catalogue for the app", modes,
                           "0 ok, 1 runtime error (a bundle failed verification), 2 usage error.",
                           argc, argv);
}
