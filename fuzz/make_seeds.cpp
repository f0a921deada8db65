// make_seeds SOURCE_DIR OUT_DIR: the seed corpus of every harness, OUT_DIR/<harness>/..., made by
// the project's own writers (images, SH files, corner files, response curves, BTF zips, bundles)
// and the project's own TOML files under SOURCE_DIR/configs. No third-party file is used.
#include <zip.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "brdf/brdf.h"
#include "brdf/table.h"
#include "btf/synthetic.h"
#include "calib/corner_file.h"
#include "calib/response.h"
#include "core/error.h"
#include "core/fs.h"
#include "envmap/lights.h"
#include "samples.h"
#include "sh/sh_io.h"

namespace stdfs = std::filesystem;
using namespace inlight;

namespace {

std::string g_out;

/// Writes OUT/<harness>/<name> = prefix + bytes.
void seed(const std::string& harness, const std::string& name, const std::string& bytes,
          const std::string& prefix = "") {
    stdfs::create_directories(g_out + "/" + harness);
    std::ofstream out(g_out + "/" + harness + "/" + name, std::ios::binary | std::ios::trunc);
    out << prefix << bytes;
    if (!out) throw Error(str(g_out, "/", harness, "/", name, ": cannot write"));
}

void image_seeds(const std::string& tmp) {
    const image::Image env = fuzz::gradient_image(16, 8);  // 2:1, a lat-long map
    image::WriteOptions half;
    half.exr_half = true;
    image::write_image(tmp + "/env.exr", env);
    seed("image", "float.exr", fs::read_file(tmp + "/env.exr"), std::string(1, '\0'));
    image::write_image(tmp + "/env_half.exr", env, half);
    seed("image", "half.exr", fs::read_file(tmp + "/env_half.exr"), std::string(1, '\0'));
    image::write_image(tmp + "/env.hdr", env);
    seed("image", "rgbe.hdr", fs::read_file(tmp + "/env.hdr"), std::string(1, '\1'));
    image::write_image(tmp + "/env.png", env);
    seed("image", "8bit.png", fs::read_file(tmp + "/env.png"), std::string(1, '\2'));
    image::WriteOptions sixteen;
    sixteen.bits = 16;
    image::write_image(tmp + "/env16.png", env, sixteen);
    seed("image", "16bit.png", fs::read_file(tmp + "/env16.png"), std::string(1, '\2'));
}

void toml_seeds(const std::string& source_dir) {
    for (const auto& e : stdfs::recursive_directory_iterator(source_dir + "/configs")) {
        if (e.is_regular_file() && e.path().extension() == ".toml") {
            const std::string rel = stdfs::relative(e.path(), source_dir + "/configs").string();
            std::string name = rel;
            for (char& c : name) c = c == '/' ? '_' : c;
            seed("toml", name, fs::read_file(e.path().string()));
        }
    }
    brdf::Material m;
    seed("toml", "material_to_toml.toml", brdf::to_toml(m));
    seed("toml", "config.toml", "gain = 2.5\ncount = 3\nname = \"x\"\nlist = [1, 2.5]\nflag = true\n"
                                "threads = 2\nseed = 7\n");
}

void mesh_seeds() {
    // A unit quad as two triangles, with uvs and normals, in each syntax the readers take.
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4 -2 -1\n";
    seed("mesh", "quad.obj", obj, std::string(1, '\0'));
    const std::string header =
        "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty float u\n"
        "property float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const float v[4][8] = {{0, 0, 0, 0, 0, 1, 0, 0},
                           {1, 0, 0, 0, 0, 1, 1, 0},
                           {1, 1, 0, 0, 0, 1, 1, 1},
                           {0, 1, 0, 0, 0, 1, 0, 1}};
    const int f[2][3] = {{0, 1, 2}, {0, 2, 3}};
    std::string ascii = "ply\nformat ascii 1.0\n" + header;
    for (const auto& row : v) {
        for (int k = 0; k < 8; ++k) ascii += str(row[k], k < 7 ? " " : "\n");
    }
    for (const auto& t : f) ascii += str("3 ", t[0], " ", t[1], " ", t[2], "\n");
    seed("mesh", "quad_ascii.ply", ascii, std::string(1, '\1'));
    std::string binary = "ply\nformat binary_little_endian 1.0\n" + header;
    binary.append(reinterpret_cast<const char*>(v), sizeof v);
    for (const auto& t : f) {
        binary += static_cast<char>(3);
        binary.append(reinterpret_cast<const char*>(t), sizeof t);
    }
    seed("mesh", "quad_binary.ply", binary, std::string(1, '\1'));
}

void corner_seeds(const std::string& tmp) {
    std::vector<calib::View> views(2);
    for (int i = 0; i < 2; ++i) {
        for (int r = 0; r < 2; ++r) {
            for (int c = 0; c < 3; ++c) {
                views[i].image_points.emplace_back(100.0 + 40 * c + 5 * i, 80.0 + 40 * r);
                views[i].object_points.emplace_back(0.025 * c, 0.025 * r, 0.0);
            }
        }
        views[i].name = str("view", i, ".png");
    }
    calib::write_corner_files(tmp + "/image_points.yml", tmp + "/object_points.yml", views, 640,
                              480);
    seed("corners", "pair.yml",
         fs::read_file(tmp + "/image_points.yml") + std::string(1, '\0') +
             fs::read_file(tmp + "/object_points.yml"));
    seed("corners", "image_points_only.yml", fs::read_file(tmp + "/image_points.yml"));
}

void sh_seeds(const std::string& tmp) {
    for (int bands : {1, 3}) {
        sh::CoefficientSet set;
        set.sh_bands = bands;
        set.coeffs = Eigen::MatrixXd::Zero(bands * bands, 3);
        for (int k = 0; k < bands * bands; ++k) set.coeffs.row(k) << 0.1 * k, 0.5, -0.2 * k;
        seed("sh", str("bands", bands, ".json"), sh::to_json(set).dump(1), std::string(1, '\0'));
        sh::write_binary(tmp + "/c.bin", set);
        seed("sh", str("bands", bands, ".bin"), fs::read_file(tmp + "/c.bin"), std::string(1, '\1'));
    }
}

void response_seeds(const std::string& tmp) {
    calib::ResponseFit fit;
    for (const char* channel : {"r", "g", "b"}) {
        std::array<double, calib::kCodes> g{};
        for (int z = 0; z < calib::kCodes; ++z) g[z] = std::log((z + 1.0) / (calib::kReferenceCode + 1.0));
        fit.curve.channel_names.push_back(channel);
        fit.curve.log_exposure.push_back(g);
        fit.fit_rms_log.push_back(0.01);
    }
    fit.samples = 64;
    calib::write_response(tmp + "/response.json", fit, 50, {0.01, 0.04}, {"a.png", "b.png"});
    seed("response", "response.json", fs::read_file(tmp + "/response.json"));
}

void zip_folder(const std::string& dir, const std::string& zip_path) {
    int err = 0;
    zip_t* z = zip_open(zip_path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    if (!z) throw Error(str(zip_path, ": cannot create"));
    std::vector<std::string> paths;
    for (const auto& e : stdfs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) paths.push_back(e.path().string());
    }
    std::sort(paths.begin(), paths.end());
    for (const std::string& p : paths) {
        zip_source_t* s = zip_source_file(z, p.c_str(), 0, -1);
        if (!s || zip_file_add(z, stdfs::relative(p, dir).generic_string().c_str(), s, 0) < 0) {
            throw Error(str(zip_path, ": cannot add ", p));
        }
    }
    if (zip_close(z) != 0) throw Error(str(zip_path, ": cannot write"));
}

void btf_seeds(const std::string& tmp) {
    // The light and view sets btf_fuzz.cpp opens with.
    fs::write_text_atomic(tmp + "/lights.txt", "0 0\n15 0\n30 90\n60 200\n");
    fs::write_text_atomic(tmp + "/views.txt", "0 0\n30 0\n45 120\n");
    btf::AnalyticBtfOptions opt;
    opt.width = 4;
    opt.height = 3;
    opt.lights = btf::read_directions(tmp + "/lights.txt");
    opt.views = btf::read_directions(tmp + "/views.txt");
    opt.rank = 2;
    const btf::AnalyticBtf truth(opt);
    btf::UboWriteOptions flat;
    flat.per_view_folders = false;
    btf::write_ubo2003(truth, tmp + "/btf_folders");
    btf::write_ubo2003(truth, tmp + "/btf_flat", flat);
    zip_folder(tmp + "/btf_folders", tmp + "/folders.zip");
    zip_folder(tmp + "/btf_flat", tmp + "/flat.zip");
    seed("btf", "per_view_folders.zip", fs::read_file(tmp + "/folders.zip"));
    seed("btf", "flat.zip", fs::read_file(tmp + "/flat.zip"));
}

void btfpca_seeds(const std::string& tmp) {
    // btf-pca.json, NUL, weights.bin: the folder btfpca_fuzz.cpp reads holds the same images.
    fuzz::make_compressed_btf(tmp + "/btfpca");
    seed("btfpca", "btfpca.json",
         fs::read_file(tmp + "/btfpca/btf-pca.json") + std::string(1, '\0') +
             fs::read_file(tmp + "/btfpca/weights.bin"));
}

void lighting_seeds() {
    // As envmap-project writes them: SH coefficients, with and without dominant lights.
    sh::CoefficientSet set;
    set.sh_bands = 3;
    set.coeffs = Eigen::MatrixXd::Zero(9, 3);
    for (int k = 0; k < 9; ++k) set.coeffs.row(k) << 0.3 / (k + 1), 0.2, 0.1 * k;
    nlohmann::json doc = sh::to_json(set);
    seed("lighting", "sh_only.json", doc.dump(1));
    envmap::DirectionalLight sun;
    sun.direction = Eigen::Vector3d(0.3, 0.4, std::sqrt(1 - 0.25));
    sun.flux = Eigen::Vector3d(2, 1.8, 1.5);
    sun.angular_radius = 0.0093;
    envmap::DirectionalLight sky = sun;
    sky.direction = Eigen::Vector3d(0, 0, 1);
    sky.angular_radius = 0.3;
    sky.shading = envmap::LightShading::kSmoothCap;
    doc["lights"] = {envmap::to_json(sun), envmap::to_json(sky)};
    seed("lighting", "sh_lights.json", doc.dump(1));
}

void brdftable_seeds(const std::string& tmp) {
    // One table per grid kind and channel count, small.
    const brdf::GridKind kinds[] = {brdf::GridKind::kReport5x5, brdf::GridKind::kThetaPhi,
                                    brdf::GridKind::kOcta, brdf::GridKind::kDisk};
    for (int i = 0; i < 4; ++i) {
        brdf::Table t;
        t.grid.kind = kinds[i];
        t.grid.rows = t.grid.cols = i == 0 ? 5 : 2 + i;  // report5x5, thetaphi:3x3, octa:4, disk:5
        t.grid.theta_max = 1.2;
        t.sh_bands = 2 + i % 2;
        t.channels = i % 2 ? 3 : 1;
        t.resize();
        for (size_t k = 0; k < t.coeffs.size(); ++k) t.coeffs[k] = 0.01f * static_cast<float>(k);
        brdf::write_binary(tmp + "/t.bin", t);
        seed("brdftable", str("grid", i, ".bin"), fs::read_file(tmp + "/t.bin"));
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: make_seeds SOURCE_DIR OUT_DIR\n";
        return 2;
    }
    g_out = argv[2];
    try {
        const std::string tmp = g_out + "/.tmp";
        stdfs::remove_all(tmp);
        stdfs::create_directories(tmp);
        image_seeds(tmp);
        toml_seeds(argv[1]);
        mesh_seeds();
        corner_seeds(tmp);
        sh_seeds(tmp);
        response_seeds(tmp);
        btf_seeds(tmp);
        btfpca_seeds(tmp);
        lighting_seeds();
        brdftable_seeds(tmp);
        fuzz::make_fabric_bundle(tmp + "/bundle_src", tmp + "/bundles/weave");
        seed("bundle", "manifest.json", fs::read_file(tmp + "/bundles/weave/manifest.json"));
        stdfs::remove_all(tmp);
    } catch (const std::exception& e) {
        std::cerr << "make_seeds: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
