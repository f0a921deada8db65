// render/scene.h: scene files (TOML) and the loaded scene the integrators query.
//
// A scene file (see configs/scenes/*.toml and docs/render.md) has:
//   [environment]  path = "sky.exr" | radiance = [r, g, b]; layout = "latlong" | "cube" |
//                  "angular" (cube and angular are resampled to lat-long, latlong_height_px
//                  rows, 0 = automatic; render/environment.h); rotation = "none"
//                  (core/conventions.h parse_rotation), intensity = 1.0
//   [camera]       projection = "orthographic" | "perspective", position, look_at, up,
//                  fov_deg (vertical, perspective), ortho_height (world units), width_px, height_px
//   [material.<name>]  file = "denim.toml" (a brdf-sh-bake material, brdf::load_material), then
//                  any of its keys inline to override (brdf::read_material_keys: same keys and
//                  ranges): specular, albedo, f0, alpha, report_f, report_r, sheen_color,
//                  specular_scale; and albedo_texture, normal_texture,
//                  roughness_texture, uv_scale = [su, sv] (render/material.h)
//   [[object]]     shape = "patch" | "sphere" | "mesh" | "weave", material = "<name>", name = "...";
//                  patch: size = [w, h], center = [x, y, z] (in the plane z = center.z, facing +z)
//                  sphere: center, radius; mesh: path (.obj/.ply), scale, rotation, translate
//                  weave: fabric = "wool.toml" (weave/weave.h; no material key: the fabric
//                  brings its yarn and backing materials), size = [w, h] and center = [x, y, z]:
//                  the region the yarns cover, repeated from the tile at the origin, mid-plane
//                  z = center.z; lengths in mm (render/weave_geometry.h)
// Relative paths are relative to the scene file's folder. Every key is checked: an unknown key,
// a wrong type or a value out of range throws Error "<file>:<line>: [<table>] <key>: <what>".
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/accel.h"
#include "render/camera.h"
#include "render/environment.h"
#include "render/material.h"
#include "weave/weave.h"

namespace inlight::render {

struct EnvironmentSpec {
    std::string path;                   ///< environment file; empty = constant `radiance`
    std::string layout = "latlong";     ///< "latlong" | "cube" | "angular" (envmap-project's)
    int latlong_height_px = 0;          ///< resampling height for cube/angular; 0 = automatic
    std::string rotation = "none";      ///< parse_rotation syntax: world_from_env
    double intensity = 1.0;             ///< linear scale, >= 0
    Eigen::Vector3d radiance{1, 1, 1};  ///< constant environment (when path and image are empty)
    image::Image image;                 ///< in-memory lat-long map (tests); used when non-empty
};

struct ObjectSpec {
    std::string name;
    Shape shape;            ///< kind, center, size, radius (meshes: filled by Scene)
    std::string mesh_path;  ///< kMesh
    double scale = 1.0;     ///< kMesh: world = translate + rotation * (scale * object)
    std::string rotation = "none";
    Eigen::Vector3d translate = Eigen::Vector3d::Zero();
    std::string material;  ///< name of a material in SceneDesc::materials (not for kWeave)
    std::string fabric_path;                    ///< kWeave: the fabric file
    std::shared_ptr<const weave::Weave> weave;  ///< kWeave: built from fabric_path if null
};

struct SceneDesc {
    std::string source;  ///< scene file, for messages ("" for scenes built in code)
    EnvironmentSpec environment;
    Camera camera;
    std::vector<SurfaceMaterial> materials;  ///< textures not loaded yet
    std::vector<ObjectSpec> objects;
};

/// Parses scene TOML text; relative paths are resolved against `base_dir`. Does not read the
/// files it names (Scene does). Throws Error naming the source, line, table and key.
SceneDesc parse_scene(const std::string& text, const std::string& source,
                      const std::string& base_dir);
/// Reads and parses a scene file.
SceneDesc load_scene_desc(const std::string& path);

/// A loaded scene: environment, textures, meshes, and the Embree acceleration structure.
/// Immutable after construction and safe to query from many threads.
class Scene {
  public:
    /// Loads everything `desc` names. Throws Error naming the file (or the object/material)
    /// on any failure.
    explicit Scene(SceneDesc desc);

    const SceneDesc& desc() const { return m_desc; }
    const Camera& camera() const { return m_desc.camera; }
    const EnvironmentLight& environment() const { return *m_environment; }
    const Accel& accel() const { return *m_accel; }
    /// The material of shape `shape` (index of Accel::shapes(); a weave object adds two shapes,
    /// its yarns and its backing, so shape indices follow objects only without weaves).
    const SurfaceMaterial& material(int shape) const {
        return m_materials[static_cast<size_t>(m_material_of_shape[static_cast<size_t>(shape)])];
    }
    /// The loaded materials (SceneDesc::materials, then two per weave object), textures loaded.
    const std::vector<SurfaceMaterial>& materials() const { return m_materials; }
    /// Index into the scene's loaded materials (SceneDesc::materials, then two per weave object)
    /// of shape `shape`'s material.
    int material_index(int shape) const { return m_material_of_shape[static_cast<size_t>(shape)]; }
    /// Every file the scene read (for the run report's inputs).
    const std::vector<std::string>& files() const { return m_files; }

  private:
    SceneDesc m_desc;
    std::unique_ptr<EnvironmentLight> m_environment;
    std::vector<SurfaceMaterial> m_materials;
    std::vector<int> m_material_of_shape;
    std::unique_ptr<Accel> m_accel;
    std::vector<std::string> m_files;
};

}  // namespace inlight::render
