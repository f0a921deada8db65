// Material files: flat TOML read with core/toml.h, so that each error names the file, the line
// and the key.
#include <iomanip>
#include <sstream>

#include "brdf/brdf.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/toml.h"

namespace inlight::brdf {
namespace {

/// A material file is flat: throws Error "<file>:<line>: tables ([name]) are not supported..."
/// naming the first [table] or [[array]] header of `doc`, if it has any.
void reject_tables(const toml::Document& doc) {
    const toml::Table* first = nullptr;
    std::string header;
    for (const auto& [name, table] : doc.tables) {
        if (!first || table.line < first->line) {
            first = &table;
            header = str("[", name, "]");
        }
    }
    for (const auto& [name, list] : doc.table_arrays) {
        if (!first || list.front().line < first->line) {
            first = &list.front();
            header = str("[[", name, "]]");
        }
    }
    if (first) {
        throw Error(str(doc.source, ":", first->line, ": tables (", header,
                        ") are not supported in material files: use flat keys"));
    }
}

}  // namespace

void read_material_keys(const toml::Reader& r, Material& m) {
    if (r.has("specular")) {
        const std::string name = r.get_string("specular", "");  // its own errors name the key
        try {
            m.specular = model_from_string(name);
        } catch (const Error& e) {  // rethrown as Error: a bad file is a runtime error (exit 1)
            throw Error(str(r.where("specular"), e.what()));
        }
    }
    auto colour = [&r](const std::string& key, Eigen::Vector3d& c) {
        c = r.get_vector(key, 3, c, /*allow_scalar=*/true);
        for (int i = 0; i < 3; ++i) r.check_range(key, c[i], 0, 1);
    };
    colour("albedo", m.albedo);
    colour("f0", m.f0);
    colour("sheen_color", m.sheen_color);
    m.alpha = r.get_double("alpha", m.alpha);
    r.check_range("alpha", m.alpha, 0, 1);
    m.report_f = r.get_double("report_f", m.report_f);
    r.check_range("report_f", m.report_f, 0, 1);
    m.report_r = r.get_double("report_r", m.report_r);
    if (!(m.report_r > 0)) throw Error(str(r.where("report_r"), m.report_r, " is not > 0"));
    r.check_range("report_r", m.report_r, 0, 100);
    m.specular_scale = r.get_double("specular_scale", m.specular_scale);
    r.check_range("specular_scale", m.specular_scale, 0, 1e6);
}

void require_specular(const toml::Reader& r) {
    if (!r.has("specular")) {
        throw Error(str(r.where("specular"), "required key is missing: name the lobe (specular = "
                                             "\"ggx\", \"cook-torrance-report\", \"charlie\" or "
                                             "\"lambert\")"));
    }
}

Material parse_material(const std::string& text, const std::string& name) {
    const toml::Document doc = toml::parse(text, name);
    reject_tables(doc);
    const toml::Reader r(doc, doc.root);
    Material m;
    read_material_keys(r, m);
    r.get_string("name", "");  // name, description: documentation only
    r.get_string("description", "");
    r.finish();
    require_specular(r);
    return m;
}

Material load_material(const std::string& toml_path) {
    std::string text;
    try {
        text = fs::read_file(toml_path);
    } catch (const Error&) {
        throw Error(str(toml_path, ": cannot read material file"));
    }
    return parse_material(text, toml_path);
}

std::string to_toml(const Material& m) {
    std::ostringstream os;
    os << std::setprecision(17);
    auto rgb = [&](const Eigen::Vector3d& c) {
        os << "[" << c[0] << ", " << c[1] << ", " << c[2] << "]\n";
    };
    os << "specular = \"" << to_string(m.specular) << "\"\n";
    os << "albedo = ";
    rgb(m.albedo);
    os << "f0 = ";
    rgb(m.f0);
    os << "alpha = " << m.alpha << "\n";
    os << "report_f = " << m.report_f << "\n";
    os << "report_r = " << m.report_r << "\n";
    os << "sheen_color = ";
    rgb(m.sheen_color);
    os << "specular_scale = " << m.specular_scale << "\n";
    return os.str();
}

}  // namespace inlight::brdf
