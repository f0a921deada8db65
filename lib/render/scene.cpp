#include "render/scene.h"

#include <filesystem>
#include <map>

#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/toml.h"
#include "envmap/environment.h"
#include "render/mesh.h"
#include "render/weave_geometry.h"

namespace inlight::render {
namespace {

/// envmap's layouts but the fisheye frame: the path tracer needs the whole sphere.
constexpr EnumName<envmap::Layout> kSceneLayoutNames[] = {
    {envmap::Layout::kLatLong, "latlong"},
    {envmap::Layout::kCube, "cube"},
    {envmap::Layout::kAngular, "angular"},
};

std::string resolve(const std::string& base_dir, const std::string& path) {
    if (path.empty()) return path;
    const std::filesystem::path p(path);
    if (p.is_absolute() || base_dir.empty()) return p.lexically_normal().string();
    return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

Eigen::Vector3d vec3(const toml::Reader& r, const std::string& key, const Eigen::Vector3d& def,
                     bool allow_scalar = false) {
    return r.get_vector(key, 3, def, allow_scalar);
}

Eigen::Matrix3d rotation_of(const toml::Reader& r, const std::string& key,
                            const std::string& spec) {
    try {
        return parse_rotation(spec);
    } catch (const Error& e) {
        throw Error(str(r.where(key), e.what()));
    }
}

void parse_environment(const toml::Document& doc, SceneDesc& scene, const std::string& base) {
    const auto it = doc.tables.find("environment");
    if (it == doc.tables.end()) {
        throw Error(str(doc.source, ": missing [environment] table"));
    }
    toml::Reader r(doc, it->second);
    EnvironmentSpec& env = scene.environment;
    env.path = resolve(base, r.get_string("path", ""));
    if (r.has("path") && r.has("radiance")) {
        throw Error(str(r.where("radiance"), "give either path or radiance, not both"));
    }
    env.radiance = vec3(r, "radiance", env.radiance, true);
    env.layout = r.get_string("layout", env.layout);
    try {
        enum_from_string<Error>(kSceneLayoutNames, env.layout, "environment layout");
    } catch (const Error& e) {
        throw Error(str(r.where("layout"), e.what()));
    }
    env.latlong_height_px = r.get_int("latlong_height_px", env.latlong_height_px);
    r.check_range("latlong_height_px", env.latlong_height_px, 0, 16384);
    env.rotation = r.get_string("rotation", env.rotation);
    rotation_of(r, "rotation", env.rotation);
    env.intensity = r.get_double("intensity", env.intensity);
    r.check_range("intensity", env.intensity, 0, 1e12);
    for (int c = 0; c < 3; ++c) r.check_range("radiance", env.radiance[c], 0, 1e12);
    r.finish();
}

void parse_camera(const toml::Document& doc, SceneDesc& scene) {
    const auto it = doc.tables.find("camera");
    if (it == doc.tables.end()) throw Error(str(doc.source, ": missing [camera] table"));
    toml::Reader r(doc, it->second);
    Camera& cam = scene.camera;
    try {
        cam.projection = projection_from_string(r.get_string("projection", "orthographic"));
    } catch (const Error& e) {
        throw Error(str(r.where("projection"), e.what()));
    }
    cam.position = vec3(r, "position", cam.position);
    cam.look_at = vec3(r, "look_at", cam.look_at);
    cam.up = vec3(r, "up", cam.up);
    cam.fov_deg = r.get_double("fov_deg", cam.fov_deg);
    r.check_range("fov_deg", cam.fov_deg, 1e-3, 179.9);
    cam.ortho_height = r.get_double("ortho_height", cam.ortho_height);
    r.check_range("ortho_height", cam.ortho_height, 1e-9, 1e9);
    cam.width_px = r.get_int("width_px", cam.width_px);
    r.check_range("width_px", cam.width_px, 1, 16384);
    cam.height_px = r.get_int("height_px", cam.height_px);
    r.check_range("height_px", cam.height_px, 1, 16384);
    r.finish();
    cam.validate(str(doc.source, ": [camera] "));
}

void parse_materials(const toml::Document& doc, SceneDesc& scene, const std::string& base) {
    for (const auto& [table_name, table] : doc.tables) {
        if (table_name.rfind("material.", 0) != 0) {
            if (table_name != "environment" && table_name != "camera") {
                throw Error(str(doc.source, ":", table.line, ": unknown table [", table_name,
                                "] (known: [environment], [camera], [material.<name>], "
                                "[[object]])"));
            }
            continue;
        }
        toml::Reader r(doc, table);
        SurfaceMaterial m;
        m.name = table_name.substr(9);
        if (r.has("file")) {
            const std::string file = resolve(base, r.get_string("file", ""));
            try {
                m.brdf = brdf::load_material(file);
            } catch (const Error& e) {
                throw Error(str(r.where("file"), e.what()));
            }
        }
        brdf::read_material_keys(r, m.brdf);  // the keys of a material file, inline
        m.albedo_texture_path = resolve(base, r.get_string("albedo_texture", ""));
        m.normal_texture_path = resolve(base, r.get_string("normal_texture", ""));
        m.roughness_texture_path = resolve(base, r.get_string("roughness_texture", ""));
        m.uv_scale = r.get_vector("uv_scale", 2, m.uv_scale, true);
        r.check_range("uv_scale", m.uv_scale.minCoeff(), 1e-6, 1e6);
        r.finish();
        if (!r.has("file")) brdf::require_specular(r);
        scene.materials.push_back(std::move(m));
    }
}

void parse_objects(const toml::Document& doc, SceneDesc& scene, const std::string& base) {
    const auto it = doc.table_arrays.find("object");
    if (it == doc.table_arrays.end() || it->second.empty()) {
        throw Error(str(doc.source, ": no [[object]] in the scene"));
    }
    for (const auto& [name, list] : doc.table_arrays) {
        if (name != "object") {
            throw Error(str(doc.source, ":", list.front().line, ": unknown table array [[", name,
                            "]] (known: [[object]])"));
        }
    }
    for (const toml::Table& table : it->second) {
        toml::Reader r(doc, table);
        ObjectSpec o;
        o.name = r.get_string("name", str("object ", scene.objects.size()));
        try {
            o.shape.kind = shape_from_string(r.require_string("shape"));
        } catch (const Error& e) {
            throw Error(str(r.where("shape"), e.what()));
        }
        if (o.shape.kind == ShapeKind::kWeave) {
            if (r.has("material")) {
                throw Error(str(r.where("material"),
                                "a weave takes its materials from its fabric file"));
            }
        } else {
            o.material = r.require_string("material");
            bool found = false;
            for (const auto& m : scene.materials) found |= m.name == o.material;
            if (!found) {
                throw Error(
                    str(r.where("material"), "no [material.", o.material, "] in the scene"));
            }
        }
        if (o.shape.kind == ShapeKind::kWeave) {
            o.fabric_path = resolve(base, r.require_string("fabric"));
            o.shape.size = r.get_vector("size", 2, o.shape.size, true);
            r.check_range("size", o.shape.size.minCoeff(), 1e-6, 1e6);
            o.shape.center = vec3(r, "center", o.shape.center);
        } else if (o.shape.kind == ShapeKind::kPatch) {
            o.shape.size = r.get_vector("size", 2, o.shape.size, true);
            r.check_range("size", o.shape.size.minCoeff(), 1e-9, 1e9);
            o.shape.center = vec3(r, "center", o.shape.center);
        } else if (o.shape.kind == ShapeKind::kSphere) {
            o.shape.center = vec3(r, "center", o.shape.center);
            o.shape.radius = r.get_double("radius", o.shape.radius);
            r.check_range("radius", o.shape.radius, 1e-9, 1e9);
        } else {
            o.mesh_path = resolve(base, r.require_string("path"));
            o.scale = r.get_double("scale", o.scale);
            r.check_range("scale", o.scale, 1e-9, 1e9);
            o.rotation = r.get_string("rotation", o.rotation);
            rotation_of(r, "rotation", o.rotation);
            o.translate = vec3(r, "translate", o.translate);
        }
        r.finish();
        scene.objects.push_back(std::move(o));
    }
}

}  // namespace

SceneDesc parse_scene(const std::string& text, const std::string& source,
                      const std::string& base_dir) {
    const toml::Document doc = toml::parse(text, source);
    if (!doc.root.values.empty()) {
        const auto& [key, value] = *doc.root.values.begin();
        throw Error(str(source, ":", value.line, ": key '", key,
                        "' outside any table (put it under [environment], [camera], ...)"));
    }
    SceneDesc scene;
    scene.source = source;
    parse_environment(doc, scene, base_dir);
    parse_camera(doc, scene);
    parse_materials(doc, scene, base_dir);
    parse_objects(doc, scene, base_dir);
    return scene;
}

SceneDesc load_scene_desc(const std::string& path) {
    const std::string base = std::filesystem::path(path).parent_path().string();
    return parse_scene(fs::read_file(path), path, base);
}

Scene::Scene(SceneDesc desc) : m_desc(std::move(desc)) {
    const std::string ctx = m_desc.source.empty() ? "scene" : m_desc.source;
    const EnvironmentSpec& env = m_desc.environment;
    Eigen::Matrix3d world_from_env = parse_rotation(env.rotation);
    if (env.image.width > 0) {
        m_environment = std::make_unique<EnvironmentLight>(env.image, world_from_env, env.intensity,
                                                           ctx + ": environment");
    } else if (!env.path.empty()) {
        m_environment = std::make_unique<EnvironmentLight>(
            load_environment_latlong(env.path, env.layout, env.latlong_height_px), world_from_env,
            env.intensity, env.path);
        m_files.push_back(env.path);
    } else {
        m_environment = std::make_unique<EnvironmentLight>(
            EnvironmentLight::constant(env.radiance * env.intensity));
    }
    m_desc.camera.validate(ctx + ": camera: ");

    std::map<std::string, int> material_index;
    for (const SurfaceMaterial& m : m_desc.materials) {
        SurfaceMaterial loaded = m;
        load_textures(loaded);
        for (const auto* p :
             {&m.albedo_texture_path, &m.normal_texture_path, &m.roughness_texture_path}) {
            if (!p->empty()) m_files.push_back(*p);
        }
        material_index[m.name] = static_cast<int>(m_materials.size());
        m_materials.push_back(std::move(loaded));
    }
    if (m_desc.objects.empty()) throw Error(str(ctx, ": the scene has no objects"));
    std::vector<Shape> shapes;
    for (const ObjectSpec& o : m_desc.objects) {
        if (o.shape.kind == ShapeKind::kWeave) {
            std::shared_ptr<const weave::Weave> w = o.weave;
            if (!w) {
                w = std::make_shared<weave::Weave>(weave::build(weave::load_weave(o.fabric_path)));
                m_files.push_back(o.fabric_path);
            }
            const Eigen::Vector2d half = 0.5 * o.shape.size;
            const Eigen::Vector2d c = o.shape.center.head<2>();
            WeaveShapes ws = weave_shapes(*w, c - half, c + half, o.shape.center.z());
            SurfaceMaterial yarn, backing;
            yarn.name = o.name + "/yarn";
            yarn.brdf = ws.yarn_material;
            backing.name = o.name + "/backing";
            backing.brdf = ws.backing_material;
            for (auto* m : {&yarn, &backing}) {
                m_material_of_shape.push_back(static_cast<int>(m_materials.size()));
                m_materials.push_back(*m);
            }
            shapes.push_back(std::move(ws.yarns));
            shapes.push_back(std::move(ws.backing));
            continue;
        }
        const auto it = material_index.find(o.material);
        if (it == material_index.end()) {
            throw Error(str(ctx, ": object '", o.name, "': unknown material '", o.material, "'"));
        }
        m_material_of_shape.push_back(it->second);
        Shape s = o.shape;
        if (s.kind == ShapeKind::kMesh) {
            if (!s.mesh) {
                auto mesh = std::make_shared<TriangleMesh>(load_mesh(o.mesh_path));
                m_files.push_back(o.mesh_path);
                const Eigen::Matrix3d r = parse_rotation(o.rotation);
                for (auto& p : mesh->positions) {
                    p = o.translate + r * (o.scale * p);
                    if (!p.allFinite()) {
                        throw Error(str(o.mesh_path, ": a vertex is not finite after scale ",
                                        o.scale, " and translate (object '", o.name, "')"));
                    }
                }
                for (auto& n : mesh->normals) n = (r * n).normalized();
                s.mesh = std::move(mesh);
            }
        }
        shapes.push_back(std::move(s));
    }
    m_accel = std::make_unique<Accel>(std::move(shapes));
}

}  // namespace inlight::render
