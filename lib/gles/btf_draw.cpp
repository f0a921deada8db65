#include "gles/btf_draw.h"

#include <algorithm>
#include <vector>

namespace inlight::gles {

Mesh btf_sample_quad() {
    Mesh m;
    const Eigen::Vector3f p[4] = {{-1, 1, 0}, {1, 1, 0}, {-1, -1, 0}, {1, -1, 0}};
    const Eigen::Vector2f t[4] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    for (int i : {0, 2, 1, 1, 2, 3}) {
        m.position.push_back(p[i]);
        m.uv.push_back(t[i]);
        m.normal.emplace_back(0, 0, 1);
        m.tangent.emplace_back(1, 0, 0);
    }
    return m;
}

image::Image draw_btf(const Context& context, const BtfGlesExport& e, const BtfGlesVariant& variant,
                      const btf::Direction& view, const Eigen::MatrixXd& sh, int64_t sent, double* draw_ms,
                      const std::vector<BtfLight>& lights) {
    const BtfFrame frame = btf_frame_weights(e, variant, view, sh, sent, lights);
    const Readback out = draw(context, variant.as_export, btf_bindings(e, frame), btf_sample_quad(), e.width,
                              e.height, TargetFormat::kRgba32f);
    if (draw_ms) *draw_ms = out.draw_ms;
    image::Image img(e.width, e.height, 3);
    for (int y = 0; y < e.height; ++y) {
        for (int x = 0; x < e.width; ++x) {
            for (int c = 0; c < 3; ++c)
                img.pixels[(static_cast<size_t>(y) * e.width + x) * 3 + c] = out.at(x, y, c);
        }
    }
    return img;
}

}  // namespace inlight::gles
