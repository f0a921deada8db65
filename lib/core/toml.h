// core/toml.h: the one TOML reader of inlight (scene files, material files, fabric files and the
// tools' --config files). TOML v1.0 itself is parsed by toml++ (Debian's libtomlplusplus-dev);
// this layer adds what TOML does not say: typed access whose errors name the file, the line and
// the key, ranges, and unknown keys as errors.
//
// Tables, dotted keys (a.b = 1) and inline tables ({b = 1}) all become Document::tables under
// their dotted name; [[name]] arrays of tables become Document::table_arrays. Rejected with an
// error: a table or array of tables inside an [[array]] element, tables inside arrays of values,
// dates and times (nothing in inlight takes them).
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace inlight::toml {

struct Value;
using Array = std::vector<Value>;

/// One value with where it was read from (for messages; 1-based).
struct Value {
    std::variant<bool, double, std::string, Array> data;
    bool is_integer = false;  ///< a TOML integer (written without '.', 'e', inf or nan)
    int line = 0;
    int column = 0;
};

/// A table: its key/value pairs (sorted by key) and where it was declared.
struct Table {
    std::string name;  ///< "" for the root, "camera", "material.denim", "object" (per element)
    int line = 0;      ///< of the [header] (0 for the root)
    int column = 0;
    std::map<std::string, Value> values;
};

/// A parsed document: the root table, named tables by their dotted header name, and arrays of
/// tables by name (each element a Table).
struct Document {
    std::string source;  ///< file name for messages
    Table root;
    std::map<std::string, Table> tables;
    std::map<std::string, std::vector<Table>> table_arrays;
};

/// Parses TOML text; `source` names it in errors. Throws Error
/// "<source>:<line>:<column>: TOML syntax error: <what>" for anything TOML v1.0 rejects (syntax,
/// duplicate keys or tables, bad escapes, invalid UTF-8 such as a binary file), and
/// "<source>:<line>:<column>: [<table>] <key>: <what>" for the constructs listed above.
Document parse(const std::string& text, const std::string& source);
/// Reads and parses a file. Throws Error naming the file if it cannot be read.
Document parse_file(const std::string& path);

/// Typed access to one table, with errors "<source>:<line>: [<table>] <key>: <what>".
/// Every key read is remembered, so finish() can reject the ones nobody asked for (typos).
class Reader {
  public:
    /// Reads `table` of `doc`; both must outlive the Reader.
    Reader(const Document& doc, const Table& table);

    /// Whether the table has `key` (does not count as reading it).
    bool has(const std::string& key) const;
    /// The string at `key`, or `fallback` when absent; throws Error for another type.
    std::string get_string(const std::string& key, const std::string& fallback) const;
    /// The string at `key`; throws Error when it is absent or not a string.
    std::string require_string(const std::string& key) const;
    /// A finite number (integer or float), or `fallback` when absent.
    double get_double(const std::string& key, double fallback) const;
    /// An integer written without '.', 'e', inf or nan, |value| <= 2e9, or `fallback`.
    int get_int(const std::string& key, int fallback) const;
    /// true or false, or `fallback` when absent.
    bool get_bool(const std::string& key, bool fallback) const;
    /// An array of exactly n finite numbers, or (when allow_scalar) one finite number repeated
    /// n times, or `fallback` when absent.
    Eigen::VectorXd get_vector(const std::string& key, int n, const Eigen::VectorXd& fallback,
                               bool allow_scalar = false) const;

    /// Throws Error for a value outside [lo, hi], naming the key.
    void check_range(const std::string& key, double value, double lo, double hi) const;
    /// Throws Error "<source>:<line>: [<table>] unknown key '<k>' (known: a, b, ...)" for any key
    /// that was not read.
    void finish() const;
    /// "<source>:<line>: [<table>] <key>: " for errors about a value.
    std::string where(const std::string& key) const;

  private:
    const Value* find(const std::string& key) const;
    const Document& m_doc;
    const Table& m_table;
    mutable std::vector<std::string> m_read;
};

}  // namespace inlight::toml
