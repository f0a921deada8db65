// tests/gles/binder/harness_image.cpp: the project's own image of a scene export's draw, the
// reference inlight_gles_binder is compared with. It re-exports the scene as render export-gles
// does (the same options give the same variant: its sources must equal the exported files),
// draws the variant with gles::render_scene (the harness path of render compare) lit by the
// lighting file (zero-padded to the variant's bands, its lights when the variant has them),
// and encodes the radiance to 8 bits with render's auto exposure and image::srgb_encode.
//
//   inlight_gles_harness_image SCENE EXPORT_DIR VARIANT[,VARIANT...] LIGHTING OUT.ppm GRID
//                              BAKE_SAMPLES MAX_BANDS WIDTH_PX [MAX_TEXTURE_SIZE]
// (several variants: OUT.ppm holds '%', replaced by each variant's name.)
// (MAX_TEXTURE_SIZE: export-gles' --gles-max-texture-size, default 0; a "...-trilinear" variant
// is re-exported with --gles-texture-filter trilinear.)
//   inlight_gles_harness_image --table TABLE.bin MATERIAL.toml EXPORT_DIR VARIANT LIGHTING OUT.ppm N
//                              [ALBEDO.png NORMAL.png TILE_SIZE_M]
// The second form is brdf-sh-bake's export (a bundle's shaders: no scene): the variant re-exported
// from the table and material (and the textures and tile size brdf-sh-bake was given, as
// --gles-albedo-texture, --gles-normal-texture, --gles-tile-size-m) at the minimum limits, drawn
// with gles::draw on the quad the binder states for --quad (tests/gles/binder/binder.cpp,
// quad_vertices()) into N x N pixels.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>

#include "brdf/brdf.h"
#include "brdf/table.h"
#include "core/error.h"
#include "core/report.h"
#include "gles/cli.h"
#include "gles/scene.h"
#include "image/color.h"
#include "render/compare.h"
#include "render/realtime_lights.h"
#include "sh/sh.h"

using namespace inlight;

namespace {

/// 8-bit codes by render's auto exposure and the sRGB OETF, as a binary PPM.
bool write_codes(const std::string& path, const image::Image& r) {
    const double exposure = render::auto_exposure(r);
    std::ofstream out(path, std::ios::binary);
    out << "P6\n" << r.width << " " << r.height << "\n255\n";
    for (int y = 0; y < r.height; ++y) {
        for (int x = 0; x < r.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const float v = std::clamp(static_cast<float>(exposure * r.at(x, y, c)), 0.0f, 1.0f);
                out.put(static_cast<char>(std::lround(255.0f * image::srgb_encode(v))));
            }
        }
    }
    std::printf("harness: exposure %.6g\n", exposure);
    return static_cast<bool>(out);
}

void check_sources(const gles::Export& e, const std::string& dir) {
    for (const auto& [file, text] : {std::pair{".vert", &e.vertex_source}, {".frag", &e.fragment_source}}) {
        std::ifstream in(dir + "/" + e.name + file);
        if (std::string(std::istreambuf_iterator<char>(in), {}) != *text) {
            throw Error(str(dir, "/", e.name, file, " is not the re-export's source"));
        }
    }
}

Eigen::MatrixXd padded(const render::LightingFile& lighting, int bands) {
    Eigen::MatrixXd coeffs = Eigen::MatrixXd::Zero(sh::count(bands), 3);
    const int rows = std::min<int>(static_cast<int>(lighting.sh.coeffs.rows()), sh::count(bands));
    coeffs.topRows(rows) = lighting.sh.coeffs.topRows(rows);
    return coeffs;
}

/// brdf-sh-bake's variant `name` (<stem>-es<v>-<mode>-b<bands>-<precision>) of the table.
int table_image(int argc, char** argv) {
    const brdf::Table table = brdf::read_binary(argv[2]);
    gles::MaterialInputs in;
    in.brdf = brdf::load_material(argv[3]);
    const std::string dir = argv[4], name = argv[5];
    in.name = name.substr(0, name.find("-es"));
    if (argc == 12) {
        gles::ExportArgs args;
        args.albedo_texture = argv[9];
        args.normal_texture = argv[10];
        args.tile_size_m = std::stod(argv[11]);
        Report report("harness_image");
        args.add_textures(in, report);
    }
    gles::Variant v;
    v.version = name.find("-es100-") != std::string::npos ? gles::GlslVersion::kEs100 : gles::GlslVersion::kEs300;
    v.mode = name.find("-seed-") != std::string::npos ? gles::ShaderMode::kSeed : gles::ShaderMode::kConsistent;
    v.sh_bands = std::stoi(name.substr(name.find("-b") + 2));
    std::string rest = name;
    const std::string trilinear = "-trilinear";
    if (rest.size() > trilinear.size() && rest.compare(rest.size() - trilinear.size(), trilinear.size(), trilinear) == 0) {
        v.texture_filter = gles::TextureFilter::kTrilinear;
        rest.resize(rest.size() - trilinear.size());
    }
    v.precision = gles::precision_from_string(rest.substr(rest.rfind('-') + 1));
    // The limits the variant was exported for (--gles-max-texture-size), from its manifest.
    gles::Limits limits = gles::Limits::minimum(v.version);
    {
        std::ifstream mf(dir + "/" + name + ".json");
        const nlohmann::json m = nlohmann::json::parse(std::string(std::istreambuf_iterator<char>(mf), {}));
        limits.max_texture_size = m.at("gl_limits_needed").at("limits_given").at("max_texture_size").get<int>();
    }
    const bool lambert = in.brdf.specular == brdf::Model::kLambert;
    const gles::Export e = gles::export_variant(lambert ? nullptr : &table, in, v, limits);
    if (e.name != name) throw Error(str("re-exported ", e.name, ", not ", name));
    check_sources(e, dir);
    const render::LightingFile lighting = render::read_lighting_file(argv[6]);
    const int n = std::stoi(argv[8]);
    gles::Mesh quad;  // the binder's quad_vertices()
    for (const auto& [x, y] : {std::pair{-1, 1}, {1, 1}, {1, -1}, {-1, 1}, {1, -1}, {-1, -1}}) {
        quad.position.emplace_back(x, y, 0);
        quad.normal.push_back(Eigen::Vector3d(0.6 * x, 0.6 * y, 1).normalized().cast<float>());
        quad.tangent.emplace_back(1, 0, 0);
        quad.uv.emplace_back((x + 1) / 2.0f, (1 - y) / 2.0f);
    }
    gles::Bindings b;
    b.sh = padded(lighting, std::max(3, v.sh_bands));
    b.albedo = in.brdf.albedo.cast<float>();
    b.uv_scale = in.uv_scale;
    gles::Texture8 albedo{in.albedo_texture_px.x(), in.albedo_texture_px.y(), in.albedo_rgba8};
    gles::Texture8 normal{in.normal_texture_px.x(), in.normal_texture_px.y(), in.normal_rgba8};
    if (in.has_albedo_texture()) b.albedo_texture = &albedo;
    if (in.has_normal_texture()) b.normal_texture = &normal;
    const gles::Context context(v.version == gles::GlslVersion::kEs300 ? 3 : 2);
    const gles::Readback rb = gles::draw(context, e, b, quad, n, n, gles::TargetFormat::kRgba32f);
    image::Image r(n, n, 3, image::ColorSpace::kLinearSrgb);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            for (int c = 0; c < 3; ++c) r.at(x, y, c) = rb.at(x, y, c);
        }
    }
    return write_codes(argv[7], r) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    if ((argc == 9 || argc == 12) && std::string(argv[1]) == "--table") {
        try {
            return table_image(argc, argv);
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "harness_image: %s\n", ex.what());
            return 1;
        }
    }
    if (argc != 10 && argc != 11) {
        std::fprintf(stderr, "usage: %s SCENE EXPORT_DIR VARIANT LIGHTING OUT.ppm GRID BAKE_SAMPLES MAX_BANDS "
                             "WIDTH_PX [MAX_TEXTURE_SIZE]\n", argv[0]);
        return 2;
    }
    try {
        const std::string dir = argv[2], out_pattern = argv[5];
        std::vector<std::string> variants;
        for (std::string list = argv[3]; !list.empty();) {
            const size_t comma = list.find(',');
            variants.push_back(list.substr(0, comma));
            list = comma == std::string::npos ? "" : list.substr(comma + 1);
        }
        if (variants.size() > 1 && out_pattern.find('%') == std::string::npos) {
            throw Error("several variants need OUT.ppm with '%' (replaced by each variant's name)");
        }
        render::SceneDesc desc = render::load_scene_desc(argv[1]);
        desc.camera.width_px = desc.camera.height_px = std::stoi(argv[9]);
        const render::Scene scene(std::move(desc));
        if (scene.materials().size() != 1) throw Error("the scene must have one material");
        const render::LightingFile lighting = render::read_lighting_file(argv[4]);
        // One re-export per (lights, texture filter) the variants ask for: the scene's table
        // is baked once per set, not once per variant (a process per variant took half the test).
        std::map<std::pair<bool, bool>, std::vector<gles::Export>> exported;
        for (const std::string& variant : variants) {
            gles::SceneExportOptions options;
            options.grid = argv[6];
            options.bake_samples = std::stoi(argv[7]);
            options.set.max_sh_bands = std::stoi(argv[8]);
            if (argc == 11) options.set.max_texture_size = std::stoi(argv[10]);
            const std::string trilinear = "-trilinear";
            const bool is_trilinear = variant.size() > trilinear.size() &&
                variant.compare(variant.size() - trilinear.size(), trilinear.size(), trilinear) == 0;
            if (is_trilinear) options.set.texture_filter = gles::TextureFilter::kTrilinear;
            const bool with_lights = variant.find("-l") != std::string::npos;
            if (with_lights) options.set.lights = lighting.lights;
            std::vector<gles::Export>& exports = exported[{with_lights, is_trilinear}];
            if (exports.empty()) exports = gles::export_scene(scene, options);
            const auto e = std::find_if(exports.begin(), exports.end(),
                                        [&](const gles::Export& x) { return x.name == variant; });
            if (e == exports.end()) throw Error(str("no variant ", variant, " in the re-export"));
            check_sources(*e, dir);
            const Eigen::MatrixXd coeffs = padded(lighting, std::max(3, e->variant.sh_bands));
            const gles::Context context(e->variant.version == gles::GlslVersion::kEs300 ? 3 : 2);
            const gles::SceneFrame frame = gles::render_scene(context, scene, {*e}, coeffs, 1,
                                                              e->variant.lights > 0 ? lighting.lights
                                                                                    : std::vector<envmap::DirectionalLight>{});
            std::printf("harness: %s on %s\n", variant.c_str(), context.info().summary().c_str());
            std::string out = out_pattern;
            if (const size_t at = out.find('%'); at != std::string::npos) out.replace(at, 1, variant);
            if (!write_codes(out, frame.radiance)) return 1;
        }
        return 0;
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "harness_image: %s\n", ex.what());
        return 1;
    }
}
