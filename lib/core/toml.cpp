#include "core/toml.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/fs.h"

namespace inlight::toml {
namespace {

/// A cursor over the whole text that tracks the line number.
class Parser {
  public:
    Parser(const std::string& text, const std::string& source) : m_s(text), m_source(source) {}

    Document run() {
        Document doc;
        doc.source = m_source;
        Table* current = &doc.root;
        while (true) {
            skip_blank_lines();
            if (at_end()) break;
            if (peek() == '[') {
                current = &header(doc);
            } else {
                key_value(*current);
            }
        }
        return doc;
    }

  private:
    /// Throws "<source>:<line>: <what>", or "<source>:<line>: [<table>] <key>: <what>" while a
    /// value is being read.
    [[noreturn]] void fail(const std::string& what, int line = 0) const {
        throw Error(str(m_source, ":", line > 0 ? line : m_line, ": ", m_key_context, what));
    }
    bool at_end() const { return m_pos >= m_s.size(); }
    char peek() const { return at_end() ? '\0' : m_s[m_pos]; }
    char get() {
        const char c = m_s[m_pos++];
        if (c == '\n') ++m_line;
        return c;
    }
    void skip_space() {
        while (!at_end() && (peek() == ' ' || peek() == '\t')) ++m_pos;
    }
    void skip_comment() {
        if (peek() == '#') {
            while (!at_end() && peek() != '\n') ++m_pos;
        }
    }
    /// Whitespace, comments and newlines (between statements and inside arrays).
    void skip_blank_lines() {
        while (!at_end()) {
            skip_space();
            skip_comment();
            if (peek() == '\n' || peek() == '\r') {
                get();
            } else {
                break;
            }
        }
    }
    /// After a statement: only spaces and a comment may follow before the newline.
    void end_of_line() {
        skip_space();
        skip_comment();
        if (peek() == '\r') ++m_pos;
        if (at_end()) return;
        if (peek() != '\n') fail(str("unexpected '", peek(), "' after the value"));
        get();
    }

    std::string key() {
        skip_space();
        if (peek() == '"' || peek() == '\'') return string_value();
        std::string k;
        while (!at_end() && (std::isalnum(static_cast<unsigned char>(peek())) || peek() == '_' ||
                             peek() == '-')) {
            k += get();
        }
        if (k.empty()) fail(str("expected a key, got '", peek(), "'"));
        return k;
    }

    Table& header(Document& doc) {
        get();  // '['
        const bool array = peek() == '[';
        if (array) get();
        std::string name;
        while (true) {
            name += key();
            skip_space();
            if (peek() == '.') {
                get();
                name += '.';
                continue;
            }
            break;
        }
        if (peek() != ']') fail(str("expected ']' to close [", name));
        get();
        if (array) {
            if (peek() != ']') fail(str("expected ']]' to close [[", name));
            get();
        }
        const int line = m_line;
        end_of_line();
        if (array) {
            if (doc.tables.count(name)) {
                fail(str("[[", name, "]] was already declared as [", name, "]"), line);
            }
            auto& list = doc.table_arrays[name];
            list.push_back(Table{name, line, {}});
            return list.back();
        }
        if (doc.table_arrays.count(name)) {
            fail(str("[", name, "] was already declared as [[", name, "]]"), line);
        }
        auto [it, inserted] = doc.tables.emplace(name, Table{name, line, {}});
        if (!inserted) fail(str("duplicate table [", name, "]"), line);
        return it->second;
    }

    void key_value(Table& table) {
        const int line = m_line;
        const std::string k = key();
        skip_space();
        if (peek() == '.') fail(str("dotted key '", k, ".' is not supported; use a [table]"));
        if (peek() != '=') fail(str("expected '=' after key '", k, "'"));
        get();
        skip_space();
        m_key_context = str(table.name.empty() ? "" : str("[", table.name, "] "), k, ": ");
        Value v = value();
        m_key_context.clear();
        v.line = line;
        if (table.values.count(k)) fail(str("duplicate key '", k, "'"), line);
        table.values.emplace(k, std::move(v));
        end_of_line();
    }

    std::string string_value() {
        const char quote = get();
        std::string out;
        while (true) {
            if (at_end() || peek() == '\n') fail("unterminated string");
            const char c = get();
            if (c == quote) break;
            if (c == '\\' && quote == '"') {
                if (at_end()) fail("unterminated string");
                const char e = get();
                switch (e) {
                    case '"':
                        out += '"';
                        break;
                    case '\\':
                        out += '\\';
                        break;
                    case 'n':
                        out += '\n';
                        break;
                    case 't':
                        out += '\t';
                        break;
                    case 'r':
                        out += '\r';
                        break;
                    default:
                        fail(str("unsupported escape '\\", e, "' in a string"));
                }
            } else {
                out += c;
            }
        }
        return out;
    }

    Value value() {
        Value v;
        v.line = m_line;
        const char c = peek();
        if (c == '"' || c == '\'') {
            if (m_s.compare(m_pos, 3, std::string(3, c)) == 0)
                fail("multi-line strings are not supported");
            v.data = string_value();
        } else if (c == '[') {
            get();
            Array items;
            while (true) {
                skip_blank_lines();
                if (peek() == ']') {
                    get();
                    break;
                }
                items.push_back(value());
                skip_blank_lines();
                if (peek() == ',') {
                    get();
                } else if (peek() != ']') {
                    fail(str("expected ',' or ']' in an array, got '", peek(), "'"));
                }
            }
            v.data = std::move(items);
        } else if (c == '{') {
            fail("inline tables are not supported; use a [table]");
        } else {
            std::string word;
            while (!at_end() &&
                   (std::isalnum(static_cast<unsigned char>(peek())) || peek() == '.' ||
                    peek() == '+' || peek() == '-' || peek() == '_')) {
                word += get();
            }
            if (word.empty()) fail(str("expected a value, got '", c, "'"));
            if (word == "true" || word == "false") {
                v.data = word == "true";
            } else {
                v.data = number(word, v.is_integer);
            }
        }
        return v;
    }

    double number(std::string word, bool& is_integer) const {
        word.erase(std::remove(word.begin(), word.end(), '_'), word.end());
        std::string body = word;
        double sign = 1;
        if (!body.empty() && (body[0] == '+' || body[0] == '-')) {
            sign = body[0] == '-' ? -1 : 1;
            body = body.substr(1);
        }
        is_integer = false;
        if (body == "inf") return sign * std::numeric_limits<double>::infinity();
        if (body == "nan") return std::numeric_limits<double>::quiet_NaN();
        try {
            size_t used = 0;
            const double d = std::stod(word, &used);
            if (used != word.size()) throw std::invalid_argument("trailing");
            is_integer = word.find_first_of(".eE") == std::string::npos;
            return d;
        } catch (const std::exception&) {
            fail(str("'", word, "' is not a number, boolean or quoted string"));
        }
    }

    const std::string& m_s;
    std::string m_source;
    std::string m_key_context;  ///< "[table] key: " while a value is read, else ""
    size_t m_pos = 0;
    int m_line = 1;
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
    return Parser(text, source).run();
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
    return str(m_doc.source, ":", line, ": ", table, key, ": ");
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
