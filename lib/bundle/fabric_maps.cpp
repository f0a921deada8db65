#include "bundle/fabric_maps.h"

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/fs.h"
#include "image/image.h"
#include "image/normal_map.h"

namespace inlight::bundle {

namespace {

image::Image fit_size(const image::Image& img, int max_px) {
    const int longer = std::max(img.width, img.height);
    if (longer <= max_px) return img;
    const double s = static_cast<double>(max_px) / longer;
    return image::resize_box(img, std::max(1, static_cast<int>(std::lround(img.width * s))),
                             std::max(1, static_cast<int>(std::lround(img.height * s))));
}

image::Image rgb(const image::Image& img) {
    if (img.channels == 3) return img;
    image::Image out(img.width, img.height, 3, img.color_space);
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                out.at(x, y, c) = img.at(x, y, img.channels >= 3 ? c : 0);
            }
        }
    }
    return out;
}

}  // namespace

void write_fabric_maps(const FabricMapsOptions& o, const std::string& out_dir, Report& report) {
    if (!std::isfinite(o.relief_texels) || o.relief_texels < 0) {
        throw UsageError(str("--relief-texels ", o.relief_texels, ": must be finite and >= 0"));
    }
    if (!std::isfinite(o.tile_size_m) || o.tile_size_m <= 0) {
        throw UsageError(str("--tile-size-m ", o.tile_size_m, ": must be finite and > 0"));
    }
    if (o.blur_px < 0 || o.max_size_px < 1 || o.thumbnail_px < 1) {
        throw UsageError("--blur-px must be >= 0, --max-size-px and --thumbnail-px >= 1");
    }
    // The outputs are named before any work: -o naming a file (or an input) was found only
    // when the first image could not be written.
    const std::filesystem::path dir(out_dir);
    const std::string albedo_path = (dir / "albedo.png").string();
    const std::string normal_path = (dir / "normal.png").string();
    const std::string thumb_path = (dir / "thumbnail.png").string();
    for (const std::string& p : {albedo_path, normal_path, thumb_path}) fs::declare_output(p, "-o");
    report.add_input(o.albedo_texture);
    image::Image albedo = rgb(image::read_image(o.albedo_texture));
    for (float v : albedo.pixels) {
        if (!std::isfinite(v)) throw Error(str(o.albedo_texture, ": holds a NaN or Inf pixel"));
    }
    const int source_w = albedo.width, source_h = albedo.height;
    albedo = fit_size(albedo, o.max_size_px);

    image::Image normals;
    if (!o.normal_texture.empty()) {
        report.add_input(o.normal_texture);
        image::ReadOptions ro;
        ro.decode_srgb = false;
        image::Image n = rgb(image::read_image(o.normal_texture, ro));
        n.color_space = image::ColorSpace::kData;
        normals = image::resize_box(n, albedo.width, albedo.height);
    } else {
        normals = image::encode_normal_map(image::normal_map_from_height(
            image::height_from_albedo(albedo, o.relief_texels, o.blur_px)));
    }
    const int longer = std::max(albedo.width, albedo.height);
    const double ts = static_cast<double>(o.thumbnail_px) / longer;
    const image::Image thumb = image::resize_box(
        albedo, std::max(1, static_cast<int>(std::lround(albedo.width * ts))),
        std::max(1, static_cast<int>(std::lround(albedo.height * ts))));

    for (const std::string& p : {albedo_path, normal_path, thumb_path}) {
        for (const std::string& in : {o.albedo_texture, o.normal_texture}) {
            std::error_code ec;
            if (!in.empty() && std::filesystem::equivalent(p, in, ec)) {
                throw UsageError(str(p, ": would overwrite the input ", in));
            }
        }
    }
    std::vector<std::string> written;
    try {
        image::WriteOptions srgb;  // 8-bit, sRGB-encoded
        image::write_image(albedo_path, albedo, srgb);
        written.push_back(albedo_path);
        image::WriteOptions data;
        data.encode_srgb = false;
        image::write_image(normal_path, normals, data);
        written.push_back(normal_path);
        image::write_image(thumb_path, thumb, srgb);
        written.push_back(thumb_path);
    } catch (...) {
        for (const auto& p : written) std::filesystem::remove(p);
        throw;
    }
    report.add_output(albedo_path, "albedo", "srgb");
    report.add_output(normal_path, "normal_map", "data");
    report.add_output(thumb_path, "thumbnail", "srgb");
    auto& m = report.metrics();
    m["source_width_px"] = source_w;
    m["source_height_px"] = source_h;
    m["width_px"] = albedo.width;
    m["height_px"] = albedo.height;
    m["thumbnail_width_px"] = thumb.width;
    m["thumbnail_height_px"] = thumb.height;
    m["name"] = o.name;
    m["tile_size_m"] = o.tile_size_m;
    m["normal_source"] = o.normal_texture.empty() ? "derived" : "given";
    if (o.normal_texture.empty()) {
        m["relief_texels"] = o.relief_texels;
        m["blur_px"] = o.blur_px;
    }
}

}  // namespace inlight::bundle
