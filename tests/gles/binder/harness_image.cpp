// tests/gles/binder/harness_image.cpp: the project's own image of a scene export's draw, the
// reference inlight_gles_binder is compared with. It re-exports the scene as render export-gles
// does (the same options give the same variant: its sources must equal the exported files),
// draws the variant with gles::render_scene (the harness path of render compare) lit by the
// lighting file (zero-padded to the variant's bands, its lights when the variant has them),
// and encodes the radiance to 8 bits with render's auto exposure and image::srgb_encode.
//
//   inlight_gles_harness_image SCENE EXPORT_DIR VARIANT LIGHTING OUT.ppm GRID BAKE_SAMPLES
//                              MAX_BANDS WIDTH_PX
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "gles/scene.h"
#include "image/color.h"
#include "render/compare.h"
#include "render/realtime_lights.h"
#include "sh/sh.h"

using namespace inlight;

int main(int argc, char** argv) {
    if (argc != 10) {
        std::fprintf(stderr, "usage: %s SCENE EXPORT_DIR VARIANT LIGHTING OUT.ppm GRID BAKE_SAMPLES MAX_BANDS "
                             "WIDTH_PX\n", argv[0]);
        return 2;
    }
    try {
        const std::string dir = argv[2], variant = argv[3];
        render::SceneDesc desc = render::load_scene_desc(argv[1]);
        desc.camera.width_px = desc.camera.height_px = std::stoi(argv[9]);
        const render::Scene scene(std::move(desc));
        if (scene.materials().size() != 1) throw Error("the scene must have one material");
        const render::LightingFile lighting = render::read_lighting_file(argv[4]);
        gles::SceneExportOptions options;
        options.grid = argv[6];
        options.bake_samples = std::stoi(argv[7]);
        options.set.max_sh_bands = std::stoi(argv[8]);
        const bool with_lights = variant.find("-l") != std::string::npos;
        if (with_lights) options.set.lights = lighting.lights;
        const std::vector<gles::Export> exports = gles::export_scene(scene, options);
        const auto e = std::find_if(exports.begin(), exports.end(),
                                    [&](const gles::Export& x) { return x.name == variant; });
        if (e == exports.end()) throw Error(str("no variant ", variant, " in the re-export"));
        for (const auto& [file, text] : {std::pair{".vert", &e->vertex_source}, {".frag", &e->fragment_source}}) {
            std::ifstream in(dir + "/" + variant + file);
            if (std::string(std::istreambuf_iterator<char>(in), {}) != *text) {
                throw Error(str(dir, "/", variant, file, " is not the re-export's source"));
            }
        }
        const int bands = std::max(3, e->variant.sh_bands);
        Eigen::MatrixXd coeffs = Eigen::MatrixXd::Zero(sh::count(bands), 3);
        const int rows = std::min<int>(static_cast<int>(lighting.sh.coeffs.rows()), sh::count(bands));
        coeffs.topRows(rows) = lighting.sh.coeffs.topRows(rows);
        const gles::Context context(e->variant.version == gles::GlslVersion::kEs300 ? 3 : 2);
        const gles::SceneFrame frame = gles::render_scene(context, scene, {*e}, coeffs, 1,
                                                          e->variant.lights > 0 ? lighting.lights
                                                                                : std::vector<envmap::DirectionalLight>{});
        const image::Image& r = frame.radiance;
        const double exposure = render::auto_exposure(r);
        std::ofstream out(argv[5], std::ios::binary);
        out << "P6\n" << r.width << " " << r.height << "\n255\n";
        for (int y = 0; y < r.height; ++y) {
            for (int x = 0; x < r.width; ++x) {
                for (int c = 0; c < 3; ++c) {
                    const float v = std::clamp(static_cast<float>(exposure * r.at(x, y, c)), 0.0f, 1.0f);
                    out.put(static_cast<char>(std::lround(255.0f * image::srgb_encode(v))));
                }
            }
        }
        std::printf("harness: %s on %s, exposure %.6g\n", variant.c_str(), context.info().summary().c_str(), exposure);
        return out ? 0 : 1;
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "harness_image: %s\n", ex.what());
        return 1;
    }
}
