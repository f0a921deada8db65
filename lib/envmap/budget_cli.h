// envmap/budget_cli.h: envmap-project's error-budget options (CLI11), registered here so the
// tool's main.cpp only maps flags to options (docs/budget.md).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "envmap/budget.h"

namespace inlight::envmap {

/// The flags, as given.
struct BudgetArgs {
    double max_error = 0;  ///< --max-error: 0 = no budget (plain --sh-bands projection)
    std::string metric = "abs-over-mean";
    int max_lights = 3;
    int max_bands = 9;
    int fit_normals = 512;   ///< --light-fit-normals: 0 = shade the extracted regions' caps
    /// --budget-normals: Fibonacci normals (+6 axes) every candidate is scored on (not
    /// --validate-normals, which is --validate's own); docs/budget.md, "What the plain command
    /// guarantees".
    int check_normals = kDefaultBudgetNormals;
    double margin = kDefaultBudgetMargin;  ///< --budget-margin
    int holdout_normals = 0;  ///< --holdout-normals: score the choice again off its own normals
    std::string light_shading = "smooth-cap";  ///< --light-shading: cap | smooth-cap
    std::string sh_fit = "projection";         ///< --sh-fit: projection | metric
    std::string brdf_table;  ///< brdf-sh-bake .bin table (with --material)
    std::string material;    ///< the material file the table was baked from

    bool enabled() const { return max_error > 0; }
};

/// Registers --max-error, --error-metric, --max-lights, --budget-max-bands, --budget-normals,
/// --budget-margin, --holdout-normals, --light-fit-normals, --brdf-table and --material on `app`.
void add_budget_options(CLI::App& app, BudgetArgs& args);

/// BudgetOptions built from the flags (options().project is left for the caller), owning the
/// radiance check (table and material, read here; Error names the file on failure).
class BudgetSetup {
  public:
    explicit BudgetSetup(const BudgetArgs& args);
    const BudgetOptions& options() const { return m_options; }

  private:
    std::unique_ptr<RadianceCheck> m_radiance;
    BudgetOptions m_options;
};

}  // namespace inlight::envmap
