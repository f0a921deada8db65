// Tests of scene files (every error naming file, line, table and key) and mesh readers (OBJ, PLY
// ascii and binary). The TOML reader itself is tested in lib/core/toml_test.cpp.
#include "render/scene.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "core/error.h"
#include "render/mesh.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

const char* const kScene = R"(# a scene
[environment]
radiance = [0.5, 1, 2]
rotation = "z=90"

[camera]
projection = "perspective"
position = [0, 0, 3]
fov_deg = 30
width_px = 64
height_px = 32

[material.denim]
specular = "ggx"
albedo = [0.1, 0.2, 0.5]
alpha = 0.4
uv_scale = 4

[[object]]
shape = "patch"
material = "denim"
size = [2, 1]

[[object]]
shape = "sphere"
material = "denim"
center = [0, 0, 0.5]
radius = 0.25
)";

TEST(SceneFile, ParsesAllTables) {
    const SceneDesc d = parse_scene(kScene, "s.toml", "/base");
    EXPECT_TRUE(d.environment.path.empty());
    EXPECT_EQ(d.environment.radiance, Eigen::Vector3d(0.5, 1, 2));
    EXPECT_EQ(d.environment.rotation, "z=90");
    EXPECT_EQ(d.camera.projection, Projection::kPerspective);
    EXPECT_EQ(d.camera.width_px, 64);
    EXPECT_EQ(d.camera.position, Eigen::Vector3d(0, 0, 3));
    ASSERT_EQ(d.materials.size(), 1u);
    EXPECT_EQ(d.materials[0].brdf.specular, brdf::Model::kGgx);
    EXPECT_DOUBLE_EQ(d.materials[0].brdf.alpha, 0.4);
    EXPECT_EQ(d.materials[0].uv_scale, Eigen::Vector2d(4, 4));
    ASSERT_EQ(d.objects.size(), 2u);
    EXPECT_EQ(d.objects[0].shape.kind, ShapeKind::kPatch);
    EXPECT_EQ(d.objects[0].shape.size, Eigen::Vector2d(2, 1));
    EXPECT_EQ(d.objects[1].shape.kind, ShapeKind::kSphere);
    EXPECT_DOUBLE_EQ(d.objects[1].shape.radius, 0.25);
}

/// Parses `text` and expects an Error whose message contains `expected`.
void expect_error(const std::string& text, const std::string& expected) {
    try {
        parse_scene(text, "bad.toml", "");
        ADD_FAILURE() << "no error; expected: " << expected;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
            << "message: " << e.what() << "\nexpected to contain: " << expected;
    }
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return s.replace(pos, from.size(), to);
}

TEST(SceneFile, ErrorsNameFileLineTableAndKey) {
    expect_error(replace(kScene, "width_px = 64", "widht_px = 64"),
                 "bad.toml:10: [camera] unknown key 'widht_px'");
    expect_error(replace(kScene, "width_px = 64", "width_px = \"64\""),
                 "bad.toml:10: [camera] width_px: expected an integer");
    expect_error(replace(kScene, "width_px = 64", "width_px = 6.5"),
                 "bad.toml:10: [camera] width_px: expected an integer");
    expect_error(replace(kScene, "fov_deg = 30", "fov_deg = 200"),
                 "bad.toml:9: [camera] fov_deg: 200 is outside");
    expect_error(replace(kScene, "alpha = 0.4", "alpha = [0.4]"),
                 "bad.toml:16: [material.denim] alpha: expected a number, got an array");
    expect_error(replace(kScene, "alpha = 0.4", "alpha = 0.4\nreport_r = 0"),
                 "bad.toml:17: [material.denim] report_r: 0 is not > 0");
    expect_error(replace(kScene, "albedo = [0.1, 0.2, 0.5]", "albedo = [0.1, 0.2]"),
                 "bad.toml:15: [material.denim] albedo: expected an array of 3 numbers");
    expect_error(replace(kScene, "specular = \"ggx\"", "specular = \"phong\""),
                 "bad.toml:14: [material.denim] specular:");
    expect_error(replace(kScene, "material = \"denim\"\nsize", "material = \"silk\"\nsize"),
                 "bad.toml:21: [object] material: no [material.silk] in the scene");
    expect_error(replace(kScene, "shape = \"sphere\"", "shape = \"cube\""),
                 "bad.toml:25: [object] shape: unknown shape 'cube' (expected patch, sphere, mesh "
                 "or weave)");
    expect_error(replace(kScene, "rotation = \"z=90\"", "rotation = \"q=90\""),
                 "bad.toml:4: [environment] rotation: rotation 'q=90'");
    expect_error(
        replace(kScene, "rotation = \"z=90\"", "rotation = \"z=90\"\nlayout = \"fisheye\""),
        "bad.toml:5: [environment] layout: unknown environment layout 'fisheye' (expected "
        "latlong, cube or angular)");
    expect_error(replace(kScene, "[environment]", "[environmnet]"),
                 "bad.toml: missing [environment] table");
    expect_error(replace(kScene, "radius = 0.25", "radius = 0.25 0.5"),
                 "bad.toml:28:15: TOML syntax error");
    expect_error(replace(kScene, "[camera]", "[camera]\n[camera]"),
                 "bad.toml:7:1: TOML syntax error: Error while parsing table header: cannot redefine existing table 'camera'");
    expect_error(replace(kScene, "size = [2, 1]", "size = [2, 1"), "bad.toml:");
    expect_error(std::string("x = 1\n") + kScene, "bad.toml:1: key 'x' outside any table");
    expect_error(replace(kScene, "[environment]\nradiance = [0.5, 1, 2]",
                         "[environment]\nradiance = [0.5, 1, 2]\npath = \"a.exr\""),
                 "bad.toml:3: [environment] radiance: give either path or radiance");
}

TEST(SceneFile, WeaveObjectBecomesYarnCurvesAndABacking) {
    // A weave object: its fabric file brings two materials and two shapes (curves + plate);
    // a camera ray straight down at a yarn's top finds the yarn with the thread's colour.
    const std::string dir = testing::temp_dir("scene_weave");
    std::ofstream(dir + "/f.toml") << "pattern = \"plain\"\nspacing_mm = 1\nyarn_radius_mm = 0.3\n"
                                      "warp_albedo = [0.9, 0.1, 0.1]\nweft_albedo = 0.5\n";
    const std::string scene = std::string(R"(
[environment]
radiance = 1
[camera]
position = [0, 0, 5]
[[object]]
shape = "weave"
fabric = "f.toml"
size = [4, 4]
)");
    std::ofstream(dir + "/s.toml") << scene;
    const Scene s(load_scene_desc(dir + "/s.toml"));
    ASSERT_EQ(s.accel().shapes().size(), 2u);
    EXPECT_EQ(s.accel().shapes()[0].kind, ShapeKind::kCurves);
    EXPECT_EQ(s.accel().shapes()[1].kind, ShapeKind::kPatch);
    // Warp 0 at x = 0.5 passes over weft 0 at y = 0.5 (plain: (i + j) even): its top there is
    // at z = crimp + r = 0.3 + 0.3 (crimp defaults to the mean radius).
    Ray r;
    r.origin = {0.5, 0.5, 5};
    r.dir = {0, 0, -1};
    SurfaceHit hit;
    ASSERT_TRUE(s.accel().intersect(r, &hit));
    EXPECT_EQ(hit.shape, 0);
    EXPECT_NEAR(hit.p.z(), 0.6, 1e-5);  // Embree's float t: ~1e-6 relative
    EXPECT_NEAR(hit.ng.z(), 1.0, 1e-5);
    ASSERT_TRUE(hit.has_albedo);
    EXPECT_NEAR(hit.albedo.x(), 0.9, 1e-6);  // stored as float
    EXPECT_EQ(s.material(0).name, "object 0/yarn");

    std::ofstream(dir + "/bad.toml") << scene << "material = \"x\"\n";
    EXPECT_NE(testing::error_of([&] { load_scene_desc(dir + "/bad.toml"); })
                  .find("a weave takes its materials from its fabric file"),
              std::string::npos);
}

TEST(SceneFile, MissingFilesAreNamed) {
    const std::string text = replace(kScene, "radiance = [0.5, 1, 2]", "path = \"nowhere.exr\"");
    const SceneDesc d = parse_scene(text, "s.toml", "/no/such/dir");
    EXPECT_EQ(d.environment.path, "/no/such/dir/nowhere.exr");
    try {
        const Scene s(d);
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/no/such/dir/nowhere.exr"), std::string::npos)
            << e.what();
    }
}

TEST(Mesh, ObjPolygonsNegativeIndicesAndUvFlip) {
    const TriangleMesh m = parse_obj(
        "# quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
        "vt 0 1\nf 1/1 2/2 3/3 4/4\nf -4/-4 -3/-3 -1/-1\n",
        "q.obj");
    EXPECT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.positions.size(), 4u);  // identical v/vt corners are shared
    ASSERT_EQ(m.uvs.size(), 4u);
    EXPECT_EQ(m.uvs[0], Eigen::Vector2d(0, 1));  // vt v is up; stored v is down
    EXPECT_TRUE(m.normals.empty());
    try {
        parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "bad.obj");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.obj:3: face index '3' out of range"),
                  std::string::npos)
            << e.what();
    }
}

TEST(Mesh, ObjNonFiniteNumbersAreErrorsWithTheLine) {
    // NaN/Inf vertices used to make their triangles vanish without a word.
    const struct {
        const char* text;
        const char* expect;
    } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n", "n.obj:3: 'v': 'nan' is not a finite number"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 1e999\nf 1 2 3\n", "n.obj:3: 'v': '1e999' is not"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 inf\nf 1//1 2//1 3//1\n", "n.obj:4: 'vn': 'inf'"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt -inf 0\nf 1/1 2/1 3/1\n", "n.obj:4: 'vt': '-inf'"},
        {"v 0 0\n", "n.obj:1: expected 3 numbers after 'v', got 2"},
    };
    for (const auto& c : cases) {
        const std::string msg = testing::error_of([&] { parse_obj(c.text, "n.obj"); });
        EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
    }
}

TEST(Mesh, PlyAsciiAndBinaryAgree) {
    const std::string dir = testing::temp_dir("render_ply");
    const char* header_fmt =
        "ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty float u\nproperty float v\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    const float verts[4][5] = {{0, 0, 0, 0, 0}, {1, 0, 0, 1, 0}, {1, 1, 0, 1, 1}, {0, 1, 0, 0, 1}};
    char header[512];
    {
        std::snprintf(header, sizeof(header), header_fmt, "ascii");
        std::ofstream f(dir + "/a.ply");
        f << header;
        for (const auto& v : verts)
            f << v[0] << " " << v[1] << " " << v[2] << " " << v[3] << " " << v[4] << "\n";
        f << "4 0 1 2 3\n";
    }
    {
        std::snprintf(header, sizeof(header), header_fmt, "binary_little_endian");
        std::ofstream f(dir + "/b.ply", std::ios::binary);
        f << header;
        f.write(reinterpret_cast<const char*>(verts), sizeof(verts));
        const unsigned char n = 4;
        const int idx[4] = {0, 1, 2, 3};
        f.write(reinterpret_cast<const char*>(&n), 1);
        f.write(reinterpret_cast<const char*>(idx), sizeof(idx));
    }
    const TriangleMesh a = load_mesh(dir + "/a.ply");
    const TriangleMesh b = load_mesh(dir + "/b.ply");
    ASSERT_EQ(a.triangles.size(), 2u);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.uvs, b.uvs);
    EXPECT_EQ(a.uvs[2], Eigen::Vector2d(1, 0));
    EXPECT_THROW(load_mesh(dir + "/missing.ply"), Error);
    EXPECT_THROW(load_mesh(dir + "/a.stl"), Error);
}

}  // namespace
}  // namespace inlight::render
