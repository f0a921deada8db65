#include "render/material.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "render/mip.h"

namespace inlight::render {

void load_textures(SurfaceMaterial& m) {
    if (!m.albedo_texture_path.empty()) {
        m.albedo_texture = std::make_shared<image::Image>(image::read_image(m.albedo_texture_path));
    }
    image::ReadOptions data;
    data.decode_srgb = false;
    if (!m.normal_texture_path.empty()) {
        auto img = std::make_shared<image::Image>(image::read_image(m.normal_texture_path, data));
        if (img->channels < 3) {
            throw Error(
                str(m.normal_texture_path, ": a normal map needs 3 channels, got ", img->channels));
        }
        m.normal_texture = std::move(img);
    }
    if (!m.roughness_texture_path.empty()) {
        m.roughness_texture =
            std::make_shared<image::Image>(image::read_image(m.roughness_texture_path, data));
    }
}

Eigen::Vector3d sample_texture_rect(const image::Image& img, int x0_px, int y0_px, int width,
                                    int height, const Eigen::Vector2d& uv) {
    const double x = uv[0] * width - 0.5;
    const double y = uv[1] * height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    auto wrap = [](long long i, int n) {
        const long long r = i % n;
        return static_cast<int>(r < 0 ? r + n : r);
    };
    const int x0 = x0_px + wrap(static_cast<long long>(fx), width);
    const int x1 = x0_px + wrap(static_cast<long long>(fx) + 1, width);
    const int y0 = y0_px + wrap(static_cast<long long>(fy), height);
    const int y1 = y0_px + wrap(static_cast<long long>(fy) + 1, height);
    auto texel = [&img](int px, int py) {
        Eigen::Vector3d v;
        for (int c = 0; c < 3; ++c) v[c] = img.at(px, py, std::min(c, img.channels - 1));
        return v;
    };
    return (1 - ay) * ((1 - ax) * texel(x0, y0) + ax * texel(x1, y0)) +
           ay * ((1 - ax) * texel(x0, y1) + ax * texel(x1, y1));
}

Eigen::Vector3d sample_texture(const image::Image& img, const Eigen::Vector2d& uv) {
    return sample_texture_rect(img, 0, 0, img.width, img.height, uv);
}

ShadingPoint shade(const SurfaceMaterial& m, const SurfaceHit& hit, const Eigen::Vector3d& wo,
                   const FilteredLookup* filtered) {
    ShadingPoint sp;
    sp.brdf = m.brdf;
    if (hit.has_albedo) sp.brdf.albedo = hit.albedo;  // a yarn's own colour
    const Eigen::Vector2d uv = hit.uv.cwiseProduct(m.uv_scale);
    // Trilinear from the mip atlas when one is given, else bilinear on the texture.
    auto lookup = [&](const image::Image& img, const MipAtlas* mip) {
        if (!mip) return sample_texture(img, uv);
        const double lod = mip_lod(filtered->duv_dx.cwiseProduct(m.uv_scale),
                                   filtered->duv_dy.cwiseProduct(m.uv_scale), {img.width, img.height});
        return sample_trilinear(*mip, uv, filtered->box_matched_lod ? box_matched_lod(lod) : lod);
    };
    if (m.albedo_texture) {
        sp.brdf.albedo = sp.brdf.albedo.cwiseProduct(
            lookup(*m.albedo_texture, filtered ? filtered->albedo : nullptr));
    }
    if (m.roughness_texture) {
        const double r = std::clamp(sample_texture(*m.roughness_texture, uv)[0], 0.0, 1.0);
        sp.brdf.alpha *= r;
        sp.brdf.report_r *= r;
    }
    Eigen::Vector3d n = hit.ns;
    Eigen::Vector3d t = hit.dpdu;
    if (m.normal_texture) {
        const Eigen::Vector3d c =
            lookup(*m.normal_texture, filtered ? filtered->normal : nullptr) * 2.0 -
            Eigen::Vector3d::Ones();
        const Eigen::Vector3d b = n.cross(t);
        const Eigen::Vector3d mapped = t * c.x() + b * c.y() + n * c.z();
        if (mapped.squaredNorm() > 1e-12) {
            sp.normal_length = std::min(1.0, c.norm());
            n = mapped.normalized();
        }
    }
    sp.ng = hit.ng;
    if (sp.ng.dot(wo) < 0) {
        sp.ng = -sp.ng;
        n = -n;
    }
    if (n.dot(wo) <= 0) {
        n = sp.ng;
        sp.normal_length = 1;  // the fallback normal is not a filtered one
    }
    Eigen::Vector3d tangent = t - n * n.dot(t);
    if (tangent.squaredNorm() < 1e-20) tangent = brdf::world_from_local(n).col(0);
    tangent.normalize();
    sp.world_from_local.col(0) = tangent;
    sp.world_from_local.col(1) = n.cross(tangent);
    sp.world_from_local.col(2) = n;
    return sp;
}

}  // namespace inlight::render
