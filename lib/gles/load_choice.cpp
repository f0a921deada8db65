// gles/load_choice.cpp: which exported variant an app loads for each GL capability (index.json's
// "load", export.h load_choices(); btf-gles.json's "load", btf_export.h btf_load_choices()).
#include <algorithm>
#include <map>

#include "core/error.h"
#include "gles/btf_draw.h"
#include "gles/btf_export.h"
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

nlohmann::json btf_load_choices(const BtfGlesExport& e) {
    const BtfGlesVariant *es3 = nullptr, *es1 = nullptr;
    for (const BtfGlesVariant& v : e.variants) (v.version == GlslVersion::kEs300 ? es3 : es1) = &v;
    const int max_c = e.components.empty() ? 0 : *std::max_element(e.components.begin(), e.components.end());
    const char* validated = "; highp: drawn through EGL equal to the CPU decoder within one 8-bit code "
                            "(docs/btf-gles.md, \"Tests\")";
    // Both variants read every slab (9 S + 1 fragment uniform vectors): ES 3.0 guarantees 224,
    // which the export enforces; ES 2.0 guarantees 16, one slab, and a device reports its own.
    const int es2_guaranteed = Limits::minimum(GlslVersion::kEs100).max_fragment_uniform_vectors;
    const int es1_vectors = es1 ? es1->fragment_uniform_vectors : 0;
    int guaranteed_slabs = 0;
    while (btf_fragment_uniform_vectors(guaranteed_slabs + 1) <= es2_guaranteed) ++guaranteed_slabs;
    auto entry = [&](const std::string& capability, const BtfGlesVariant* v, const std::string& why) {
        nlohmann::json c = {{"capability", capability}};
        if (!v) {
            c["variant"] = nullptr;
            c["why"] = why;
            return c;
        }
        c["variant"] = v->name;
        c["manifest"] = "btf-gles.json";
        c["validated"] = true;
        c["why"] = why + validated;
        return c;
    };
    const std::string every = str("all ", e.slabs, " slab(s): the mean and every component (at most ", max_c,
                                  " per group)");
    nlohmann::json out = nlohmann::json::array();
    if (es3) {
        out.push_back(entry("OpenGL ES 3.0 or later", es3, "GLSL ES 3.00: exact texel fetches, " + every));
    } else {
        out.push_back(entry("OpenGL ES 3.0 or later", es1,
                            es1 ? str("btf-es300-highp was not exported: the ES 1.00 variant runs on ES 3.0 (", es1_vectors,
                                          " fragment uniform vectors, within its ",
                                          Limits::minimum(GlslVersion::kEs300).max_fragment_uniform_vectors, "), ", every)
                                : std::string("no variant was exported")));
    }
    if (!es1) {
        out.push_back(entry("OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH", nullptr,
                            "btf-es100-highp was not exported (--gles-versions)"));
    } else {
        nlohmann::json c = entry("OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH", es1,
                                 str("GLSL ES 1.00: ", every, ", ", es1_vectors, " fragment uniform vectors"));
        if (es1_vectors > es2_guaranteed) {
            // Machine-readable, beside the text: the app compares it with GL_MAX_FRAGMENT_UNIFORM_VECTORS.
            c["requires"] = {{"max_fragment_uniform_vectors", es1_vectors}};
            c["why"] = str(c["why"].get<std::string>(), "; needs GL_MAX_FRAGMENT_UNIFORM_VECTORS >= ", es1_vectors,
                           " (ES 2.0 guarantees ", es2_guaranteed, "): the last entry covers a device that reports fewer");
        }
        out.push_back(c);
    }
    out.push_back(entry("OpenGL ES 2.0 without GL_FRAGMENT_PRECISION_HIGH", nullptr,
                        "mediump is refused: its 10-bit mantissa on 3 x (1 + C) decoded terms errs by more than "
                        "an 8-bit code (docs/btf-gles.md, \"Precision\"); every exported variant needs highp "
                        "fragment floats"));
    if (es1 && es1_vectors > es2_guaranteed) {
        out.push_back(entry(str("OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH and GL_MAX_FRAGMENT_UNIFORM_VECTORS < ",
                                es1_vectors),
                            nullptr,
                            str("btf-es100-highp reads ", e.slabs, " atlas slabs (", es1_vectors,
                                " fragment uniform vectors) for groups of up to ", max_c,
                                " components; no variant draws the whole stream within fewer, and none is cut "
                                "to a prefix silently (compress with at most ",
                                guaranteed_slabs * 4 - 1, " components per group for every ES 2.0 device)")));
    }
    return out;
}

}  // namespace inlight::gles
