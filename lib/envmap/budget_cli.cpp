#include "envmap/budget_cli.h"

#include "brdf/table.h"
#include "core/error.h"
#include "core/validators.h"

namespace inlight::envmap {

void add_budget_options(CLI::App& app, BudgetArgs& a) {
    auto* max_error =
        app.add_option(
               "--max-error", a.max_error,
               "Error budget: choose the SH band count and the number of extracted dominant lights "
               "with the least shader cost whose error (--error-metric, irradiance and, with "
               "--brdf-table, outgoing radiance) is at most this; exit 3 if none is (0 = off: "
               "plain "
               "--sh-bands projection)")
            ->check(app::finite_range(0.0, 10.0));
    app.add_option("--error-metric", a.metric,
                   "Budget metric: abs-over-mean (mean |E - E_ref| / mean E_ref) or mean-rel "
                   "(mean of per-normal relative errors, inflated by dark normals)")
        ->check(CLI::IsMember({"abs-over-mean", "mean-rel"}))
        ->capture_default_str();
    app.add_option("--max-lights", a.max_lights,
                   "Budget: dominant lights (sun, window, lamp) that may be extracted and shaded "
                   "analytically (0 = pure SH)")
        ->check(CLI::Range(0, 8))
        ->capture_default_str();
    app.add_option("--budget-max-bands", a.max_bands, "Budget: largest SH band count considered")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    app.add_option("--budget-normals", a.check_normals,
                   "Budget: Fibonacci normals (+6 axes) at which every candidate's error is "
                   "measured against brute force (fisheye: within 60 deg of the axis); the "
                   "default is dense enough that the choice holds on other dense sets "
                   "(docs/budget.md)")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    app.add_option("--budget-margin", a.margin,
                   "Budget: a candidate meets --max-error E when its error on the budget's normals "
                   "is at most E (1 - this), so that it holds on normals it was not scored on "
                   "(the default is twice the largest excess measured on held-out normals: "
                   "docs/budget.md)")
        ->check(app::finite_range(0.0, 0.49))
        ->capture_default_str();
    app.add_option("--holdout-normals", a.holdout_normals,
                   "Budget: after the choice, score it again against brute force on this many "
                   "normals that it was neither scored nor fitted on (a turned Fibonacci set), "
                   "reported as budget.holdout (0 = off)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    app.add_option("--light-fit-normals", a.fit_normals,
                   "Budget: fit each candidate's lights by least squares against the brute-force "
                   "irradiance at this many normals (other than the validation normals; "
                   "full-sphere maps without clipped pixels or window); 0 = shade the extracted "
                   "regions as found")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    app.add_option("--light-shading", a.light_shading,
                   "Budget: shade each light as the exact uniform cap (cap: acos, atan, sqrt; 45 "
                   "operations) or with a quadratic across its horizon band (smooth-cap: 15)")
        ->check(CLI::IsMember({"cap", "smooth-cap"}))
        ->capture_default_str();
    app.add_option("--sh-fit", a.sh_fit,
                   "Budget: each candidate's SH coefficients (and its lights' fluxes) as the "
                   "projection of the map minus the lights, or fitted to the brute-force "
                   "irradiance at the fit normals to minimise --error-metric there (metric: "
                   "same coefficient count and shader; full-sphere maps without clipped pixels)")
        ->check(CLI::IsMember({"projection", "metric"}))
        ->capture_default_str();
    auto* table = app.add_option("--brdf-table", a.brdf_table,
                                 "Budget: a brdf-sh-bake table (.bin); the outgoing radiance "
                                 "toward its view must meet the budget too")
                      ->check(CLI::ExistingFile);
    auto* material = app.add_option("--material", a.material,
                                    "Budget: the material file the --brdf-table was baked from")
                         ->check(CLI::ExistingFile);
    table->needs(material);
    material->needs(table);
    table->needs(max_error);
}

BudgetSetup::BudgetSetup(const BudgetArgs& a) {
    m_options.max_error = a.max_error;
    m_options.metric = error_metric_from_string(a.metric);
    m_options.max_bands = a.max_bands;
    m_options.extract.max_lights = a.max_lights;
    m_options.fit_normals = a.fit_normals;
    m_options.light_shading = light_shading_from_string(a.light_shading);
    m_options.sh_fit = sh_fit_from_string(a.sh_fit);
    m_options.validate_normals = a.check_normals;
    m_options.holdout_normals = a.holdout_normals;
    m_options.scoring_margin = a.margin;
    if (!a.brdf_table.empty()) {
        m_radiance = std::make_unique<RadianceCheck>();
        m_radiance->table = brdf::read_binary(a.brdf_table);
        m_radiance->material = brdf::load_material(a.material);
        m_options.radiance = m_radiance.get();
    }
}

}  // namespace inlight::envmap
