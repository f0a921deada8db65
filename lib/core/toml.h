// core/toml.h: the one TOML reader of inlight (scene files, material files and any later config
// file): the subset of TOML v1.0 below, with messages that name the file, the line and the key.
//
// Supported: comments (#), bare and "quoted" keys, [table] and [a.b] headers, [[array-of-tables]]
// headers, key = value with basic "strings" (escapes \" \\ \n \t \r), 'literal strings', integers,
// floats (1.5, 1e-3, inf, nan), booleans, and arrays of those values (which may span lines).
// Not supported (rejected with an error): dotted keys on the left of '=', inline tables,
// multi-line strings, dates.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace inlight::toml {

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
/// syntax error, a duplicate key or a duplicate [table]; an error inside a value also names its
/// key: "<source>:<line>: [<table>] <key>: <what>" ("[<table>] " absent for root keys).
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
