#include "core/toml.h"

#include <algorithm>
#include <cmath>
#include <string_view>

// toml++ 3.3 asserts, with TOML_ASSERT_ASSUME, conditions on the input that its parser then
// handles: "[`x`]" (a table header whose key starts with a character no key may start with)
// fails `assert` in a build without NDEBUG (the fuzz build: fuzz/regressions/toml) and becomes
// __builtin_assume(false), undefined behaviour, in a clang build with NDEBUG. Included with
// NDEBUG undefined and TOML_ASSERT empty, the assumption is neither checked nor assumed, in
// every build; the parser's own error for such input stays ("expected bare key starting
// character or string delimiter").
#pragma push_macro("NDEBUG")
#undef NDEBUG
#define TOML_ASSERT(expr) static_cast<void>(0)
#include <toml++/toml.h>
#pragma pop_macro("NDEBUG")

#include "core/check.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::toml {
namespace {

/// Converts toml++'s tree into the Document the project's readers use: TOML itself (syntax,
/// duplicate keys and tables, escapes, numbers) is toml++'s job; this only flattens tables into
/// dotted names and keeps each value's line and column for messages.
class Converter {
  public:
    explicit Converter(Document& doc) : m_doc(doc) {}

    /// Adds the key/values of `in` to `out` and every sub-table of `in` to the document, under
    /// `prefix` + key. `in_array` names the [[array]] element being read, if any.
    void table(const ::toml::table& in, Table& out, const std::string& prefix,
               const std::string& in_array) {
        for (const auto& [key, node] : in) {
            const std::string name = prefix + std::string(key.str());
            if (const auto* t = node.as_table()) {
                if (!in_array.empty()) {
                    fail(node, str("[", in_array, "] ", key.str(), ": a table inside [[", in_array,
                                   "]] is not supported"));
                }
                sub_table(*t, name);
            } else if (const auto* a = node.as_array(); a && !a->empty() && a->is_array_of_tables()) {
                if (!in_array.empty()) {
                    fail(node, str("[", in_array, "] ", key.str(), ": an array of tables inside [[",
                                   in_array, "]] is not supported"));
                }
                if (m_doc.tables.count(name)) fail(node, str("[[", name, "]] is also a [", name, "]"));
                auto& list = m_doc.table_arrays[name];
                for (const auto& element : *a) {
                    const auto& et = *element.as_table();
                    list.push_back(Table{name, line_of(et), column_of(et), {}});
                    table(et, list.back(), name + ".", name);
                }
            } else {
                out.values.emplace(std::string(key.str()), value(node, out.name, key.str()));
            }
        }
    }

  private:
    /// A [table] (or dotted key / inline table): listed under its dotted name when it holds
    /// values or nothing at all; a table holding only tables (such as the implicit [material]
    /// of [material.denim]) is not listed itself.
    void sub_table(const ::toml::table& t, const std::string& name) {
        const bool only_tables =
            !t.empty() && std::all_of(t.begin(), t.end(), [](const auto& kv) {
                return kv.second.is_table() || kv.second.is_array_of_tables();
            });
        if (only_tables) {
            Table ignored{name, 0, 0, {}};
            table(t, ignored, name + ".", "");
            return;
        }
        auto [it, inserted] = m_doc.tables.emplace(name, Table{name, line_of(t), column_of(t), {}});
        INLIGHT_CHECK(inserted) << "toml++ gave table " << name << " twice";
        table(t, it->second, name + ".", "");
    }

    Value value(const ::toml::node& node, const std::string& table_name, std::string_view key) {
        Value v;
        v.line = line_of(node);
        v.column = column_of(node);
        switch (node.type()) {
            case ::toml::node_type::boolean:
                v.data = node.as_boolean()->get();
                break;
            case ::toml::node_type::integer:
                v.data = static_cast<double>(node.as_integer()->get());
                v.is_integer = true;
                break;
            case ::toml::node_type::floating_point:
                v.data = node.as_floating_point()->get();
                break;
            case ::toml::node_type::string:
                v.data = node.as_string()->get();
                break;
            case ::toml::node_type::array: {
                Array items;
                for (const auto& element : *node.as_array()) {
                    if (element.is_table()) {
                        fail(element, str(where(table_name, key), "tables inside an array of "
                                                                  "values are not supported"));
                    }
                    items.push_back(value(element, table_name, key));
                }
                v.data = std::move(items);
                break;
            }
            default:  // dates and times
                fail(node, str(where(table_name, key), "dates and times are not used by inlight"));
        }
        return v;
    }

    static std::string where(const std::string& table_name, std::string_view key) {
        return str(table_name.empty() ? "" : str("[", table_name, "] "), key, ": ");
    }
    static int line_of(const ::toml::node& n) { return static_cast<int>(n.source().begin.line); }
    static int column_of(const ::toml::node& n) {
        return static_cast<int>(n.source().begin.column);
    }
    [[noreturn]] void fail(const ::toml::node& n, const std::string& what) const {
        throw Error(str(m_doc.source, ":", line_of(n), ":", column_of(n), ": ", what));
    }

    Document& m_doc;
};

std::string type_name(const Value& v) {
    switch (v.data.index()) {
        case 0:
            return "a boolean";
        case 1:
            return "a number";
        case 2:
            return "a string";
        default:
            return "an array";
    }
}

}  // namespace

Document parse(const std::string& text, const std::string& source) {
    if (const size_t nul = text.find('\0'); nul != std::string::npos) {
        const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(nul), '\n');
        throw Error(str(source, ":", line, ": binary data (a NUL byte): not a TOML text file"));
    }
    ::toml::table parsed;
    try {
        parsed = ::toml::parse(text, source);
    } catch (const ::toml::parse_error& e) {
        const auto& at = e.source().begin;
        const std::string what(e.description());
        const bool binary = what.find("utf-8") != std::string::npos;
        throw Error(str(source, ":", at.line, ":", at.column, ": TOML syntax error: ", what,
                        binary ? " (a binary file, not TOML text?)" : ""));
    }
    Document doc;
    doc.source = source;
    Converter(doc).table(parsed, doc.root, "", "");
    return doc;
}
Document parse_file(const std::string& path) { return parse(fs::read_file(path), path); }

Reader::Reader(const Document& doc, const Table& table) : m_doc(doc), m_table(table) {}

const Value* Reader::find(const std::string& key) const {
    m_read.push_back(key);
    const auto it = m_table.values.find(key);
    return it == m_table.values.end() ? nullptr : &it->second;
}

bool Reader::has(const std::string& key) const { return m_table.values.count(key) > 0; }

std::string Reader::where(const std::string& key) const {
    const auto it = m_table.values.find(key);
    const int line = it == m_table.values.end() ? m_table.line : it->second.line;
    const std::string table = m_table.name.empty() ? "" : str("[", m_table.name, "] ");
    // The root table has no line: then the file alone is named.
    return str(m_doc.source, line > 0 ? str(":", line) : "", ": ", table, key, ": ");
}

std::string Reader::get_string(const std::string& key, const std::string& fallback) const {
    const Value* v = find(key);
    if (!v) return fallback;
    if (const auto* s = std::get_if<std::string>(&v->data)) return *s;
    throw Error(str(where(key), "expected a string, got ", type_name(*v)));
}

std::string Reader::require_string(const std::string& key) const {
    if (!has(key)) throw Error(str(where(key), "required key is missing"));
    return get_string(key, "");
}

double Reader::get_double(const std::string& key, double fallback) const {
    const Value* v = find(key);
    if (!v) return fallback;
    if (const auto* d = std::get_if<double>(&v->data)) {
        if (!std::isfinite(*d)) throw Error(str(where(key), "expected a finite number"));
        return *d;
    }
    throw Error(str(where(key), "expected a number, got ", type_name(*v)));
}

int Reader::get_int(const std::string& key, int fallback) const {
    const Value* v = find(key);
    if (!v) return fallback;
    const auto* d = std::get_if<double>(&v->data);
    if (!d || !v->is_integer || std::abs(*d) > 2e9) {
        throw Error(str(where(key), "expected an integer, got ", d ? str(*d) : type_name(*v)));
    }
    return static_cast<int>(*d);
}

bool Reader::get_bool(const std::string& key, bool fallback) const {
    const Value* v = find(key);
    if (!v) return fallback;
    if (const auto* b = std::get_if<bool>(&v->data)) return *b;
    throw Error(str(where(key), "expected true or false, got ", type_name(*v)));
}

Eigen::VectorXd Reader::get_vector(const std::string& key, int n, const Eigen::VectorXd& fallback,
                                   bool allow_scalar) const {
    const Value* v = find(key);
    if (!v) return fallback;
    if (const auto* d = std::get_if<double>(&v->data); d && allow_scalar) {
        if (!std::isfinite(*d)) throw Error(str(where(key), "expected finite numbers"));
        return Eigen::VectorXd::Constant(n, *d);
    }
    const auto* a = std::get_if<Array>(&v->data);
    if (!a || static_cast<int>(a->size()) != n) {
        throw Error(str(where(key), "expected an array of ", n, " numbers",
                        allow_scalar ? " (or one number)" : "", ", got ",
                        a ? str(a->size(), " values") : type_name(*v)));
    }
    Eigen::VectorXd out(n);
    for (int i = 0; i < n; ++i) {
        const auto* d = std::get_if<double>(&(*a)[static_cast<size_t>(i)].data);
        if (!d || !std::isfinite(*d)) {
            throw Error(str(where(key), "element ", i, " is not a finite number"));
        }
        out[i] = *d;
    }
    return out;
}

void Reader::check_range(const std::string& key, double value, double lo, double hi) const {
    if (!(value >= lo && value <= hi)) {
        throw Error(str(where(key), value, " is outside [", lo, ", ", hi, "]"));
    }
}

void Reader::finish() const {
    for (const auto& [k, v] : m_table.values) {
        if (std::find(m_read.begin(), m_read.end(), k) == m_read.end()) {
            std::string known;
            std::vector<std::string> sorted = m_read;
            std::sort(sorted.begin(), sorted.end());
            sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
            for (const auto& r : sorted) known += (known.empty() ? "" : ", ") + r;
            const std::string table = m_table.name.empty() ? "" : str("[", m_table.name, "] ");
            throw Error(str(m_doc.source, ":", v.line, ": ", table, "unknown key '", k,
                            "' (known: ", known, ")"));
        }
    }
}

}  // namespace inlight::toml
