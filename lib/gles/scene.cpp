#include "gles/scene.h"

#include <algorithm>
#include <cctype>

#include "brdf/bake.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/log.h"
#include "image/color.h"
#include "render/realtime.h"

namespace inlight::gles {

namespace {

void add_vertex(Mesh& m, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                const Eigen::Vector3d& t, const Eigen::Vector2d& uv) {
    m.position.push_back(p.cast<float>());
    m.normal.push_back(n.cast<float>());
    m.tangent.push_back(t.cast<float>());
    m.uv.push_back(uv.cast<float>());
}

/// A unit tangent orthogonal to n: `hint` made orthogonal, else any (as accel.cpp).
Eigen::Vector3d tangent_for(const Eigen::Vector3d& n, const Eigen::Vector3d& hint) {
    Eigen::Vector3d t = hint - n * n.dot(hint);
    if (t.squaredNorm() > 1e-24) return t.normalized();
    t = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    return (t - n * n.dot(t)).normalized();
}

/// A patch's two triangles: normal +z, tangent +x, uv (0, 0) at its top-left corner, v down.
void add_patch(Mesh& m, const render::Shape& s) {
    const double x0 = s.center.x() - 0.5 * s.size.x(), x1 = x0 + s.size.x();
    const double y1 = s.center.y() + 0.5 * s.size.y(), y0 = y1 - s.size.y();
    auto corner = [&](double x, double y) {
        add_vertex(m, {x, y, s.center.z()}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                   {(x - x0) / s.size.x(), (y1 - y) / s.size.y()});
    };
    for (const auto& [x, y] : {std::pair{x0, y1}, {x1, y1}, {x1, y0}, {x0, y1}, {x1, y0}, {x0, y0}}) {
        corner(x, y);
    }
}

/// The draw's depth range from the meshes' extent along the view (1% margin; perspective: near
/// at least 1e-3 far) and the camera's clip_from_world over it.
Eigen::Matrix4f clip_for_meshes(const render::Camera& cam, const std::vector<Mesh>& meshes) {
    const Eigen::Vector3d f = (cam.look_at - cam.position).normalized();
    double zmin = 1e300, zmax = -1e300;
    for (const Mesh& m : meshes) {
        for (const Eigen::Vector3f& p : m.position) {
            const double z = f.dot(p.cast<double>() - cam.position);
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
    }
    const double span = std::max(zmax - zmin, 1e-3);
    double near = zmin - 0.01 * span, far = zmax + 0.01 * span;
    if (cam.projection == render::Projection::kPerspective) near = std::max(near, 1e-3 * far);
    return clip_from_world(cam, near, far);
}

std::vector<Mesh> scene_meshes(const render::Scene& scene) {
    std::vector<Mesh> meshes;
    for (size_t i = 0; i < scene.materials().size(); ++i) meshes.push_back(scene_mesh(scene, static_cast<int>(i)));
    return meshes;
}

/// The manifest's "scene": the draw render export-gles' scene makes with one material, so that
/// an app (or tests/gles/binder) can reproduce it from the manifest alone.
nlohmann::json scene_section(const render::Scene& scene, int material, const Eigen::Matrix4f& clip) {
    const render::Camera& cam = scene.camera();
    nlohmann::json patches = nlohmann::json::array();
    int others = 0;
    const auto& shapes = scene.accel().shapes();
    for (size_t i = 0; i < shapes.size(); ++i) {
        if (scene.material_index(static_cast<int>(i)) != material) continue;
        if (shapes[i].kind != render::ShapeKind::kPatch) {
            ++others;
            continue;
        }
        Mesh m;
        add_patch(m, shapes[i]);
        nlohmann::json vertices = nlohmann::json::array();
        for (size_t v = 0; v < m.position.size(); ++v) {
            vertices.push_back({m.position[v].x(), m.position[v].y(), m.position[v].z(), m.normal[v].x(),
                                m.normal[v].y(), m.normal[v].z(), m.tangent[v].x(), m.tangent[v].y(),
                                m.tangent[v].z(), m.uv[v].x(), m.uv[v].y()});
        }
        patches.push_back({{"object", static_cast<int>(i)}, {"vertices", vertices}});
    }
    return {{"camera", {{"width_px", cam.width_px}, {"height_px", cam.height_px}}},
            {"clip_from_object", std::vector<float>(clip.data(), clip.data() + 16)},
            {"clip_from_object_layout", "column-major, as glUniformMatrix4fv(transpose GL_FALSE) takes it"},
            {"frame", "the scene's world frame is the device frame"},
            {"patches", patches},
            {"patch_vertex", "a_position (3), a_normal (3), a_tangent (3), a_uv (2) per vertex, GL_TRIANGLES"},
            {"other_shapes", others},
            {"note", "the draw render export-gles' scene makes with this material (its camera, its patches; "
                     "spheres and meshes are counted in other_shapes, not listed): an example of the app's "
                     "u_clip_from_object and geometry"}};
}

/// export_scene() on the baked tables, or (`shapes_only`) on zero tables of their shape: the
/// same variants at the same limits, without the bake.
std::vector<Export> export_materials(const render::Scene& scene,
                                     const SceneExportOptions& options, bool shapes_only) {
    brdf::BakeOptions bo;
    bo.sh_bands = std::max(3, options.set.max_sh_bands);
    bo.samples = options.bake_samples;
    const render::Camera& cam = scene.camera();
    bo.view = (cam.position - cam.look_at).normalized();
    const brdf::Grid grid = brdf::parse_grid(options.grid);
    std::vector<Export> out;
    const auto& materials = scene.materials();  // textures loaded: their sizes are known
    const Eigen::Matrix4f clip = clip_for_meshes(cam, scene_meshes(scene));
    for (size_t i = 0; i < materials.size(); ++i) {
        const render::SurfaceMaterial& m = materials[i];
        MaterialInputs in;
        in.name = m.name.empty() ? str("material", i) : m.name;
        std::replace_if(
            in.name.begin(), in.name.end(),
            [](char c) { return !(std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
                                  c == '.' || c == '-'); },
            '_');
        in.brdf = m.brdf;
        in.uv_scale = m.uv_scale.cast<float>();
        // The bytes render_scene() binds (the harness draw of the scene).
        if (m.albedo_texture) {
            in.albedo_texture_px = {m.albedo_texture->width, m.albedo_texture->height};
            if (!shapes_only) in.albedo_rgba8 = to_texture8(*m.albedo_texture, true).rgba;
        }
        if (m.normal_texture) {
            in.normal_texture_px = {m.normal_texture->width, m.normal_texture->height};
            if (!shapes_only) in.normal_rgba8 = to_texture8(*m.normal_texture, false).rgba;
        }
        const bool lambert = m.brdf.specular == brdf::Model::kLambert;
        const brdf::Table table = lambert ? brdf::Table() : shapes_only ? table_shape(m.brdf, grid, bo.sh_bands)
                                                                        : brdf::bake(m.brdf, grid, bo);
        for (Export& e : export_material(lambert ? nullptr : &table, in, options.set)) {
            e.manifest["scene"] = scene_section(scene, static_cast<int>(i), clip);
            out.push_back(std::move(e));
        }
    }
    return out;
}

}  // namespace

Texture8 to_texture8(const image::Image& img, bool srgb) {
    Texture8 t;
    t.width = img.width;
    t.height = img.height;
    t.rgba.reserve(static_cast<size_t>(img.width) * img.height * 4);
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                // The 8-bit file's code: the CPU holds it decoded (sRGB) or as code / 255.
                const float v = img.at(x, y, std::min(c, img.channels - 1));
                const float e = srgb ? image::srgb_encode(v) : v;
                t.rgba.push_back(static_cast<uint8_t>(std::clamp(std::lround(e * 255.0f), 0L, 255L)));
            }
            t.rgba.push_back(255);
        }
    }
    return t;
}

std::vector<Export> export_scene(const render::Scene& scene, const SceneExportOptions& options) {
    return export_materials(scene, options, false);
}

void check_scene_export(const render::Scene& scene, const SceneExportOptions& options) {
    export_materials(scene, options, true);
}

Eigen::Matrix4f clip_from_world(const render::Camera& cam, double near, double far) {
    const Eigen::Vector3d f = (cam.look_at - cam.position).normalized();
    const Eigen::Vector3d r = f.cross(cam.up).normalized();
    const Eigen::Vector3d u = r.cross(f);
    Eigen::Matrix4d view = Eigen::Matrix4d::Identity();  // rows: right, up, forward (depth)
    view.block<1, 3>(0, 0) = r.transpose();
    view.block<1, 3>(1, 0) = u.transpose();
    view.block<1, 3>(2, 0) = f.transpose();
    view.block<3, 1>(0, 3) = -view.block<3, 3>(0, 0) * cam.position;
    const double aspect = static_cast<double>(cam.width_px) / cam.height_px;
    Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
    if (cam.projection == render::Projection::kOrthographic) {
        const double half = 0.5 * cam.ortho_height;
        proj(0, 0) = 1.0 / (half * aspect);
        proj(1, 1) = 1.0 / half;
        proj(2, 2) = 2.0 / (far - near);
        proj(2, 3) = -(far + near) / (far - near);
        proj(3, 3) = 1.0;
    } else {
        const double t = std::tan(0.5 * cam.fov_deg * kPi / 180.0);
        proj(0, 0) = 1.0 / (t * aspect);
        proj(1, 1) = 1.0 / t;
        proj(2, 2) = (far + near) / (far - near);
        proj(2, 3) = -2.0 * far * near / (far - near);
        proj(3, 2) = 1.0;
    }
    return (proj * view).cast<float>();
}

Mesh scene_mesh(const render::Scene& scene, int material, int sphere_rows) {
    Mesh m;
    const auto& shapes = scene.accel().shapes();
    for (size_t i = 0; i < shapes.size(); ++i) {
        if (scene.material_index(static_cast<int>(i)) != material) continue;
        const render::Shape& s = shapes[i];
        if (s.kind == render::ShapeKind::kPatch) {
            add_patch(m, s);
        } else if (s.kind == render::ShapeKind::kSphere) {
            const int rows = sphere_rows, cols = 2 * sphere_rows;
            auto vertex = [&](int r, int c) {
                const Eigen::Vector2d uv(static_cast<double>(c) / cols,
                                         static_cast<double>(r) / rows);
                const double phi = kPi * (1.0 - 2.0 * uv.x()), theta = kPi * uv.y();
                const Eigen::Vector3d n = direction_from_spherical(theta, phi);
                add_vertex(m, s.center + s.radius * n, n,
                           tangent_for(n, {std::sin(phi), -std::cos(phi), 0.0}), uv);
            };
            for (int r = 0; r < rows; ++r) {
                for (int c = 0; c < cols; ++c) {
                    for (const auto& [dr, dc] : {std::pair{0, 0}, {0, 1}, {1, 1}, {0, 0}, {1, 1},
                                                 {1, 0}}) {
                        vertex(r + dr, c + dc);
                    }
                }
            }
        } else {
            const render::TriangleMesh& tm = *s.mesh;
            for (const Eigen::Vector3i& tri : tm.triangles) {
                const Eigen::Vector3d p[3] = {tm.positions[tri[0]], tm.positions[tri[1]],
                                              tm.positions[tri[2]]};
                const Eigen::Vector3d ng = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
                Eigen::Vector3d dpdu = Eigen::Vector3d::UnitX();
                Eigen::Vector2d uv[3] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
                                         Eigen::Vector2d::Zero()};
                if (!tm.uvs.empty()) {
                    for (int k = 0; k < 3; ++k) uv[k] = tm.uvs[tri[k]];
                    const Eigen::Vector2d d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
                    const double det = d1.x() * d2.y() - d1.y() * d2.x();
                    if (std::abs(det) > 1e-20) {
                        dpdu = (d2.y() * (p[1] - p[0]) - d1.y() * (p[2] - p[0])) / det;
                    }
                }
                for (int k = 0; k < 3; ++k) {
                    const Eigen::Vector3d n = tm.normals.empty() ? ng : tm.normals[tri[k]];
                    add_vertex(m, p[k], n, tangent_for(n, dpdu), uv[k]);
                }
            }
        }
    }
    return m;
}

SceneFrame render_scene(const Context& context, const render::Scene& scene,
                        const std::vector<Export>& per_material, const Eigen::MatrixXd& coeffs,
                        int repeat, const std::vector<envmap::DirectionalLight>& lights) {
    const render::Camera& cam = scene.camera();
    const auto& materials = scene.materials();
    if (per_material.size() != materials.size()) {
        throw Error(str("GLES scene: ", per_material.size(), " exports for ", materials.size(),
                        " materials"));
    }
    const std::vector<Mesh> meshes = scene_meshes(scene);
    std::vector<Texture8> albedo(materials.size()), normal(materials.size());
    std::vector<Bindings> bindings(materials.size());
    const Eigen::Matrix4f clip = clip_for_meshes(cam, meshes);
    std::vector<DrawItem> items;
    for (size_t i = 0; i < materials.size(); ++i) {
        if (meshes[i].position.empty()) continue;
        const render::SurfaceMaterial& m = materials[i];
        Bindings& b = bindings[i];
        b.clip_from_object = clip;
        b.sh = coeffs;
        b.lights = lights;
        b.albedo = m.brdf.albedo.cast<float>();
        b.uv_scale = m.uv_scale.cast<float>();
        if (m.albedo_texture) {
            albedo[i] = to_texture8(*m.albedo_texture, true);
            b.albedo_texture = &albedo[i];
        }
        if (m.normal_texture) {
            normal[i] = to_texture8(*m.normal_texture, false);
            b.normal_texture = &normal[i];
        }
        items.push_back({&per_material[i], &b, &meshes[i]});
    }
    const Readback rb = draw(context, items, cam.width_px, cam.height_px, TargetFormat::kRgba32f,
                             repeat);
    SceneFrame out;
    out.frame_ms = rb.draw_ms;
    out.radiance = image::Image(cam.width_px, cam.height_px, 3, image::ColorSpace::kLinearSrgb);
    for (int y = 0; y < cam.height_px; ++y) {
        for (int x = 0; x < cam.width_px; ++x) {
            if (rb.at(x, y, 3) > 0) {
                for (int c = 0; c < 3; ++c) out.radiance.at(x, y, c) = rb.at(x, y, c);
            } else {
                const render::Ray ray = cam.generate_ray(x + 0.5, y + 0.5);
                const Eigen::Vector3d e = scene.environment().eval(ray.dir);
                for (int c = 0; c < 3; ++c) out.radiance.at(x, y, c) = static_cast<float>(e[c]);
            }
        }
    }
    return out;
}

nlohmann::json compare_scene(const render::Scene& scene, const render::RenderResult& truth,
                             const render::CompareOptions& options, const std::string& prefix,
                             std::vector<render::WrittenFile>& written,
                             const render::LightingFile* lighting) {
    const double exposure =
        options.exposure > 0 ? options.exposure : render::auto_exposure(truth.radiance);
    render::RealtimeLighting lighting_sh;
    lighting_sh.coeffs = render::project_environment(scene.environment(), options.max_bands);
    lighting_sh.tables = render::compare_tables(scene, options, options.max_bands);

    // The lighting file's variants: its residual SH (zero-padded to 3 bands) and its lights.
    render::RealtimeLighting lit;
    const int lit_bands = lighting ? std::max(3, lighting->sh.sh_bands) : 0;
    nlohmann::json out = {{"exposure", exposure}, {"variants", nlohmann::json::array()}};
    if (lighting && lit_bands > brdf::kMaxBakeBands) {
        const std::string why = str("the lighting file has ", lighting->sh.sh_bands,
                                    " bands, the BRDF bake at most ", brdf::kMaxBakeBands);
        log::warn(str("compare gles: no variants with the file's lights: ", why));
        out["lighting_file_variants_skipped"] = why;
    } else if (lighting) {
        lit.coeffs = Eigen::MatrixXd::Zero(sh::count(lit_bands), 3);
        lit.coeffs.topRows(lighting->sh.coeffs.rows()) = lighting->sh.coeffs;
        lit.lights = lighting->lights;
        lit.tables = render::compare_tables(scene, options, lit_bands);
    }

    for (GlslVersion version : {GlslVersion::kEs300, GlslVersion::kEs100}) {
        const Context context(version == GlslVersion::kEs300 ? 3 : 2);
        out["driver"] = context.info().summary();
        std::vector<std::pair<Variant, const render::RealtimeLighting*>> variants;
        for (int bands = 3; bands <= options.max_bands; ++bands) {
            variants.push_back({{version, ShaderMode::kConsistent, bands, Precision::kHighp}, &lighting_sh});
        }
        variants.push_back({{version, ShaderMode::kSeed, 3, Precision::kHighp}, &lighting_sh});
        if (!lit.tables.empty()) {
            const int n_lights = static_cast<int>(lit.lights.size());
            variants.push_back({{version, ShaderMode::kConsistent, lit_bands, Precision::kHighp, n_lights,
                                 common_light_shading(lit.lights)},
                                &lit});
        }
        for (auto& variant : variants) variant.first.texture_filter = options.gles_texture_filter;
        for (const auto& [v, source] : variants) {
            std::vector<Export> exports;
            render::RealtimeLighting bound = *source;
            std::string name;
            for (size_t i = 0; i < scene.materials().size(); ++i) {
                const render::SurfaceMaterial& m = scene.materials()[i];
                MaterialInputs in;
                in.name = "m" + std::to_string(i);
                in.brdf = m.brdf;
                if (m.albedo_texture) in.albedo_texture_px = {m.albedo_texture->width, m.albedo_texture->height};
                if (m.normal_texture) in.normal_texture_px = {m.normal_texture->width, m.normal_texture->height};
                const bool lambert = m.brdf.specular == brdf::Model::kLambert;
                exports.push_back(export_variant(lambert ? nullptr : &source->tables[i], in, v,
                                                 context.info().limits));
                if (exports.back().table_as_bound) bound.tables[i] = *exports.back().table_as_bound;
                name = exports.back().name.substr(exports.back().name.find('-') + 1);
            }
            if (source == &lit) name += "-file";  // lit by the --rt-lighting file
            const SceneFrame frame = render_scene(context, scene, exports, source->coeffs, 3, source->lights);
            // The CPU model on the same inputs, one fragment per pixel (what the GPU shades).
            render::RealtimeOptions ro;
            ro.mode = v.mode == ShaderMode::kSeed ? render::RealtimeMode::kSeed
                                                  : render::RealtimeMode::kConsistent;
            ro.sh_bands = v.sh_bands;
            ro.supersample = 1;
            ro.texture_filter = v.texture_filter;
            const image::Image cpu = render::render_realtime(scene, bound, ro);
            int within = 0;
            const int n = cpu.width * cpu.height;
            for (int y = 0; y < cpu.height; ++y) {
                for (int x = 0; x < cpu.width; ++x) {
                    bool ok = true;
                    for (int c = 0; c < 3; ++c) {
                        const double want = cpu.at(x, y, c), got = frame.radiance.at(x, y, c);
                        ok = ok && std::abs(got - want) <= 1e-3 * std::max(std::abs(want), options.rel_floor);
                    }
                    within += ok ? 1 : 0;
                }
            }
            const render::Comparison c = render::compare_images(truth.radiance, frame.radiance, exposure, options);
            const render::Comparison c_cpu = render::compare_images(truth.radiance, cpu, exposure, options);
            nlohmann::json j = render::metrics_json(c.metrics);
            j["variant"] = name;
            j["glsl_version"] = to_string(version);
            j["mode"] = to_string(v.mode);
            j["sh_bands"] = v.sh_bands;
            j["lights"] = v.lights;
            j["texture_filter"] = to_string(v.texture_filter);
            if (v.lights > 0) j["lighting_file_bands"] = lighting->sh.sh_bands;
            j["frame_time_ms"] = frame.frame_ms;
            j["cpu_model_fraction_within_1e-3"] = static_cast<double>(within) / n;
            j["cpu_model_vs_truth"] = render::metrics_json(c_cpu.metrics);
            out["variants"].push_back(j);
            const std::string base = prefix + "_gles_" + name;
            image::write_image(base + ".exr", frame.radiance);
            written.push_back({base + ".exr", "gles_radiance", "linear_srgb"});
            image::write_image(base + "_relerr.exr", c.rel_error);
            written.push_back({base + "_relerr.exr", "relative_error", "data"});
            image::write_image(base + "_de2000.exr", c.de2000);
            written.push_back({base + "_de2000.exr", "delta_e2000", "data"});
            // truth | CPU model | GLES | GLES relative-error heat map.
            const int w = cpu.width;
            image::Image cpu_panel(w, cpu.height, 3, image::ColorSpace::kLinearSrgb);
            for (int y = 0; y < cpu.height; ++y)
                for (int x = 0; x < w; ++x)
                    for (int ch = 0; ch < 3; ++ch) cpu_panel.at(x, y, ch) = c_cpu.side_by_side.at(w + x, y, ch);
            image::write_image(prefix + "_compare3_" + name + ".png",
                               render::comparison_figure(c, "GLES", options, {{&cpu_panel, "CPU model"}}));
            written.push_back({prefix + "_compare3_" + name + ".png", "side_by_side", "srgb"});
            log::summary("render", str("GLES ", name, " vs path-traced truth"),
                         str("mean relative error ", log::num(c.metrics.mean_rel), ", mean Delta E 2000 ",
                             log::num(c.metrics.mean_de2000), "; ", log::num(100.0 * within / n),
                             "% of pixels within 1e-3 of the CPU model, ",
                             log::num(frame.frame_ms, 3), " ms/frame"));
        }
    }
    return out;
}

}  // namespace inlight::gles
