/// Plain-text tables, and the contact table that brings other codes' data into the
/// analysis tools (docs/analysis.md, "The contact table").
///
/// A text table is: comment lines starting with '#', one header line naming the columns,
/// then one row per line. Columns are separated by tabs, or by commas when the header has
/// commas and no tab, or else by runs of spaces. Numbers are read with std::from_chars;
/// NaN and infinities are refused; "NA" is a missing value where a reader allows it.
/// Blank lines end a table; a file may hold several (the products of critical, localnu
/// and correlate do), each named by a `# table: NAME` comment.
///
/// No HDF5 here: this file is only text, so it builds and tests on its own.
#pragma once

#include "cdpile/model.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cdpile::io {

/// The marker of a missing value in text tables.
inline constexpr const char* missing_marker = "NA";

/// One parsed table: named columns, each numbers or (for declared text columns) text.
struct TextTable {
  std::string name;                   ///< from `# table: NAME`, else empty
  std::vector<std::string> comments;  ///< comment lines before the header, without '#'
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;     ///< [column][row]; a missing value is NaN
  std::vector<std::vector<std::string>> text;  ///< [column][row] for text columns, else empty
  std::vector<std::size_t> line;               ///< 1-based line of each row in the source
  std::size_t first_line = 0;                  ///< line of the header

  std::size_t rows() const { return line.size(); }
  std::optional<std::size_t> find(const std::string& column) const;
};

struct TextTableOptions {
  bool allow_missing = false;             ///< accept "NA" (read as NaN, for the caller to check)
  std::vector<std::string> text_columns;  ///< columns kept as text, not parsed as numbers
  /// When not empty: only these columns are parsed as numbers, every other column is kept
  /// as text (a reader that ignores unknown columns, whatever they hold).
  std::vector<std::string> numeric_columns;
};

/// Parses every table of a text. Errors name the file and the line and column:
/// `FILE: line L, column NAME: 'x' is not a number`.
std::vector<TextTable> parse_text_tables(const std::string& text, const std::string& file,
                                         const TextTableOptions& opt = {});

/// Parses a number the way tables do: the whole cell, finite. Empty if not a number.
std::optional<double> parse_number(const std::string& cell);

// ---------------------------------------------------------------------------------
// The contact table

/// One frame of a contact table.
struct ContactTableFrame {
  std::int64_t frame = 0;       ///< the `frame` column's value (0 without the column)
  std::optional<double> theta;  ///< tilt angle [deg] from the `theta` column, if any
  std::size_t first_line = 0;   ///< source line of the frame's first row
  Contacts contacts;            ///< points, forces, ids; normal, gap unset; status stick
                                ///< unless a `status` column gives it
};

/// What to do with a contact given twice in one frame (the same pair of ids, or without
/// ids the same contact point): LAMMPS writes a pair twice with `newton off` across
/// ranks, and concatenated dumps repeat rows.
enum class Duplicates {
  error,  ///< refuse the table, naming both lines
  merge,  ///< keep the first row, count the contact once (the rows must agree on the forces)
};

struct ContactTableOptions {
  Duplicates duplicates = Duplicates::error;
};

/// A contact table read from text. Columns (names are case-sensitive):
///   x, y     contact point                          required
///   fn, ft   normal and tangential force            required; ft signed or |f_t|
///   i, j     ids of the two bodies                  optional; j < 0 is a wall
///   wall     1 for a contact with a wall, else 0    optional (j is set to -1 when 1)
///   frame    integer frame id                       optional; rows grouped by it
///   theta    tilt angle [deg] of the row's frame    optional; constant within a frame
///   status   solver status 0 open, 1 stick, 2 slide optional
/// Other columns are ignored, whatever they hold. Units are the user's: the analysis is
/// scale-free given the mean diameter D (a command-line option) and mu. A comment line
/// `# length_unit: U` before the header declares the unit of x, y (and of D), e.g. `m`.
struct ContactTable {
  std::string file;
  std::vector<std::string> columns;
  bool has_ids = false, has_walls = false, has_theta = false, has_status = false;
  std::string length_unit;                ///< from `# length_unit:`; empty = not declared
  std::size_t merged = 0;                 ///< rows dropped as repeats (Duplicates::merge)
  std::vector<ContactTableFrame> frames;  ///< in increasing frame id
};

/// Reads a contact table. Errors: a missing required column, a cell that is not a finite
/// number, a status other than 0/1/2, theta varying within a frame, an id that is not an
/// integer, a contact given twice (unless merged; then the two rows must agree: fn and
/// |ft| within 1e-9 of the larger normal force of the two, points within 1e-9 of their
/// distance scale). A table with a header and no rows has no frames (the tools then write
/// their documented empty result). With the grains' mean diameter D (in the table's length
/// unit), x and y are held within 1e9 D of the origin (docs/schema.md, "Ranges": deposit's
/// largest pile is 1e7 D wide and 1e8 D tall; a point beyond is no pile's).
ContactTable read_contact_table(const std::string& text, const std::string& file,
                                const ContactTableOptions& opt = {},
                                std::optional<double> diameter = std::nullopt);

}  // namespace cdpile::io
