// render/mesh.h: triangle meshes from Wavefront OBJ and PLY (ASCII or binary little-endian),
// for draped cloth and test quads.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace inlight::render {

/// An indexed triangle mesh. Triangles are counter-clockwise seen from the side their geometric
/// normal (p1 - p0) x (p2 - p0) points to. normals and uvs are per vertex, either empty or of
/// the same size as positions.
struct TriangleMesh {
    std::vector<Eigen::Vector3d> positions;
    std::vector<Eigen::Vector3d> normals;  ///< optional smooth shading normals (unit)
    std::vector<Eigen::Vector2d> uvs;      ///< optional texture coordinates, v down (row 0 = v 0)
    std::vector<Eigen::Vector3i> triangles;
};

/// Reads .obj (v, vt, vn, f with any polygon size, negative indices; a corner's v/vt/vn triple
/// becomes one vertex) or .ply (vertex x y z [nx ny nz] [u v | s t | texture_u texture_v],
/// face vertex_indices | vertex_index, ascii or binary_little_endian), by extension. OBJ's vt
/// has v up; it is stored flipped (1 - v) so that v grows downward like image rows.
/// Throws Error "<file>:<line>: ..." (OBJ) or "<file>: ..." (PLY) on malformed input, indices
/// out of range, or a mesh without triangles.
TriangleMesh load_mesh(const std::string& path);

/// Parses OBJ text (for tests); `source` names it in errors.
TriangleMesh parse_obj(const std::string& text, const std::string& source);

}  // namespace inlight::render
