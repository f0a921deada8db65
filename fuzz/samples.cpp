#include "samples.h"

#include <cmath>
#include <filesystem>

#include "btf/pca_run.h"
#include "btf/synthetic.h"
#include "bundle/bundle.h"
#include "core/fs.h"

namespace inlight::fuzz {

image::Image gradient_image(int width, int height) {
    image::Image img(width, height, 3);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            img.at(x, y, 0) = static_cast<float>(x + 0.5) / static_cast<float>(width);
            img.at(x, y, 1) = static_cast<float>(y + 0.5) / static_cast<float>(height);
            img.at(x, y, 2) = 0.5f + 0.4f * static_cast<float>(std::sin(x + 2.0 * y));
        }
    }
    return img;
}

void make_fabric_bundle(const std::string& src, const std::string& dest) {
    std::filesystem::create_directories(src);
    image::write_image(src + "/albedo.png", gradient_image(8, 4));
    image::write_image(src + "/thumbnail.png", gradient_image(2, 1));
    fs::write_text_atomic(src + "/material.toml", "specular = \"ggx\"\nalpha = 0.2\n");
    bundle::PackRequest request;
    request.kind = bundle::Kind::kFabric;
    request.id = "weave";
    request.name = "Fuzz seed weave";
    request.properties = {{"tile_size_m", 0.05}, {"sh_bands", 3}};
    request.files = {{src + "/albedo.png", "albedo.png", "albedo", -1},
                     {src + "/thumbnail.png", "thumbnail.png", "thumbnail", -1},
                     {src + "/material.toml", "material/material.toml", "material", -1}};
    bundle::write_bundle(dest, request);
}

void make_compressed_btf(const std::string& dir) {
    btf::AnalyticBtfOptions ao;
    ao.width = 4;
    ao.height = 3;
    ao.rank = 2;
    ao.lights = {{0, 0}, {30, 90}, {60, 200}};
    ao.views = {{0, 0}, {30, 0}, {45, 120}, {60, 240}};
    const btf::AnalyticBtf truth(ao);
    btf::PcaRunOptions po;
    po.output = dir;
    po.pca.view_group_size = 2;
    po.pca.components = 2;
    po.color_samples = 16;
    btf::compress_to_folder(truth, po, 0);
}

}  // namespace inlight::fuzz
