#include "samples.h"

#include <cmath>
#include <filesystem>

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

}  // namespace inlight::fuzz
