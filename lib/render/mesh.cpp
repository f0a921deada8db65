#include "render/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <tuple>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/fs.h"
#include "core/number.h"

namespace inlight::render {
namespace {

constexpr double kMaxCoordinate = 1e9;  ///< |x|, |y|, |z| of a vertex, as the scene's sizes

void check_mesh(const TriangleMesh& mesh, const std::string& source) {
    if (mesh.triangles.empty()) throw Error(str(source, ": the mesh has no triangles"));
    const int n = static_cast<int>(mesh.positions.size());
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            if (t[k] < 0 || t[k] >= n) {
                throw Error(
                    str(source, ": vertex index ", t[k], " out of range (", n, " vertices)"));
            }
        }
    }
    // Embree holds vertices as float: a coordinate past the float range (1e39) was infinite
    // there and its triangles vanished without a word. Scene sizes are bounded by 1e9 elsewhere.
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const Eigen::Vector3d& p = mesh.positions[i];
        if (!p.allFinite()) throw Error(str(source, ": vertex ", i + 1, ": non-finite position"));
        if (p.cwiseAbs().maxCoeff() > kMaxCoordinate) {
            throw Error(str(source, ": vertex ", i + 1, ": coordinate ", p.cwiseAbs().maxCoeff(),
                            " is outside [-", kMaxCoordinate, ", ", kMaxCoordinate, "]"));
        }
    }
    // A mesh whose triangles all have zero area renders as nothing at all.
    size_t degenerate = 0;
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d& a = mesh.positions[static_cast<size_t>(t[0])];
        const Eigen::Vector3d e1 = mesh.positions[static_cast<size_t>(t[1])] - a;
        const Eigen::Vector3d e2 = mesh.positions[static_cast<size_t>(t[2])] - a;
        if (!(e1.cross(e2).norm() > 0)) ++degenerate;
    }
    if (degenerate == mesh.triangles.size()) {
        throw Error(str(source, ": all ", degenerate, " triangles have zero area (the mesh would "
                                "render as nothing)"));
    }
}

// ---------------------------------------------------------------------------------------------
// PLY

struct PlyProperty {
    std::string name;
    std::string type;        ///< scalar type, or the item type of a list
    std::string count_type;  ///< non-empty for lists
};
struct PlyElement {
    std::string name;
    int64_t count = 0;
    std::vector<PlyProperty> props;
};

int ply_type_size(const std::string& t, const std::string& source) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" ||
        t == "float32") {
        return 4;
    }
    if (t == "double" || t == "float64") return 8;
    throw Error(str(source, ": unknown PLY property type '", t, "'"));
}

double ply_read_binary(const char* p, const std::string& t) {
    auto get = [p](auto v) {
        std::memcpy(&v, p, sizeof(v));
        return static_cast<double>(v);
    };
    if (t == "char" || t == "int8") return get(int8_t{});
    if (t == "uchar" || t == "uint8") return get(uint8_t{});
    if (t == "short" || t == "int16") return get(int16_t{});
    if (t == "ushort" || t == "uint16") return get(uint16_t{});
    if (t == "int" || t == "int32") return get(int32_t{});
    if (t == "uint" || t == "uint32") return get(uint32_t{});
    if (t == "float" || t == "float32") return get(float{});
    return get(double{});
}

TriangleMesh load_ply(const std::string& path) {
    const std::string data = fs::read_file(path);
    std::istringstream header(data);
    std::string line;
    std::getline(header, line);
    if (line.rfind("ply", 0) != 0) throw Error(str(path, ": not a PLY file (no 'ply' magic)"));
    std::string format;
    std::vector<PlyElement> elements;
    bool end_header = false;
    while (std::getline(header, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "format") {
            std::string version;
            ls >> format >> version;
            if (version != "1.0") {
                throw Error(str(path, ": PLY format version '", version, "' is not supported (1.0)"));
            }
        } else if (word == "element") {
            PlyElement e;
            std::string count;
            ls >> e.name >> count;
            // Each item takes at least one byte, so a count beyond the file's size is a lie (and
            // would loop or allocate for nothing).
            try {
                e.count = parse_integer(count, str(path, ": PLY element '", e.name, "' count"), 0,
                                        static_cast<long long>(data.size()));
            } catch (const Error& bad) {  // a bad file is a data error (exit 1), not a usage error
                throw Error(bad.what());
            }
            elements.push_back(e);
        } else if (word == "property") {
            if (elements.empty()) throw Error(str(path, ": PLY property before any element"));
            PlyProperty p;
            std::string t;
            ls >> t;
            if (t == "list") {
                ls >> p.count_type >> p.type >> p.name;
            } else {
                p.type = t;
                ls >> p.name;
            }
            ply_type_size(p.type, path);  // an unknown type is an error in ascii files too
            if (!p.count_type.empty()) ply_type_size(p.count_type, path);
            elements.back().props.push_back(p);
        } else if (word == "end_header") {
            end_header = true;
            break;
        }
    }
    if (!end_header) throw Error(str(path, ": PLY header without end_header"));
    for (const PlyElement& e : elements) {
        if (e.count > 0 && e.props.empty()) {
            throw Error(str(path, ": PLY element '", e.name, "' has no properties"));
        }
    }
    if (format != "ascii" && format != "binary_little_endian") {
        throw Error(str(path, ": PLY format '", format,
                        "' is not supported (ascii or binary_little_endian)"));
    }
    for (const PlyElement& e : elements) {
        if (e.name != "vertex") continue;
        for (const char* axis : {"x", "y", "z"}) {
            if (std::none_of(e.props.begin(), e.props.end(),
                             [axis](const PlyProperty& p) { return p.name == axis && p.count_type.empty(); })) {
                throw Error(str(path, ": PLY element 'vertex' has no property '", axis, "'"));
            }
        }
    }
    size_t offset = static_cast<size_t>(header.tellg());
    std::istringstream ascii(format == "ascii" ? data.substr(offset) : std::string());

    TriangleMesh mesh;
    for (const PlyElement& e : elements) {
        for (int64_t i = 0; i < e.count; ++i) {
            std::map<std::string, double> scalars;
            std::vector<int> list;
            for (const PlyProperty& p : e.props) {
                auto read_value = [&](const std::string& type) -> double {
                    if (format == "ascii") {
                        std::string word;
                        if (!(ascii >> word))
                            throw Error(str(path, ": truncated PLY data in '", e.name, "'"));
                        return parse_finite_field(
                            word, str(path, ": element '", e.name, "' ", i, ", '", p.name, "'"));
                    }
                    const int size = ply_type_size(type, path);
                    if (offset + static_cast<size_t>(size) > data.size()) {
                        throw Error(str(path, ": truncated PLY data in '", e.name, "'"));
                    }
                    const double v = ply_read_binary(data.data() + offset, type);
                    offset += static_cast<size_t>(size);
                    if (!std::isfinite(v)) {
                        throw Error(str(path, ": element '", e.name, "' ", i, ", '", p.name,
                                        "': ", v, " is not a finite number"));
                    }
                    return v;
                };
                // List lengths and indices must be whole numbers in range before any cast.
                auto read_int = [&](const std::string& type, double lo, double hi) {
                    const double v = read_value(type);
                    if (v != std::floor(v) || v < lo || v > hi) {
                        throw Error(str(path, ": element '", e.name, "' ", i, ", '", p.name,
                                        "': ", v, " is not an integer in [", lo, ", ", hi, "]"));
                    }
                    return static_cast<int>(v);
                };
                if (!p.count_type.empty()) {
                    // A list item takes at least one byte (or character) of the file.
                    const int n = read_int(p.count_type, 0,
                                           static_cast<double>(std::min<size_t>(data.size(), 1 << 30)));
                    std::vector<int> items(static_cast<size_t>(n));
                    for (int& item : items) item = read_int(p.type, -2147483647.0, 2147483647.0);
                    if (p.name == "vertex_indices" || p.name == "vertex_index") list = items;
                } else {
                    scalars[p.name] = read_value(p.type);
                }
            }
            if (e.name == "vertex") {
                mesh.positions.emplace_back(scalars["x"], scalars["y"], scalars["z"]);
                if (scalars.count("nx")) {
                    mesh.normals.push_back(
                        Eigen::Vector3d(scalars["nx"], scalars["ny"], scalars["nz"]).normalized());
                }
                for (const auto& [u, v] : {std::pair<const char*, const char*>{"u", "v"},
                                           {"s", "t"},
                                           {"texture_u", "texture_v"}}) {
                    if (scalars.count(u) && scalars.count(v)) {
                        mesh.uvs.emplace_back(scalars[u], 1.0 - scalars[v]);
                        break;
                    }
                }
            } else if (e.name == "face") {
                for (size_t k = 1; k + 1 < list.size(); ++k) {
                    mesh.triangles.emplace_back(list[0], list[k], list[k + 1]);
                }
            }
        }
    }
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) mesh.normals.clear();
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) mesh.uvs.clear();
    check_mesh(mesh, path);
    return mesh;
}

}  // namespace

TriangleMesh parse_obj(const std::string& text, const std::string& source) {
    std::vector<Eigen::Vector3d> v, vn;
    std::vector<Eigen::Vector2d> vt;
    std::map<std::tuple<int, int, int>, int> vertex_of;
    TriangleMesh mesh;
    bool any_uv = false, any_normal = false;
    std::istringstream in(text);
    std::string line;
    int line_no = 0;
    auto fail = [&](const std::string& what) -> Error {
        return Error(str(source, ":", line_no, ": ", what));
    };
    while (std::getline(in, line)) {
        ++line_no;
        std::istringstream ls(line);
        std::string tag;
        if (!(ls >> tag) || tag[0] == '#') continue;
        if (tag == "v" || tag == "vn" || tag == "vt") {
            // v x y z [w], vn x y z, vt u [v [w]]: every number finite, or the line is an error.
            const int need = tag == "vt" ? 2 : 3;
            std::vector<double> p;
            std::string word;
            while (ls >> word) {
                p.push_back(parse_finite_field(word, str(source, ":", line_no, ": '", tag, "'")));
            }
            if (static_cast<int>(p.size()) < need) {
                throw fail(str("expected ", need, " numbers after '", tag, "', got ", p.size()));
            }
            if (tag == "vt") {
                vt.emplace_back(p[0], p[1]);
            } else {
                (tag == "v" ? v : vn).emplace_back(p[0], p[1], p[2]);
            }
        } else if (tag == "f") {
            std::vector<int> corners;
            std::string item;
            while (ls >> item) {
                int idx[3] = {0, 0, 0};
                std::istringstream is(item);
                std::string part;
                for (int k = 0; k < 3 && std::getline(is, part, '/'); ++k) {
                    if (part.empty()) continue;
                    try {
                        idx[k] = std::stoi(part);
                    } catch (const std::exception&) {
                        throw fail(str("bad face index '", item, "'"));
                    }
                }
                const int sizes[3] = {static_cast<int>(v.size()), static_cast<int>(vt.size()),
                                      static_cast<int>(vn.size())};
                for (int k = 0; k < 3; ++k) {
                    if (idx[k] < 0) idx[k] += sizes[k] + 1;  // relative index
                    if ((k == 0 || idx[k] != 0) && (idx[k] < 1 || idx[k] > sizes[k])) {
                        throw fail(str("face index '", item, "' out of range"));
                    }
                }
                const auto key = std::make_tuple(idx[0], idx[1], idx[2]);
                auto it = vertex_of.find(key);
                if (it == vertex_of.end()) {
                    it = vertex_of.emplace(key, static_cast<int>(mesh.positions.size())).first;
                    mesh.positions.push_back(v[static_cast<size_t>(idx[0] - 1)]);
                    const Eigen::Vector2d t =
                        idx[1] ? vt[static_cast<size_t>(idx[1] - 1)] : Eigen::Vector2d(0, 1);
                    mesh.uvs.emplace_back(t[0], 1.0 - t[1]);
                    mesh.normals.push_back(idx[2] ? vn[static_cast<size_t>(idx[2] - 1)].normalized()
                                                  : Eigen::Vector3d::Zero());
                    any_uv |= idx[1] != 0;
                    any_normal |= idx[2] != 0;
                }
                corners.push_back(it->second);
            }
            if (corners.size() < 3) throw fail("a face needs at least 3 vertices");
            for (size_t k = 1; k + 1 < corners.size(); ++k) {
                mesh.triangles.emplace_back(corners[0], corners[k], corners[k + 1]);
            }
        }
        // Other tags (o, g, s, usemtl, mtllib, l, p) do not change the geometry.
    }
    if (!any_uv) mesh.uvs.clear();
    if (!any_normal) mesh.normals.clear();
    for (const auto& n : mesh.normals) {
        if (n.squaredNorm() == 0) throw Error(str(source, ": some faces have normals, others not"));
    }
    check_mesh(mesh, source);
    return mesh;
}

TriangleMesh load_mesh(const std::string& path) {
    const std::string ext = fs::extension(path);
    if (ext == "obj") return parse_obj(fs::read_file(path), path);
    if (ext == "ply") return load_ply(path);
    throw Error(str(path, ": unknown mesh format '.", ext, "' (expected .obj or .ply)"));
}

}  // namespace inlight::render
