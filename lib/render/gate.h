// render/gate.h: the quality gate of `render compare` (docs/render.md "Quality gate"): warn and
// fail thresholds on each graded image's error against the path-traced truth, graded as
// OpenImageIO's idiff grades (-warn / -fail): a value above the fail threshold is a FAILURE,
// else above the warn threshold a WARNING, else a PASS; the run's verdict is its worst item's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace inlight::render {

/// Thresholds on two metrics of compare_images (image::Metrics): the mean relative error
/// (|t - r| / max(|r|, rel_floor), dimensionless) and the mean CIEDE2000 (after the compare's
/// exposure). Each is optional (unset = not graded on it); all >= 0 and finite.
struct GateThresholds {
    std::optional<double> warn_mean_rel, fail_mean_rel;
    std::optional<double> warn_de2000, fail_de2000;
    /// True when at least one threshold is set (the gate runs).
    bool any() const { return warn_mean_rel || fail_mean_rel || warn_de2000 || fail_de2000; }
};

/// Throws UsageError naming the option (`--warn-mean-rel` ... `--fail-de2000`) when a threshold
/// is NaN, infinite or negative, or a warn threshold exceeds its metric's fail threshold.
void check_gate_thresholds(const GateThresholds& t);

/// One graded image: a name for people ("cpu consistent b3", "gles es300-consistent-b3-highp")
/// and its two metrics against the truth.
struct GateItem {
    std::string name;
    double mean_rel = 0;
    double mean_de2000 = 0;
};

/// The images `render compare` grades, read from its metrics.realtime JSON (compare_realtime,
/// plus "lighting_file" and "gles" when present): what the app can show. The CPU model in both
/// modes at 3 bands ("modes"), the consistent model at each band count from 4 in the sweep
/// ("consistent_by_sh_bands"; 1 and 2 bands are below the app's 3 and only advice), the model
/// lit by the --rt-lighting file, and every GLES variant drawn; of those, only the shading modes
/// in `modes` ("consistent", "seed"; realtime.h RealtimeMode).
std::vector<GateItem> gate_items(const nlohmann::json& realtime,
                                 const std::vector<std::string>& modes);

enum class Verdict { kPass = 0, kWarning = 1, kFailure = 2 };
/// "PASS", "WARNING", "FAILURE" (idiff's words).
std::string to_string(Verdict v);

/// The verdict of every item and of the run.
struct GateResult {
    struct Graded {
        GateItem item;
        Verdict verdict = Verdict::kPass;
    };
    std::vector<Graded> items;
    Verdict overall = Verdict::kPass;
    /// The figure that decided the overall verdict: the item and metric with the largest ratio
    /// of value to the threshold of the overall verdict's level (for PASS: to the lowest
    /// threshold set for the metric), e.g. "mean Delta E 2000 1.3 of gles es300-seed-b3-highp
    /// > fail 1". Empty when there are no items.
    std::string decided_by;
};

/// Grades `items` against `t` (at least one threshold set). A metric that is not finite fails
/// when its metric has any threshold (nothing can vouch for it). Equal to a threshold passes it.
GateResult grade(const GateThresholds& t, const std::vector<GateItem>& items);

/// Report form: {"thresholds": {warn_mean_rel, fail_mean_rel, warn_de2000, fail_de2000} (null
/// when unset), "items": [{name, mean_rel, mean_de2000, verdict}], "verdict", "decided_by"}.
nlohmann::json to_json(const GateThresholds& t, const GateResult& r);

}  // namespace inlight::render
