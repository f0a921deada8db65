#include "sh/quadrature.h"

#include <cmath>

#include "core/check.h"
#include "core/conventions.h"

namespace inlight::sh {

void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    INLIGHT_CHECK_GE(n, 1);
    nodes.assign(static_cast<size_t>(n), 0.0);
    weights.assign(static_cast<size_t>(n), 0.0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        // Tricomi's initial guess, then Newton on P_n(x) via the three-term recurrence.
        double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double dp = 1.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) p0 = 1.0, p1 = x;
            dp = n * (x * p1 - p0) / (x * x - 1.0);
            const double dx = p1 / dp;
            x -= dx;
            if (std::abs(dx) < 1e-16) break;
        }
        double p0 = 1.0, p1 = x;
        for (int k = 2; k <= n; ++k) {
            const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
            p0 = p1;
            p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1.0);
        const double w = 2.0 / ((1.0 - x * x) * dp * dp);
        nodes[static_cast<size_t>(i)] = -x;
        nodes[static_cast<size_t>(n - 1 - i)] = x;
        weights[static_cast<size_t>(i)] = w;
        weights[static_cast<size_t>(n - 1 - i)] = w;
    }
    if (n % 2 == 1) nodes[static_cast<size_t>(n / 2)] = 0.0;
}

}  // namespace inlight::sh
