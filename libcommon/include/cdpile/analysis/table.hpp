/// The results of the analysis tools as plain tables: a Product is named tables of named
/// columns with units, plus the parameters and results that describe them. The io layer
/// writes a Product as TSV or HDF5 and reads either back (io/products.hpp), so each tool
/// reads the previous tool's product whatever its format. No file access here.
///
/// A value that is not defined (a standard error from one sample, nu with no contact, an
/// undefined cluster size) is *missing*: NaN inside a Column, written as "NA" in TSV and
/// as a 0 flagged by a `<column>_defined` dataset in HDF5. Never NaN in a file.
#pragma once

#include "cdpile/error.hpp"

#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace cdpile::analysis {

/// Same type as io::Values (a parameter or result: integer, real or text).
using Value = std::variant<std::int64_t, double, std::string>;
using Values = std::map<std::string, Value>;

enum class ColumnKind : std::uint8_t { real, integer, text };

struct Column {
  std::string name;
  std::string unit;  ///< "" = dimensionless; "D" = mean diameters; "deg"; SI otherwise
  ColumnKind kind = ColumnKind::real;
  std::vector<double> num;        ///< real and integer columns; NaN = missing (real only)
  std::vector<std::string> text;  ///< text columns

  std::size_t size() const { return kind == ColumnKind::text ? text.size() : num.size(); }
  void add(double v) { num.push_back(v); }
  void add(std::optional<double> v);
  void add_int(std::int64_t v) { num.push_back(static_cast<double>(v)); }
  void add_text(std::string s) { text.push_back(std::move(s)); }
  bool defined(std::size_t r) const;
  std::optional<double> get(std::size_t r) const;
};

struct Table {
  std::string name;
  std::string title;           ///< one line: what a row is
  std::deque<Column> columns;  ///< a deque: references to columns stay valid as columns are added

  Column& add_column(const std::string& name, const std::string& unit,
                     ColumnKind kind = ColumnKind::real);
  const Column* find(const std::string& name) const;
  Column* find(const std::string& name);
  /// The column, or cdpile::Error "table T has no column 'C'".
  const Column& column(const std::string& name) const;
  Column& column(const std::string& name);
  /// Rows; cdpile::Error if the columns differ in length.
  std::size_t rows() const;
};

/// One cell as a row gives it: an integer, a real (empty, NaN or infinite: missing) or a
/// text. Integer columns take a real too, for a count that may be missing.
struct Cell {
  ColumnKind kind;
  std::int64_t integer = 0;
  std::optional<double> real;
  std::string text;
  Cell(std::int64_t v) : kind(ColumnKind::integer), integer(v) {}
  Cell(double v) : kind(ColumnKind::real), real(v) {}
  Cell(std::optional<double> v) : kind(ColumnKind::real), real(v) {}
  Cell(std::string v) : kind(ColumnKind::text), text(std::move(v)) {}
};

/// A column of a table made of rows of type Row: its name, unit and kind, and how a row
/// gives its value. A table is declared as one list of these, from which both its layout
/// (declare_columns) and its rows (add_row) follow: a column is one line
/// (docs/architecture.md, "A new product column").
template <class Row>
struct ColumnSpec {
  const char* name;
  const char* unit;  ///< as Column::unit
  ColumnKind kind;
  Cell (*get)(const Row&);
};

/// Adds spec's columns to t, in order; t must have none yet.
template <class Row>
void declare_columns(Table& t, std::span<const ColumnSpec<Row>> spec);

/// Appends one row to a table declared by spec: each column's cell from its getter. Columns
/// added after spec's (one per radius of a list, say) are the caller's to fill.
template <class Row>
void add_row(Table& t, std::span<const ColumnSpec<Row>> spec, const Row& row);

/// The same for a list written as an array (`const ColumnSpec<Row> frame_columns[] = {...}`);
/// declare_columns returns the table.
template <class Row, std::size_t N>
Table& declare_columns(Table& t, const ColumnSpec<Row> (&spec)[N]) {
  declare_columns(t, std::span<const ColumnSpec<Row>>(spec));
  return t;
}
template <class Row, std::size_t N>
void add_row(Table& t, const ColumnSpec<Row> (&spec)[N], const Row& row) {
  add_row(t, std::span<const ColumnSpec<Row>>(spec), row);
}

struct Product {
  std::string kind;   ///< the tool that made it: critical, localnu, correlate, clusterfit
  Values parameters;  ///< the options and definitions used
  Values results;     ///< scalar results (nu_c, beta, ...)
  std::vector<std::string> notes;  ///< definitions, one line each
  /// The results this product lacks, each with the reason (also among the notes): the
  /// tool says each on stderr (docs/cli.md, "Messages and exit codes").
  std::vector<std::string> not_computed;
  /// Records a result not computed and why: a note, and a line on stderr.
  void omit(const std::string& why) {
    notes.push_back(why);
    not_computed.push_back(why);
  }
  std::deque<Table> tables;  ///< a deque: references to tables stay valid as tables are added
  std::string source;        ///< file it was read from, for messages

  Table& add_table(const std::string& name, const std::string& title);
  const Table* find(const std::string& name) const;
  /// The table, or cdpile::Error "FILE: no table 'T' (a KIND product has: ...)".
  const Table& table(const std::string& name) const;
  std::optional<double> result(const std::string& name) const;
  std::optional<double> parameter(const std::string& name) const;
};

// ---------------------------------------------------------------------------------
// Inline so that the io layer can use tables without linking the analysis library.

inline void Column::add(std::optional<double> v) {
  num.push_back(v && std::isfinite(*v) ? *v : std::numeric_limits<double>::quiet_NaN());
}

inline bool Column::defined(std::size_t r) const {
  if (kind == ColumnKind::text) return r < text.size();
  return r < num.size() && std::isfinite(num[r]);
}

inline std::optional<double> Column::get(std::size_t r) const {
  if (kind == ColumnKind::text || !defined(r)) return std::nullopt;
  return num[r];
}

inline Column& Table::add_column(const std::string& n, const std::string& unit, ColumnKind kind) {
  if (find(n)) throw Error("table " + name + ": column '" + n + "' declared twice");
  Column c;
  c.name = n;
  c.unit = unit;
  c.kind = kind;
  columns.push_back(std::move(c));
  return columns.back();
}

inline const Column* Table::find(const std::string& n) const {
  for (const Column& c : columns)
    if (c.name == n) return &c;
  return nullptr;
}
inline Column* Table::find(const std::string& n) {
  for (Column& c : columns)
    if (c.name == n) return &c;
  return nullptr;
}

inline const Column& Table::column(const std::string& n) const {
  if (const Column* c = find(n)) return *c;
  throw Error("table '" + name + "' has no column '" + n + "'");
}
inline Column& Table::column(const std::string& n) {
  if (Column* c = find(n)) return *c;
  throw Error("table '" + name + "' has no column '" + n + "'");
}

inline std::size_t Table::rows() const {
  if (columns.empty()) return 0;
  const std::size_t n = columns.front().size();
  for (const Column& c : columns)
    if (c.size() != n)
      throw Error("table '" + name + "': column '" + c.name + "' has " + std::to_string(c.size()) +
                  " rows, '" + columns.front().name + "' has " + std::to_string(n));
  return n;
}

template <class Row>
void declare_columns(Table& t, std::span<const ColumnSpec<Row>> spec) {
  if (!t.columns.empty())
    throw std::logic_error("table " + t.name + ": declared from a list after other columns");
  for (const ColumnSpec<Row>& c : spec) t.add_column(c.name, c.unit, c.kind);
}

template <class Row>
void add_row(Table& t, std::span<const ColumnSpec<Row>> spec, const Row& row) {
  if (t.columns.size() < spec.size())
    throw std::logic_error("table " + t.name + ": a row of another list of columns");
  for (std::size_t i = 0; i < spec.size(); ++i) {
    Column& c = t.columns[i];
    // the list's order against the table's, once, at its first row (not per cell)
    if (c.size() == 0 && c.name != spec[i].name)
      throw std::logic_error("table " + t.name + ": column " + c.name + " where the list has " +
                             spec[i].name);
    Cell v = spec[i].get(row);
    if ((c.kind == ColumnKind::text) != (v.kind == ColumnKind::text))
      throw std::logic_error("table " + t.name + ": column " + c.name +
                             " given a cell of another kind");
    if (v.kind == ColumnKind::text)
      c.add_text(std::move(v.text));
    else if (v.kind == ColumnKind::integer)
      c.add_int(v.integer);
    else
      c.add(v.real);
  }
}

inline Table& Product::add_table(const std::string& name, const std::string& title) {
  if (find(name)) throw Error("product " + kind + ": table '" + name + "' made twice");
  Table t;
  t.name = name;
  t.title = title;
  tables.push_back(std::move(t));
  return tables.back();
}

inline const Table* Product::find(const std::string& name) const {
  for (const Table& t : tables)
    if (t.name == name) return &t;
  return nullptr;
}

inline const Table& Product::table(const std::string& name) const {
  if (const Table* t = find(name)) return *t;
  std::string have;
  for (const Table& t : tables) have += (have.empty() ? "" : ", ") + t.name;
  throw Error(source, "",
              "no table '" + name + "' (this " + (kind.empty() ? "" : kind + " ") +
                  "product has: " + (have.empty() ? "none" : have) + ")");
}

namespace detail {
inline std::optional<double> number(const Values& v, const std::string& name) {
  auto it = v.find(name);
  if (it == v.end()) return std::nullopt;
  if (auto* d = std::get_if<double>(&it->second)) return *d;
  if (auto* i = std::get_if<std::int64_t>(&it->second)) return static_cast<double>(*i);
  return std::nullopt;
}
}  // namespace detail

inline std::optional<double> Product::result(const std::string& name) const {
  return detail::number(results, name);
}
inline std::optional<double> Product::parameter(const std::string& name) const {
  return detail::number(parameters, name);
}

}  // namespace cdpile::analysis
