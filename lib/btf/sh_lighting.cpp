#include "btf/sh_lighting.h"

#include <cmath>

#include "core/conventions.h"
#include "core/error.h"
#include "sh/sh.h"

namespace inlight::btf {

Eigen::MatrixXd sh_light_weight_matrix(const std::vector<Direction>& lights, int sh_bands,
                                       const DomeLightingOptions& options, int map_height) {
    if (sh_bands < 1 || sh_bands > 9) {
        throw Error(str("SH light weights: bands must be in 1..9, got ", sh_bands));
    }
    if (map_height < 16 || map_height > 2048) {
        throw Error(str("SH light weights: map height must be in 16..2048, got ", map_height));
    }
    const int count = sh::count(sh_bands), h = map_height, w = 2 * map_height;
    // The basis functions at the pixel centres, once.
    std::vector<double> basis(static_cast<size_t>(w) * h * count);
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < w; ++col) {
            const Eigen::Vector3d d = latlong_direction((col + 0.5) / w, (row + 0.5) / h);
            sh::eval(sh_bands, d, &basis[(static_cast<size_t>(row) * w + col) * count]);
        }
    }
    // Three basis functions per map (its three channels), each through the map path.
    Eigen::MatrixXd a(static_cast<Eigen::Index>(lights.size()), count);
    for (int j0 = 0; j0 < count; j0 += 3) {
        image::Image map(w, h, 3);
        for (int row = 0; row < h; ++row) {
            for (int col = 0; col < w; ++col) {
                for (int c = 0; c < 3 && j0 + c < count; ++c) {
                    map.at(col, row, c) = static_cast<float>(
                        basis[(static_cast<size_t>(row) * w + col) * count + j0 + c]);
                }
            }
        }
        const DomeLighting cells = integrate_dome_cells(map, lights, options);
        for (size_t k = 0; k < lights.size(); ++k) {
            for (int c = 0; c < 3 && j0 + c < count; ++c) a(static_cast<Eigen::Index>(k), j0 + c) = cells.weight[k][c];
        }
    }
    return a;
}

}  // namespace inlight::btf
