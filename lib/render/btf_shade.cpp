#include "render/btf_shade.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "render/path_tracer.h"
#include "render/sampling.h"

namespace inlight::render {

ViewBlend select_views(const std::vector<btf::Direction>& views, const btf::Direction& view,
                       int neighbours) {
    INLIGHT_CHECK(!views.empty());
    INLIGHT_CHECK_GE(neighbours, 1);
    std::vector<int> order(views.size());
    std::iota(order.begin(), order.end(), 0);
    std::vector<double> angle(views.size());
    for (size_t i = 0; i < views.size(); ++i) angle[i] = btf::angle_between_deg(views[i], view);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return angle[size_t(a)] < angle[size_t(b)]; });
    ViewBlend out;
    if (angle[size_t(order[0])] < 1e-9 || neighbours == 1) {
        out.views = {order[0]};
        out.weights = {1.0};
        return out;
    }
    const int n = std::min<int>(neighbours, static_cast<int>(views.size()));
    double total = 0;
    for (int i = 0; i < n; ++i) {
        out.views.push_back(order[size_t(i)]);
        out.weights.push_back(1.0 / angle[size_t(order[size_t(i)])]);
        total += out.weights.back();
    }
    for (double& w : out.weights) w /= total;
    return out;
}

ViewBlend interpolate_views(const btf::DirectionInterpolator& views, const btf::Direction& view) {
    const btf::DirectionWeights w = views.weights(view);
    ViewBlend out;
    for (int i = 0; i < w.count; ++i) {
        out.views.push_back(w.index[size_t(i)]);
        out.weights.push_back(w.weight[size_t(i)]);
    }
    return out;
}

image::Image shade_btf(const btf::BtfSource& btf, const btf::DomeLighting& lighting,
                       const ViewBlend& blend, double irradiance_w_m2) {
    const btf::BtfShape& s = btf.shape();
    INLIGHT_CHECK_EQ(lighting.weight.size(), s.lights.size());
    INLIGHT_CHECK(irradiance_w_m2 > 0);
    // Images in a fixed order (view, then light), so the sum does not depend on threads.
    return btf.combine(btf::shading_terms(lighting, blend.views, blend.weights, irradiance_w_m2));
}

image::Image truth_under_environment(const std::shared_ptr<const weave::Weave>& weave,
                                     const CaptureOptions& options, const EnvironmentSpec& env,
                                     const btf::Direction& view, double* rel_error) {
    const Eigen::Vector3d v = view.vector();
    if (!(v.z() > 1e-9)) {
        throw Error(str("view (", view.theta_deg, ", ", view.phi_deg, ") deg cannot see the sample"));
    }
    const CaptureScene cs(weave, options, 85, &env);
    RenderOptions ro;
    ro.max_depth = options.max_depth;
    ro.rr_depth = options.rr_depth;
    ro.seed = options.seed;
    const int w = options.width_px, h = options.height_px;
    image::Image out(w, h, 3, image::ColorSpace::kLinearSrgb);
    std::vector<double> se2(size_t(h), 0), ys(size_t(h), 0);
    // Independent samples: the standard error below is the per-sample variance / n.
    const Sampler sampler(SamplerKind::kIndependent, options.seed, w, h, options.spp, 1);
    parallel::for_chunks(h, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < w; ++x) {
                Eigen::Vector3d sum = Eigen::Vector3d::Zero();
                double sy = 0, sy2 = 0;
                int64_t rays = 0;
                for (int s = 0; s < options.spp; ++s) {
                    Sampler::Stream rng = sampler.stream(x, static_cast<int>(y), s);
                    const Eigen::Vector2d j = options.jitter ? rng.get2d(PathDims::kPixelDim)
                                                             : Eigen::Vector2d(0.5, 0.5);
                    Eigen::Vector3d l = trace_path(cs.scene(), cs.view_ray(v, x + j[0], y + j[1]),
                                                   rng, ro, &rays);
                    if (!l.allFinite()) l.setZero();
                    sum += l;
                    const double yl = 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2];
                    sy += yl;
                    sy2 += yl * yl;
                }
                const double n = options.spp;
                for (int c = 0; c < 3; ++c) out.at(x, int(y), c) = static_cast<float>(sum[c] / n);
                const double mean = sy / n;
                if (n > 1) se2[size_t(y)] += std::max(0.0, (sy2 - n * mean * mean) / (n - 1)) / n;
                ys[size_t(y)] += mean;
            }
        }
    });
    const double s2 = std::accumulate(se2.begin(), se2.end(), 0.0);
    const double y = std::accumulate(ys.begin(), ys.end(), 0.0);
    const double npix = double(w) * h;
    if (rel_error) {
        *rel_error = options.spp > 1 && y > 0 ? std::sqrt(s2 / npix) / (y / npix)
                                              : std::numeric_limits<double>::quiet_NaN();
    }
    return out;
}

}  // namespace inlight::render
