// btf/interp.h: angular interpolation between the measured directions of a BTF, for a light or
// a view direction that was not measured.
//
// Two schemes, each giving at most three measured directions and weights (non-negative, sum 1):
// - kThesis: the BTF thesis' scheme (../shared/seeds/, section 4.4): the set's rings of equal
//   theta bracket the query (theta_L <= theta < theta_U, the thesis' f^l and f^u), the two
//   azimuths bracketing phi on each ring give A, B (lower ring) and C, D (upper ring), and the
//   triangle is ABC when the query is nearer A than D, else BCD (4.4.1). Weights are the
//   normalised volumes |det(P, P_j, P_k)| of the tetrahedra with the origin (4.4.2, after Hatka
//   and Haindl). Below the outermost ring ("beyond the measuring directions") the two ring
//   directions bracketing phi are blended linearly in phi, as the thesis does; above the
//   innermost ring of a set without a pole direction (a case the thesis does not meet) the same.
//   The triangle choice is the thesis' approximation: the query may lie outside ABC / BCD, and
//   the absolute volumes then still give non-negative weights, but not its barycentrics.
// - kDelaunay (the reference): the spherical Delaunay triangulation of the set, i.e. the faces
//   of the convex hull of the unit vectors (Qhull, with the origin added so that a set within a
//   hemisphere closes as a cone) that face away from the origin. Weights are the barycentric
//   coordinates of the query's ray where it meets the plane of its spherical triangle (the
//   same normalised determinants, signed: exact barycentrics, continuous across edges). A query
//   outside the triangulated region (e.g. below the dome's 75-degree ring) is projected to the
//   nearest point of the region's boundary (great-circle arcs) and blended between that edge's
//   two directions; `outside_deg` reports how far it was moved.
// Frame: the BTF sample frame (docs/conventions.md), unit vectors; any direction, also below
// the sample's plane, is accepted (the caller decides what a light from below means).
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "btf/dataset.h"
#include "btf/dome.h"

namespace inlight::btf {

/// The measured directions blended for one query.
struct DirectionWeights {
    int count = 0;  ///< 1..3 entries used (weights below 1e-12, rounding of 0, are dropped)
    std::array<int, 3> index{{0, 0, 0}};  ///< indices into the direction set
    std::array<double, 3> weight{{0, 0, 0}};  ///< >= 0, sum 1
    /// How far the query was moved onto the measured region (0 inside): Delaunay, the angle to
    /// the boundary point used; thesis, the theta distance to the ring used when it lies beyond
    /// the outermost ring (or above the innermost ring of a set without a pole direction).
    double outside_deg = 0;
};

/// kNearest, the baseline without interpolation: the measured direction with the largest
/// cosine to the query, weight 1 (ties to the lowest index).
enum class InterpScheme { kThesis, kDelaunay, kNearest };
std::string to_string(InterpScheme s);  ///< "thesis", "delaunay", "nearest"
/// Inverse of to_string; throws UsageError naming the value otherwise.
InterpScheme interp_scheme_from_string(const std::string& name);

/// Interpolation weights over one direction set. Safe to call from several threads at once.
class DirectionInterpolator {
  public:
    virtual ~DirectionInterpolator() = default;
    /// Precondition: `d` is a unit vector to 1e-6 (checked; Error otherwise).
    virtual DirectionWeights weights(const Eigen::Vector3d& d) const = 0;
    DirectionWeights weights(const Direction& d) const { return weights(d.vector()); }
};

/// The thesis' ring scheme. The set must consist of rings of equal theta (within 1e-6 deg),
/// each holding n azimuths phi0 + 360 j / n (the Bonn dome; a ring at theta = 0 holds one
/// direction); throws Error naming the first ring that is not so.
class ThesisInterpolator : public DirectionInterpolator {
  public:
    explicit ThesisInterpolator(const std::vector<Direction>& set);
    using DirectionInterpolator::weights;
    DirectionWeights weights(const Eigen::Vector3d& d) const override;

  private:
    struct Ring {
        double theta_deg = 0, phi0_deg = 0, step_deg = 360;
        std::vector<int> index;  // ring position -> set index
    };
    /// The two ring directions bracketing phi, as ring positions.
    std::pair<int, int> bracket(const Ring& r, double phi_deg, double* t) const;
    std::vector<Ring> m_rings;  // theta ascending
    std::vector<Eigen::Vector3d> m_vec;
};

/// The spherical Delaunay reference. Throws Error for fewer than three directions, two
/// directions within 1e-6 deg of each other (both indices named), and a set on one great
/// circle (no spherical triangle exists).
class DelaunayInterpolator : public DirectionInterpolator {
  public:
    explicit DelaunayInterpolator(const std::vector<Direction>& set);
    using DirectionInterpolator::weights;
    DirectionWeights weights(const Eigen::Vector3d& d) const override;
    /// The spherical triangles, each oriented counter-clockwise seen from outside.
    const std::vector<std::array<int, 3>>& triangles() const { return m_tri; }
    /// The region's boundary arcs (empty when the set surrounds the origin).
    const std::vector<std::array<int, 2>>& boundary() const { return m_boundary; }

  private:
    std::vector<Eigen::Vector3d> m_vec;
    std::vector<std::array<int, 3>> m_tri;
    std::vector<std::array<int, 2>> m_boundary;
};

/// The nearest measured direction (no interpolation). Throws Error for an empty set.
class NearestInterpolator : public DirectionInterpolator {
  public:
    explicit NearestInterpolator(const std::vector<Direction>& set);
    using DirectionInterpolator::weights;
    DirectionWeights weights(const Eigen::Vector3d& d) const override;

  private:
    std::vector<Eigen::Vector3d> m_vec;
};

/// The interpolator of `scheme` over `set`.
std::unique_ptr<DirectionInterpolator> make_interpolator(InterpScheme scheme,
                                                         const std::vector<Direction>& set);

/// The thesis' nine-sample blend (4.4.3), C = sum_u b_lu sum_v b_vv C_uv, as terms of
/// BtfSource::combine (the product weight on every channel): at most 9 terms, light-major.
std::vector<ImageTerm> interpolation_terms(const DirectionInterpolator& lights,
                                           const DirectionInterpolator& views,
                                           const Eigen::Vector3d& light, const Eigen::Vector3d& view);

/// The weights as a dense vector over a set of `n` directions (tests and comparisons).
Eigen::VectorXd dense_weights(const DirectionWeights& w, int n);

}  // namespace inlight::btf
