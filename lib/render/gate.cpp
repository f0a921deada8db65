#include "render/gate.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/log.h"

namespace inlight::render {

namespace {

/// One metric's thresholds with the words the console and the errors use.
struct Metric {
    const char* words;   ///< "mean relative error"
    const char* option;  ///< option suffix: "mean-rel"
    std::optional<double> warn, fail;
    double GateItem::*value;
};

std::vector<Metric> metrics(const GateThresholds& t) {
    return {{"mean relative error", "mean-rel", t.warn_mean_rel, t.fail_mean_rel, &GateItem::mean_rel},
            {"mean Delta E 2000", "de2000", t.warn_de2000, t.fail_de2000, &GateItem::mean_de2000}};
}

Verdict level(const Metric& m, double v) {
    // A metric that is not a number (an image that is not finite) fails any threshold.
    if ((m.warn || m.fail) && !std::isfinite(v)) return Verdict::kFailure;
    if (m.fail && !(v <= *m.fail)) return Verdict::kFailure;
    if (m.warn && !(v <= *m.warn)) return Verdict::kWarning;
    return Verdict::kPass;
}

nlohmann::json optional_json(const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json();
}

}  // namespace

void check_gate_thresholds(const GateThresholds& t) {
    for (const Metric& m : metrics(t)) {
        for (const auto& [kind, v] : {std::pair{"warn", m.warn}, {"fail", m.fail}}) {
            if (v && !(std::isfinite(*v) && *v >= 0)) {
                throw UsageError(str("--", kind, "-", m.option, " ", *v,
                                     ": must be a finite number >= 0 (the ", m.words, ")"));
            }
        }
        if (m.warn && m.fail && *m.warn > *m.fail) {
            throw UsageError(str("--warn-", m.option, " ", *m.warn, " exceeds --fail-", m.option,
                                 " ", *m.fail, ": the warning threshold must not be above the "
                                 "failure threshold"));
        }
    }
}

std::vector<GateItem> gate_items(const nlohmann::json& realtime,
                                 const std::vector<std::string>& modes) {
    std::vector<GateItem> out;
    auto add = [&](const std::string& mode, const std::string& name, const nlohmann::json& m) {
        if (std::find(modes.begin(), modes.end(), mode) == modes.end()) return;
        auto num = [](const nlohmann::json& v) {  // null (not finite) reads as NaN: it fails
            return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
        };
        out.push_back({name, num(m.value("mean_rel", nlohmann::json())),
                       num(m.value("mean_de2000", nlohmann::json()))});
    };
    if (realtime.contains("modes")) {
        for (const auto& [mode, m] : realtime["modes"].items()) add(mode, str("cpu ", mode, " b3"), m);
    }
    if (realtime.contains("consistent_by_sh_bands")) {
        for (const auto& m : realtime["consistent_by_sh_bands"]) {
            const int bands = m["sh_bands"].get<int>();
            if (bands > 3) add("consistent", str("cpu consistent b", bands), m);
        }
    }
    if (realtime.contains("lighting_file")) {
        const auto& f = realtime["lighting_file"];
        add("consistent", str("cpu consistent b", f["sh_bands"].get<int>(), " + lights (--rt-lighting)"),
            f["with_lights"]);
    }
    if (realtime.contains("gles") && realtime["gles"].contains("variants")) {
        for (const auto& v : realtime["gles"]["variants"])
            add(v["mode"].get<std::string>(), str("gles ", v["variant"].get<std::string>()), v);
    }
    return out;
}

std::string to_string(Verdict v) {
    switch (v) {
        case Verdict::kPass: return "PASS";
        case Verdict::kWarning: return "WARNING";
        case Verdict::kFailure: return "FAILURE";
    }
    return "?";
}

GateResult grade(const GateThresholds& t, const std::vector<GateItem>& items) {
    GateResult r;
    const std::vector<Metric> ms = metrics(t);
    for (const GateItem& item : items) {
        Verdict v = Verdict::kPass;
        for (const Metric& m : ms) v = std::max(v, level(m, item.*m.value));
        r.items.push_back({item, v});
        r.overall = std::max(r.overall, v);
    }
    // The deciding figure: at the overall level, the largest value over its threshold.
    double best = -1;
    for (const GateResult::Graded& g : r.items) {
        for (const Metric& m : ms) {
            const double v = g.item.*m.value;
            if (level(m, v) != r.overall) continue;
            std::optional<double> th;
            const char* kind = "fail";
            if (r.overall == Verdict::kFailure) {
                th = m.fail;
            } else if (r.overall == Verdict::kWarning) {
                th = m.warn, kind = "warn";
            } else if (m.warn) {
                th = m.warn, kind = "warn";
            } else {
                th = m.fail;
            }
            if (r.overall == Verdict::kFailure && !th) th = m.warn, kind = "warn";  // not finite
            if (!th) continue;
            const double inf = std::numeric_limits<double>::infinity();
            const double ratio = !std::isfinite(v) ? inf : *th > 0 ? v / *th : (v > 0 ? inf : 0);
            if (ratio <= best) continue;
            best = ratio;
            r.decided_by = str(m.words, " ", log::num(v), " of ", g.item.name,
                               r.overall == Verdict::kPass ? " <= " : " > ", kind, " ",
                               log::num(*th));
        }
    }
    return r;
}

nlohmann::json to_json(const GateThresholds& t, const GateResult& r) {
    nlohmann::json items = nlohmann::json::array();
    auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    for (const GateResult::Graded& g : r.items) {
        items.push_back({{"name", g.item.name},
                         {"mean_rel", finite(g.item.mean_rel)},
                         {"mean_de2000", finite(g.item.mean_de2000)},
                         {"verdict", to_string(g.verdict)}});
    }
    return {{"thresholds",
             {{"warn_mean_rel", optional_json(t.warn_mean_rel)},
              {"fail_mean_rel", optional_json(t.fail_mean_rel)},
              {"warn_de2000", optional_json(t.warn_de2000)},
              {"fail_de2000", optional_json(t.fail_de2000)}}},
            {"items", items},
            {"verdict", to_string(r.overall)},
            {"decided_by", r.decided_by}};
}

}  // namespace inlight::render
