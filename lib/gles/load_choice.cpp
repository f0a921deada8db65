// gles/load_choice.cpp: which exported variant an app loads for each GL capability (index.json's
// "load", export.h load_choices()).
#include <map>

#include "core/error.h"
#include "gles/export.h"

namespace inlight::gles {
namespace {

/// Higher is better for the same capability: consistent, then bands, then ES 3.00.
int rank(const Variant& v, bool prefer_es3) {
    return (v.mode == ShaderMode::kConsistent ? 1000 : 0) + 10 * v.sh_bands +
           ((v.version == GlslVersion::kEs300) == prefer_es3 ? 1 : 0);
}

nlohmann::json choose(const std::vector<const Export*>& exports, const std::string& capability,
                      bool es3_context, bool highp) {
    const Export* best = nullptr;
    for (const Export* e : exports) {
        const Variant& v = e->variant;
        if (!es3_context && v.version == GlslVersion::kEs300) continue;  // needs ES 3
        if (!highp && v.precision == Precision::kHighp) continue;  // needs highp fragments
        if (best && best->variant.precision == Precision::kHighp &&
            v.precision == Precision::kMediump) {
            continue;
        }
        const bool better_precision = best && best->variant.precision == Precision::kMediump &&
                                      v.precision == Precision::kHighp;
        if (!best || better_precision ||
            rank(v, es3_context) > rank(best->variant, es3_context)) {
            best = e;
        }
    }
    nlohmann::json c = {{"capability", capability}};
    if (!best) {
        c["variant"] = nullptr;
        c["why"] = highp ? "no exported variant runs on this context"
                         : "no exported variant is correct without highp fragment floats: the "
                           "highp variants need GL_FRAGMENT_PRECISION_HIGH and mediump variants "
                           "(exported only on request) are not validated (docs/gles.md, "
                           "'Precision')";
        return c;
    }
    const Variant& v = best->variant;
    c["variant"] = best->name;
    c["manifest"] = best->name + ".json";
    std::string why = v.mode == ShaderMode::kConsistent
                          ? str("consistent mode (the seed variant reproduces the report's slips) "
                                "at ", v.sh_bands, " bands, the most exported")
                          : "the seed mode is the only one exported";
    if (v.lights > 0) why += str(", with the lighting file's ", v.lights, " dominant light(s)");
    why += v.precision == Precision::kHighp
               ? "; highp: validated against the CPU model (docs/gles.md)"
               : "; mediump: NOT validated, the only variant without highp (docs/gles.md, "
                 "'Precision')";
    if (v.texture_filter == TextureFilter::kTrilinear && v.version == GlslVersion::kEs100) {
        why += "; trilinear: needs GL_OES_standard_derivatives (gl_limits_needed.requires)";
    }
    if (es3_context && v.version == GlslVersion::kEs300) {
        why += "; GLSL ES 3.00: float table data and exact texel fetches";
    }
    c["why"] = why;
    c["validated"] = v.precision == Precision::kHighp;
    return c;
}

}  // namespace

nlohmann::json load_choices(const std::vector<Export>& exports) {
    std::map<std::string, std::vector<const Export*>> by_material;
    for (const Export& e : exports) by_material[e.material].push_back(&e);
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [material, list] : by_material) {
        out[material] = {
            choose(list, "OpenGL ES 3.0 or later", true, true),
            choose(list, "OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH", false, true),
            choose(list, "OpenGL ES 2.0 without GL_FRAGMENT_PRECISION_HIGH", false, false)};
    }
    return out;
}

}  // namespace inlight::gles
