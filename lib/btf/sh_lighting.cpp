#include "btf/sh_lighting.h"

#include <cmath>
#include <vector>

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
    // Every basis function at the pixel centres, one channel each, through the map path in one pass.
    image::Image map(w, h, count);
    std::vector<double> y(static_cast<size_t>(count));
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < w; ++col) {
            sh::eval(sh_bands, latlong_direction((col + 0.5) / w, (row + 0.5) / h), y.data());
            for (int j = 0; j < count; ++j) map.at(col, row, j) = static_cast<float>(y[size_t(j)]);
        }
    }
    return integrate_dome_cells_channels(map, lights, options);
}

}  // namespace inlight::btf
