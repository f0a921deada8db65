// Material files: a flat TOML subset (key = number | "string" | [n, n, n]; # comments), parsed
// here so that each error can name the file, the line and the key.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "brdf/brdf.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::brdf {
namespace {

struct Value {
    int line = 0;
    bool is_string = false;
    std::string text;             // string value
    std::vector<double> numbers;  // one number, or an array
    bool is_array = false;
};

std::string trim(const std::string& s) {
    size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
    return s.substr(b, e - b);
}

// Removes a # comment that is not inside a string.
std::string strip_comment(const std::string& s) {
    bool in_string = false;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '"' && (i == 0 || s[i - 1] != '\\')) in_string = !in_string;
        if (s[i] == '#' && !in_string) return s.substr(0, i);
    }
    return s;
}

bool parse_number(const std::string& token, double& out) {
    std::string t = trim(token);
    std::string clean;
    for (char c : t) {
        if (c != '_') clean += c;
    }
    if (clean.empty()) return false;
    char* end = nullptr;
    out = std::strtod(clean.c_str(), &end);
    return end == clean.c_str() + clean.size() && std::isfinite(out);
}

std::map<std::string, Value> parse_flat_toml(const std::string& text, const std::string& name) {
    std::map<std::string, Value> out;
    std::istringstream in(text);
    std::string raw;
    int line_no = 0;
    while (std::getline(in, raw)) {
        ++line_no;
        const std::string line = trim(strip_comment(raw));
        if (line.empty()) continue;
        const std::string where = str(name, ":", line_no, ": ");
        if (line[0] == '[') {
            throw Error(str(where, "tables ('", line, "') are not supported: use flat keys"));
        }
        const size_t eq = line.find('=');
        if (eq == std::string::npos) throw Error(str(where, "expected 'key = value'"));
        const std::string key = trim(line.substr(0, eq));
        const std::string rhs = trim(line.substr(eq + 1));
        if (key.empty()) throw Error(str(where, "missing key before '='"));
        if (out.count(key)) throw Error(str(where, key, ": duplicate key"));
        Value v;
        v.line = line_no;
        if (rhs.empty()) throw Error(str(where, key, ": missing value"));
        if (rhs.front() == '"') {
            if (rhs.size() < 2 || rhs.back() != '"') {
                throw Error(str(where, key, ": unterminated string"));
            }
            v.is_string = true;
            v.text = rhs.substr(1, rhs.size() - 2);
        } else if (rhs.front() == '[') {
            if (rhs.back() != ']') throw Error(str(where, key, ": unterminated array"));
            v.is_array = true;
            std::stringstream items(rhs.substr(1, rhs.size() - 2));
            std::string item;
            while (std::getline(items, item, ',')) {
                if (trim(item).empty()) continue;  // trailing comma
                double d;
                if (!parse_number(item, d)) {
                    throw Error(str(where, key, ": '", trim(item), "' is not a number"));
                }
                v.numbers.push_back(d);
            }
        } else {
            double d;
            if (!parse_number(rhs, d)) {
                throw Error(str(where, key, ": '", rhs, "' is not a number, string or array"));
            }
            v.numbers.push_back(d);
        }
        out[key] = v;
    }
    return out;
}

}  // namespace

Material parse_material(const std::string& text, const std::string& name) {
    const auto values = parse_flat_toml(text, name);
    static const std::set<std::string> kKeys = {
        "specular", "albedo",         "f0",   "sheen_color", "alpha", "report_f",
        "report_r", "specular_scale", "name", "description"};
    Material m;
    for (const auto& [key, v] : values) {
        const std::string where = str(name, ":", v.line, ": ", key, ": ");
        if (!kKeys.count(key)) {
            throw Error(str(where,
                            "unknown key (expected one of specular, albedo, f0, "
                            "sheen_color, alpha, report_f, report_r, specular_scale, "
                            "name, description)"));
        }
        auto want_string = [&]() -> const std::string& {
            if (!v.is_string) throw Error(str(where, "expected a string"));
            return v.text;
        };
        auto number = [&](double lo, double hi, bool lo_open) {
            if (v.is_string || v.is_array) throw Error(str(where, "expected a number"));
            const double d = v.numbers[0];
            if (d < lo || d > hi || (lo_open && d == lo)) {
                throw Error(
                    str(where, d, " out of range ", lo_open ? "(" : "[", lo, ", ", hi, "]"));
            }
            return d;
        };
        auto rgb = [&]() {
            if (v.is_string) throw Error(str(where, "expected [r, g, b] or a number"));
            if (v.is_array && v.numbers.size() != 3) {
                throw Error(str(where, "expected 3 numbers [r, g, b], got ", v.numbers.size()));
            }
            Eigen::Vector3d c = v.is_array
                                    ? Eigen::Vector3d(v.numbers[0], v.numbers[1], v.numbers[2])
                                    : Eigen::Vector3d::Constant(v.numbers[0]);
            if (c.minCoeff() < 0 || c.maxCoeff() > 1) {
                throw Error(str(where, "each channel must lie in [0, 1]"));
            }
            return c;
        };
        if (key == "specular") {
            try {
                m.specular = model_from_string(want_string());
            } catch (const UsageError& e) {
                throw Error(str(where, e.what()));
            }
        } else if (key == "albedo") {
            m.albedo = rgb();
        } else if (key == "f0") {
            m.f0 = rgb();
        } else if (key == "sheen_color") {
            m.sheen_color = rgb();
        } else if (key == "alpha") {
            m.alpha = number(0, 1, false);
        } else if (key == "report_f") {
            m.report_f = number(0, 1, false);
        } else if (key == "report_r") {
            m.report_r = number(0, 100, true);
        } else if (key == "specular_scale") {
            m.specular_scale = number(0, 1e6, false);
        } else {
            want_string();  // name, description: documentation only
        }
    }
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
