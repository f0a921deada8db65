#include "btf/synthetic.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/check.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/parallel.h"

namespace inlight::btf {

namespace {

constexpr int kMaxRank = 6;
/// Each lobe's colour (linear RGB), chosen so no two are proportional.
constexpr double kLobeColor[kMaxRank][3] = {{0.55, 0.35, 0.20}, {0.60, 0.60, 0.65},
                                            {0.20, 0.30, 0.45}, {0.30, 0.45, 0.25},
                                            {0.45, 0.20, 0.35}, {0.25, 0.25, 0.15}};

/// The largest value of an analytic BTF at scale 1 is below this.
constexpr double kPeak = 0.95;

}  // namespace

AnalyticBtf::AnalyticBtf(const AnalyticBtfOptions& options) : m_options(options) {
    INLIGHT_CHECK(options.width >= 1 && options.height >= 1)
        << options.width << "x" << options.height;
    INLIGHT_CHECK(options.rank >= 1 && options.rank <= kMaxRank) << "rank " << options.rank;
    INLIGHT_CHECK(options.scale > 0 && std::isfinite(options.scale)) << "scale " << options.scale;
    // Every lobe peaks at 1 and every map at 0.9: dividing by 0.9 times the sum of the lobes'
    // largest colour components keeps every value at scale = 1 below kPeak.
    double sum = 0;
    for (int r = 0; r < options.rank; ++r) {
        sum += std::max({kLobeColor[r][0], kLobeColor[r][1], kLobeColor[r][2]});
    }
    m_norm = kPeak / (0.9 * sum);
    m_shape.lights = options.lights;
    m_shape.views = options.views;
    m_shape.width = options.width;
    m_shape.height = options.height;
    // Spatial maps: tileable sums of two plane waves with integer frequencies and random phases.
    std::mt19937_64 rng(options.seed);
    std::uniform_real_distribution<double> phase(0, 2 * kPi);
    std::uniform_int_distribution<int> freq(1, 4);
    const int w = options.width, h = options.height;
    m_maps.resize(static_cast<size_t>(options.rank) * w * h);
    for (int r = 0; r < options.rank; ++r) {
        const int f1 = freq(rng), g1 = freq(rng) - 1 + r, f2 = freq(rng) + r, g2 = freq(rng);
        const double p1 = phase(rng), p2 = phase(rng);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const double u = (x + 0.5) / w, v = (y + 0.5) / h;
                const double a = 0.5 + 0.25 * std::sin(2 * kPi * (f1 * u + g1 * v) + p1) +
                                 0.15 * std::cos(2 * kPi * (f2 * u - g2 * v) + p2);
                m_maps[(static_cast<size_t>(r) * h + y) * w + x] = static_cast<float>(a);
            }
        }
    }
}

double AnalyticBtf::spatial(int r, int x, int y) const {
    return m_maps[(static_cast<size_t>(r) * m_shape.height + y) * m_shape.width + x];
}

double AnalyticBtf::lobe(int r, const Eigen::Vector3d& l, const Eigen::Vector3d& v, int c) const {
    const double cos_l = std::max(0.0, l.z());
    double f = 0;
    switch (r) {
        case 0:  // Lambert
            f = 1.0;
            break;
        case 1: {  // Blinn-Phong highlight
            const Eigen::Vector3d h = (l + v).normalized();
            f = std::pow(std::max(0.0, h.z()), 24.0);
            break;
        }
        case 2:  // grazing sheen
            f = std::pow(1.0 - std::max(0.0, v.z()), 2.0);
            break;
        case 3:  // retro-reflection
            f = std::pow(0.5 * (1.0 + l.dot(v)), 6.0);
            break;
        case 4: {  // a lobe tilted toward +x (anisotropic yarn-like)
            const Eigen::Vector3d h = (l + v).normalized();
            f = std::pow(std::max(0.0, h.dot(Eigen::Vector3d(0.5, 0, 0.866))), 8.0);
            break;
        }
        default: {  // a lobe tilted toward +y
            const Eigen::Vector3d h = (l + v).normalized();
            f = std::pow(std::max(0.0, h.dot(Eigen::Vector3d(0, 0.5, 0.866))), 8.0);
            break;
        }
    }
    return m_options.scale * m_norm * kLobeColor[r][c] * f * cos_l;
}

double AnalyticBtf::value(int x, int y, const Eigen::Vector3d& l, const Eigen::Vector3d& v,
                          int c) const {
    double s = 0;
    for (int r = 0; r < m_options.rank; ++r) s += spatial(r, x, y) * lobe(r, l, v, c);
    return s;
}

image::Image AnalyticBtf::render(const Eigen::Vector3d& l, const Eigen::Vector3d& v) const {
    image::Image img(m_shape.width, m_shape.height, 3);
    double b[kMaxRank][3];
    for (int r = 0; r < m_options.rank; ++r) {
        for (int c = 0; c < 3; ++c) b[r][c] = lobe(r, l, v, c);
    }
    // Row by row, the terms added in order r = 0, 1, ... to each value as value() adds them
    // (the same bits), each map row walked contiguously.
    const int w = m_shape.width;
    std::vector<double> acc(static_cast<size_t>(3 * w));
    for (int y = 0; y < m_shape.height; ++y) {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (int r = 0; r < m_options.rank; ++r) {
            const float* map = &m_maps[(static_cast<size_t>(r) * m_shape.height + y) * w];
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) acc[static_cast<size_t>(3 * x + c)] += double(map[x]) * b[r][c];
        }
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(acc[static_cast<size_t>(3 * x + c)]);
    }
    return img;
}

image::Image AnalyticBtf::read_image(int light, int view) const {
    INLIGHT_CHECK(light >= 0 && light < m_shape.n_lights() && view >= 0 && view < m_shape.n_views())
        << "light " << light << " view " << view;
    return render(m_shape.lights[static_cast<size_t>(light)].vector(),
                  m_shape.views[static_cast<size_t>(view)].vector());
}

std::string ubo2003_path(const std::string& dir, const Direction& light, const Direction& view,
                         const UboWriteOptions& options) {
    std::string path = dir + "/";
    if (options.per_view_folders) path += ubo2003_view_folder(view) + "/";
    return path + options.prefix + ubo2003_stem(light, view) + "." + options.extension;
}

void write_ubo2003(const BtfSource& source, const std::string& dir,
                   const UboWriteOptions& options) {
    const BtfShape& s = source.shape();
    image::WriteOptions wo;
    wo.bits = options.extension == "exr" ? 32 : options.bits;
    wo.exr_half = options.extension == "exr" && options.bits == 16;
    const int64_t n = int64_t(s.n_lights()) * s.n_views();
    parallel::for_chunks(n, 4, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int v = static_cast<int>(i / s.n_lights()),
                      l = static_cast<int>(i % s.n_lights());
            const Direction& ld = s.lights[static_cast<size_t>(l)];
            const Direction& vd = s.views[static_cast<size_t>(v)];
            image::write_image(ubo2003_path(dir, ld, vd, options), source.read_image(l, v), wo);
        }
    });
}

}  // namespace inlight::btf
