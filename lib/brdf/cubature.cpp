#include "brdf/cubature.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "core/check.h"
#include "core/conventions.h"

namespace inlight::brdf {
namespace {

// Genz-Malik 1980 in n = 2 dimensions, on [-1, 1]^2 with weights that sum to 1 (times the box
// area): lambda_2 = sqrt(9/70), lambda_3 = lambda_4 = sqrt(9/10), lambda_5 = sqrt(9/19).
const double kL2 = std::sqrt(9.0 / 70.0), kL3 = std::sqrt(9.0 / 10.0), kL4 = kL3,
             kL5 = std::sqrt(9.0 / 19.0);
constexpr double kN = 2;
// Degree 7: centre, 2n points at +-lambda_2 e_i, 2n at +-lambda_3 e_i, 2n(n-1) at
// +-lambda_4 (e_i +- e_j), 2^n at (+-lambda_5, +-lambda_5).
constexpr double kW7[5] = {(12824.0 - 9120.0 * kN + 400.0 * kN * kN) / 19683.0, 980.0 / 6561.0,
                           (1820.0 - 400.0 * kN) / 19683.0, 200.0 / 19683.0,
                           6859.0 / 19683.0 / 4.0};
// Degree 5 on the same points (no lambda_5 points).
constexpr double kW5[4] = {(729.0 - 950.0 * kN + 50.0 * kN * kN) / 729.0, 245.0 / 486.0,
                           (265.0 - 100.0 * kN) / 1458.0, 25.0 / 729.0};
// Ratio lambda_2^2 / lambda_3^2 of the fourth difference that picks the split axis.
constexpr double kFourthRatio = 1.0 / 7.0;

struct Box {
    Eigen::Vector2d centre, half;
    Eigen::VectorXd integral;
    double error = 0;
    int split_axis = 0;
};

class Rule {
  public:
    Rule(const CubatureIntegrand& f, int dim) : m_f(f), m_dim(dim), m_v(17, dim) {}

    // Fills box.integral, box.error and box.split_axis from its centre and half widths.
    void apply(Box& box) {
        int p = 0;
        auto at = [&](double a, double b) {
            const Eigen::Vector2d x(box.centre.x() + box.half.x() * a,
                                    box.centre.y() + box.half.y() * b);
            m_f(x, m_row.data());
            m_v.row(p++) = Eigen::Map<const Eigen::RowVectorXd>(m_row.data(), m_dim);
        };
        m_row.resize(m_dim);
        at(0, 0);                                                    // 0
        at(kL2, 0), at(-kL2, 0), at(0, kL2), at(0, -kL2);            // 1-4
        at(kL3, 0), at(-kL3, 0), at(0, kL3), at(0, -kL3);            // 5-8
        at(kL4, kL4), at(kL4, -kL4), at(-kL4, kL4), at(-kL4, -kL4);  // 9-12
        at(kL5, kL5), at(kL5, -kL5), at(-kL5, kL5), at(-kL5, -kL5);  // 13-16
        const Eigen::RowVectorXd c = m_v.row(0);
        const Eigen::RowVectorXd s2 = m_v.middleRows(1, 4).colwise().sum();
        const Eigen::RowVectorXd s3 = m_v.middleRows(5, 4).colwise().sum();
        const Eigen::RowVectorXd s4 = m_v.middleRows(9, 4).colwise().sum();
        const Eigen::RowVectorXd s5 = m_v.middleRows(13, 4).colwise().sum();
        const double area = 4.0 * box.half.x() * box.half.y();
        const Eigen::RowVectorXd i7 =
            area * (kW7[0] * c + kW7[1] * s2 + kW7[2] * s3 + kW7[3] * s4 + kW7[4] * s5);
        const Eigen::RowVectorXd i5 = area * (kW5[0] * c + kW5[1] * s2 + kW5[2] * s3 + kW5[3] * s4);
        box.integral = i7.transpose();
        box.error = (i7 - i5).cwiseAbs().maxCoeff();
        // Fourth divided difference along each axis, summed over components.
        double diff[2];
        for (int axis = 0; axis < 2; ++axis) {
            const int a2 = 1 + 2 * axis, a3 = 5 + 2 * axis;
            diff[axis] = (m_v.row(a2) + m_v.row(a2 + 1) - 2.0 * c -
                          kFourthRatio * (m_v.row(a3) + m_v.row(a3 + 1) - 2.0 * c))
                             .cwiseAbs()
                             .sum();
        }
        // Ties (smooth or flat integrands) split the wider side.
        const double tie = 1e-12 * (diff[0] + diff[1]);
        if (std::abs(diff[0] - diff[1]) <= tie) {
            box.split_axis = box.half.x() >= box.half.y() ? 0 : 1;
        } else {
            box.split_axis = diff[0] > diff[1] ? 0 : 1;
        }
        m_evals += 17;
    }
    int64_t evals() const { return m_evals; }

  private:
    const CubatureIntegrand& m_f;
    int m_dim;
    Eigen::MatrixXd m_v;
    std::vector<double> m_row;
    int64_t m_evals = 0;
};

}  // namespace

CubatureResult cubature_2d(const CubatureIntegrand& f, int dim, const std::vector<double>& xb,
                           const std::vector<double>& yb, const CubatureOptions& o) {
    INLIGHT_CHECK_GE(dim, 1);
    INLIGHT_CHECK(xb.size() >= 2 && yb.size() >= 2) << "need at least two breaks per axis";
    Rule rule(f, dim);
    std::vector<Box> boxes;
    for (size_t i = 0; i + 1 < xb.size(); ++i) {
        for (size_t j = 0; j + 1 < yb.size(); ++j) {
            if (!(xb[i + 1] > xb[i]) || !(yb[j + 1] > yb[j])) continue;
            Box b;
            b.centre = Eigen::Vector2d(0.5 * (xb[i] + xb[i + 1]), 0.5 * (yb[j] + yb[j + 1]));
            b.half = Eigen::Vector2d(0.5 * (xb[i + 1] - xb[i]), 0.5 * (yb[j + 1] - yb[j]));
            rule.apply(b);
            boxes.push_back(std::move(b));
        }
    }
    // Max-heap of box indices by error; ties by index keep the order deterministic.
    auto less = [&](int a, int b) {
        return boxes[a].error < boxes[b].error || (boxes[a].error == boxes[b].error && a > b);
    };
    std::priority_queue<int, std::vector<int>, decltype(less)> heap(less);
    for (int i = 0; i < static_cast<int>(boxes.size()); ++i) heap.push(i);
    const int scale_count = o.scale_count > 0 ? std::min(o.scale_count, dim) : dim;
    auto totals = [&](CubatureResult& r) {
        r.integral = Eigen::VectorXd::Zero(dim);
        r.error = 0;
        for (const Box& b : boxes) {
            if (b.half.x() < 0) continue;  // split: replaced by its halves
            r.integral += b.integral;
            r.error += b.error;
        }
    };
    CubatureResult r;
    totals(r);
    // Running sums are refreshed from the leaves every 64 splits, so rounding cannot drift.
    int since_refresh = 0;
    while (!heap.empty()) {
        const double scale = r.integral.head(scale_count).cwiseAbs().maxCoeff();
        if (r.error <= std::max(o.abs_tol, o.rel_tol * scale)) {
            r.converged = true;
            break;
        }
        if (rule.evals() >= o.max_evals) break;
        const int top = heap.top();
        heap.pop();
        Box parent = std::move(boxes[top]);
        boxes[top].half.x() = -1;  // mark as split (its integral was moved out)
        r.integral -= parent.integral;
        r.error -= parent.error;
        for (int side : {-1, 1}) {
            Box child;
            child.half = parent.half;
            child.half[parent.split_axis] *= 0.5;
            child.centre = parent.centre;
            child.centre[parent.split_axis] += side * child.half[parent.split_axis];
            rule.apply(child);
            r.integral += child.integral;
            r.error += child.error;
            boxes.push_back(std::move(child));
            heap.push(static_cast<int>(boxes.size()) - 1);
        }
        if (++since_refresh == 64) {
            const bool converged = r.converged;
            totals(r);
            r.converged = converged;
            since_refresh = 0;
        }
    }
    const bool converged = r.converged;
    totals(r);
    r.converged = converged;
    r.evals = rule.evals();
    return r;
}

CubatureResult hemisphere_cubature(const HemisphereIntegrand& f, int dim,
                                   const std::vector<Eigen::Vector3d>& features,
                                   const CubatureOptions& o) {
    const double phi0 = features.empty() ? 0.0 : std::atan2(features[0].y(), features[0].x());
    std::vector<double> tb, pb;
    for (int i = 0; i <= 4; ++i) tb.push_back(0.5 * kPi * i / 4);
    for (int j = 0; j <= 8; ++j) pb.push_back(phi0 + 2.0 * kPi * j / 8);
    for (const Eigen::Vector3d& d : features) {
        const double theta = std::acos(std::clamp(d.z(), -1.0, 1.0));
        if (theta > 0 && theta < 0.5 * kPi) tb.push_back(theta);
        if (d.x() != 0 || d.y() != 0) {
            double phi = std::atan2(d.y(), d.x());
            while (phi < phi0) phi += 2.0 * kPi;
            while (phi >= phi0 + 2.0 * kPi) phi -= 2.0 * kPi;
            pb.push_back(phi);
        }
    }
    // Sorted, with breaks closer than 1e-9 rad merged.
    auto tidy = [](std::vector<double>& v) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end(),
                            [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                v.end());
    };
    tidy(tb);
    tidy(pb);
    tb.front() = 0;
    tb.back() = 0.5 * kPi;
    pb.front() = phi0;
    pb.back() = phi0 + 2.0 * kPi;
    std::vector<double> row(dim);
    const CubatureIntegrand g = [&](const Eigen::Vector2d& x, double* out) {
        const double st = std::sin(x.x()), ct = std::cos(x.x());
        f(Eigen::Vector3d(st * std::cos(x.y()), st * std::sin(x.y()), ct), out);
        for (int k = 0; k < dim; ++k) out[k] *= st;
    };
    return cubature_2d(g, dim, tb, pb, o);
}

CubatureResult hemisphere_cubature_about_horizon(const HemisphereIntegrand& f, int dim,
                                                 const Eigen::Vector3d& axis,
                                                 const CubatureOptions& o) {
    INLIGHT_CHECK(std::abs(axis.z()) < 1e-7 && std::abs(axis.norm() - 1.0) < 1e-12)
        << "axis " << axis.transpose() << " is not a horizontal unit vector";
    const Eigen::Vector3d a(axis.x(), axis.y(), 0.0), z = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d b = a.cross(z);
    std::vector<double> tb, pb;
    for (int i = 0; i <= 8; ++i) tb.push_back(kPi * i / 8);
    for (int j = 0; j <= 4; ++j) pb.push_back(-0.5 * kPi + kPi * j / 4);
    const CubatureIntegrand g = [&](const Eigen::Vector2d& x, double* out) {
        const double st = std::sin(x.x()), ct = std::cos(x.x());
        Eigen::Vector3d w = ct * a + st * (std::cos(x.y()) * z + std::sin(x.y()) * b);
        w.z() = std::max(0.0, w.z());
        f(w, out);
        for (int k = 0; k < dim; ++k) out[k] *= st;
    };
    return cubature_2d(g, dim, tb, pb, o);
}

}  // namespace inlight::brdf
