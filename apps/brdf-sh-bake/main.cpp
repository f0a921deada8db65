// brdf-sh-bake: tabulate a material's cosine-weighted BRDF lobe in SH over a grid of normals for
// the GLES shader, and report how exact the table is (lib/brdf/bake.h, docs/brdf.md).
#include <cmath>
#include <filesystem>
#include <optional>

#include "brdf/bake.h"
#include "brdf/glsl.h"
#include "core/app.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/validators.h"
#include "gles/cli.h"

using namespace inlight;

int main(int argc, char** argv) {
    CLI::App cli{
        "brdf-sh-bake: project a material's cosine-weighted specular/sheen lobe into SH "
        "at each normal of a grid (view fixed) and report the table's error",
        "brdf-sh-bake"};
    app::CommonArgs common;
    std::string material_path, output, grid_spec = "thetaphi:9x32", integrator = "gauss-legendre";
    std::string view_deg, view_xyz;
    brdf::BakeOptions o;
    double max_error = -1;
    bool full_validate = false;
    cli.add_option("--material", material_path,
                   "Material file (TOML: specular, albedo, f0, "
                   "alpha, report_f, report_r, sheen_color, specular_scale)")
        ->required()
        ->check(CLI::ExistingFile);
    cli.add_option("-o,--output", output,
                   "Output stem: writes OUT.bin, OUT.json, OUT.glsl and "
                   "OUT_texture.exr")
        ->required();
    cli.add_option("--grid", grid_spec, "Normal grid: report5x5 | thetaphi:RxC | octa:N | disk:N")
        ->check(app::parses_with([](const std::string& g) { brdf::parse_grid(g); }, "GRID"))
        ->capture_default_str();
    cli.add_option("--sh-bands", o.sh_bands, "SH bands (max l + 1; 3 = 9 coefficients)")
        ->check(CLI::Range(1, brdf::kMaxBakeBands))
        ->capture_default_str();
    cli.add_option("--integrator", integrator,
                   "stratified-mc (the report's) | gauss-legendre | "
                   "sobol-is")
        ->check(CLI::IsMember({"stratified-mc", "gauss-legendre", "sobol-is"}))
        ->capture_default_str();
    cli.add_option("--samples", o.samples, "Integrand evaluations per normal")
        ->check(CLI::Range(1, 1 << 24))
        ->capture_default_str();
    auto* vdeg = cli.add_option("--view-deg", view_deg,
                                "View direction as THETA[,PHI] degrees "
                                "from the screen normal +z (default 0: the screen normal)")
                    ->check(app::parses_with([](const std::string& v) { brdf::parse_view_deg(v); },
                                             "THETA[,PHI]"));
    cli.add_option("--view", view_xyz,
                   "View direction x,y,z in the device frame (+z toward the "
                   "viewer)")
        ->check(app::parses_with([](const std::string& v) { brdf::parse_view(v); }, "X,Y,Z"))
        ->excludes(vdeg);
    cli.add_option("--max-error", max_error,
                   "Choose --sh-bands automatically: the fewest bands "
                   "whose SH truncation error of radiance under the test lightings is <= this "
                   "(relative); exit 3 if 8 bands do not meet it")
        ->check(app::finite_positive());
    auto* full = cli.add_flag("--validate", full_validate,
                              "Check every grid node and 256 off-grid normals "
                              "(default: at most 64 nodes and 64 normals)");
    bool no_reference = false;
    cli.add_flag("--no-reference-check", no_reference,
                 "Skip the check against a converged reference: most of a default run's time "
                 "(the run ends saying how much), but the table and report then carry no error "
                 "figures. Not with --max-error (its band choice needs the reference) or "
                 "--validate")
        ->excludes(full);
    gles::ExportArgs gles_args;
    gles::add_export_options(cli, gles_args);
    gles::add_texture_options(cli, gles_args);
    app::setup(cli, common,
               "brdf-sh-bake --material configs/materials/satin-ggx.toml "
               "--grid thetaphi:9x32 --sh-bands 3 -o out/satin --report run.json");
    if (auto code = app::parse(cli, argc, argv)) return *code;

    return app::run("brdf-sh-bake", cli, common, argc, argv, [&](Report& report) {
        fs::check_output_stem(output, "-o");
        if (no_reference && max_error > 0) {
            throw UsageError("--no-reference-check: --max-error chooses the bands from the "
                             "reference's truncation errors; give --sh-bands instead");
        }
        report.add_input(material_path);
        for (const char* suffix : {".bin", ".json", ".glsl", "_texture.exr"})
            fs::declare_output(output + suffix, "-o");
        gles::ExportSet gles_set;
        const bool textured = !gles_args.albedo_texture.empty() ||
                              !gles_args.normal_texture.empty() || gles_args.tile_size_m > 0;
        if (textured && gles_args.dir.empty()) {
            throw UsageError("--gles-albedo-texture, --gles-normal-texture and --gles-tile-size-m "
                             "are for the shaders: give --export-gles DIR");
        }
        if (!gles_args.dir.empty()) {
            gles_set = gles_args.prepare(report);
            if (max_error <= 0 && gles_args.max_sh_bands > o.sh_bands) {
                throw UsageError(str("--gles-max-bands ", gles_args.max_sh_bands,
                                     " exceeds the table's --sh-bands ", o.sh_bands));
            }
        }
        const brdf::Material material = brdf::load_material(material_path);
        const brdf::Grid grid = brdf::parse_grid(grid_spec);
        o.integrator = brdf::integrator_from_string(integrator);
        o.seed = common.seed;
        if (!view_xyz.empty()) o.view = brdf::parse_view(view_xyz);
        if (!view_deg.empty()) o.view = brdf::parse_view_deg(view_deg);
        gles::MaterialInputs gles_in;
        gles_in.name = std::filesystem::path(output).filename().string();
        gles_in.brdf = material;
        gles_args.add_textures(gles_in, report);
        const bool lambert = material.specular == brdf::Model::kLambert;  // no specular term
        if (!gles_args.dir.empty() && max_error <= 0) {
            // The table's shape is known: a variant that does not fit is refused before the bake.
            const brdf::Table shape = gles::table_shape(material, grid, o.sh_bands);
            gles::check_before_work(
                [&] { gles::export_material(lambert ? nullptr : &shape, gles_in, gles_set); });
        }
        brdf::ValidateOptions vopt;
        vopt.reference_rel_tol = brdf::reference_rel_tol_for(o);
        if (full_validate) {
            vopt.max_nodes = 0;
            vopt.test_normals = 256;
        }
        double reference_s = 0;
        const brdf::ReferenceSet ref = [&] {
            if (no_reference) return brdf::ReferenceSet{};
            ScopedStage stage(report, "reference");
            brdf::ReferenceSet r = brdf::make_reference(material, grid, o.view, vopt);
            reference_s = stage.elapsed_s();
            return r;
        }();
        const std::vector<double> by_bands =
            no_reference ? std::vector<double>{} : brdf::truncation_by_bands(ref);
        int chosen = 0;
        if (max_error > 0) {
            chosen = brdf::choose_bands(by_bands, max_error);
            o.sh_bands = chosen > 0 ? chosen : brdf::kMaxBakeBands;
            log::info(str("--max-error ", max_error, ": ", log::count(o.sh_bands, "band"), " (truncation error ",
                          by_bands[o.sh_bands - 1], ")"));
        }
        brdf::Table table;
        double bake_s = 0;
        {
            ScopedStage stage(report, "bake");
            table = brdf::bake(material, grid, o);
            bake_s = stage.elapsed_s();
        }
        const std::optional<brdf::Validation> v = [&]() -> std::optional<brdf::Validation> {
            if (no_reference) return std::nullopt;
            ScopedStage stage(report, "validate");
            return brdf::validate(ref, table);
        }();
        const nlohmann::json errors = v ? v->to_json() : nlohmann::json(nullptr);
        // What ships (the table's JSON) holds no time and no path of this machine, so the same
        // inputs give the same bytes: the times go to the report's metrics only.
        nlohmann::json shipped_errors = errors;
        if (v) shipped_errors.erase("validate_time_s");
        nlohmann::json meta = {
            {"tool", "brdf-sh-bake"},
            {"version", version_string()},
            {"model", brdf::to_string(material.specular)},
            {"lobe", material.specular == brdf::Model::kLambert ? "diffuse (lambert)" : "specular"},
            {"material_file", std::filesystem::path(material_path).filename().string()},
            {"material_toml", brdf::to_toml(material)},
            {"view", {o.view.x(), o.view.y(), o.view.z()}},
            {"grid", brdf::to_string(grid)},
            {"sh_bands", o.sh_bands},
            {"integrator", integrator},
            {"samples_per_normal", o.samples},
            {"seed", o.seed},
            {"error", shipped_errors}};
        brdf::write_binary(output + ".bin", table);
        brdf::write_json(output + ".json", table, meta);
        fs::write_text_atomic(output + ".glsl", brdf::glsl_lookup_source(table));
        brdf::write_texture_exr(output + "_texture.exr", table);
        report.add_output(output + ".bin", "brdf_sh_table_binary");
        report.add_output(output + ".json", "brdf_sh_table");
        report.add_output(output + ".glsl", "glsl_source");
        report.add_output(output + "_texture.exr", "brdf_sh_texture", "data");
        if (!gles_args.dir.empty()) {
            ScopedStage stage(report, "export gles");
            const auto exports = gles::export_material(lambert ? nullptr : &table, gles_in, gles_set);
            for (const auto& path : gles::write_exports(gles_args.dir, exports)) {
                report.add_output(path, "gles_export");
            }
        }
        auto& m = report.metrics();
        if (v) m = errors;
        m["reference_check"] = !no_reference;
        m["model"] = brdf::to_string(material.specular);
        m["grid"] = brdf::to_string(grid);
        m["sh_bands"] = o.sh_bands;
        m["coeff_count"] = table.coeff_count();
        m["channels"] = table.channels;
        m["table_floats"] = table.coeffs.size();
        m["integrator"] = integrator;
        m["samples_per_normal"] = o.samples;
        m["bake_time_s"] = bake_s;
        m["view"] = {o.view.x(), o.view.y(), o.view.z()};
        if (max_error > 0) {
            m["max_error"] = max_error;
            m["chosen_sh_bands"] = chosen;
        }
        if (v) {
            // Each error is the largest over the test lightings, channels and checked normals,
            // relative to the largest exact radiance under that lighting (docs/brdf.md, 5).
            const std::string tool = "brdf-sh-bake";
            log::summary(tool, "table", str(log::count(o.sh_bands, "SH band"), " on ", brdf::to_string(grid),
                                            ", baked in ", log::num(bake_s, 3), " s"));
            log::summary(tool, "integration error (bake vs converged reference, at nodes)",
                         log::num(v->integration_radiance_max_rel, 3));
            log::summary(tool, "interpolation error (the grid's, between nodes)",
                         log::num(v->interpolation_radiance_max_rel, 3));
            log::summary(tool, str("SH truncation error (", log::count(o.sh_bands, "band"), " vs the exact lobe)"),
                         log::num(v->truncation_radiance_max_rel, 3));
            log::summary(tool, "total error (the table's lookup vs the exact radiance)",
                         log::num(v->total_radiance_max_rel, 3));
            log::info(str("reference check: ", std::round(reference_s * 100) / 100, " s of this run "
                          "(--no-reference-check skips it, and these error figures)"));
        } else {
            log::info(str("bake ", bake_s, " s; no reference check (--no-reference-check): the "
                          "table's error is not measured"));
        }
        if (max_error > 0 && chosen == 0) {
            throw app::QualityGateFailed(str("8 SH bands leave a truncation error of ",
                                             by_bands.back(), " > --max-error ", max_error));
        }
    });
}
