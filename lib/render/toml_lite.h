// render/toml_lite.h: the subset of TOML v1.0 that scene files use, with messages that name the
// file, the line and the key.
//
// Supported: comments (#), bare and "quoted" keys, [table] and [a.b] headers, [[array-of-tables]]
// headers, key = value with basic "strings" (escapes \" \\ \n \t), 'literal strings', integers,
// floats (1.5, 1e-3, inf, nan), booleans, and arrays of those values (which may span lines).
// Not supported (rejected with an error): dotted keys on the left of '=', inline tables,
// multi-line strings, dates.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace inlight::render::toml {

struct Value;
using Array = std::vector<Value>;

/// One value with the line it was read from (for messages).
struct Value {
    std::variant<bool, double, std::string, Array> data;
    bool is_integer = false;  ///< written without '.', 'e', inf or nan
    int line = 0;
};

/// A table: its key/value pairs (sorted by key) and where it was declared.
struct Table {
    std::string name;  ///< "" for the root, "camera", "material.denim", "object" (per element)
    int line = 0;
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

/// Parses TOML text; `source` names it in errors. Throws Error "<source>:<line>: <what>" on a
/// syntax error, a duplicate key or a duplicate [table].
Document parse(const std::string& text, const std::string& source);
/// Reads and parses a file. Throws Error naming the file if it cannot be read.
Document parse_file(const std::string& path);

/// Typed access to one table, with errors "<source>:<line>: [<table>] <key>: <what>".
/// Every key read is remembered, so finish() can reject the ones nobody asked for (typos).
class Reader {
  public:
    Reader(const Document& doc, const Table& table);

    bool has(const std::string& key) const;
    std::string get_string(const std::string& key, const std::string& fallback) const;
    std::string require_string(const std::string& key) const;
    double get_double(const std::string& key, double fallback) const;
    int get_int(const std::string& key, int fallback) const;
    bool get_bool(const std::string& key, bool fallback) const;
    /// An array of exactly n numbers, or (when allow_scalar) one number repeated n times.
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

}  // namespace inlight::render::toml
