/// LAMMPS and LIGGGHTS dumps, both ways (docs/analysis.md, "Other codes").
///
/// In: `from-lammps` turns the contacts of a LAMMPS or LIGGGHTS run into the contact table
/// that `localnu` reads (io/contact_table.hpp). It reads text dumps:
///   - atoms: `dump custom` snapshots (ITEM: ATOMS), at least id, x, y and radius (or
///     diameter); mass, fx, fy for the force check; the per-atom columns of
///     `fix wall/gran ... contacts` (f_ID[1] flag, [2..4] force on the atom, [5..7] the
///     contact point on the wall) for wall contacts;
///   - contacts: `dump local` snapshots (ITEM: ENTRIES) of `compute property/local patom1
///     patom2` with `compute pair/local` (LAMMPS), or of `compute pair/gran/local` and
///     `compute wall/gran/local` (LIGGGHTS).
/// Columns are found by name, in any order: a dump local names them c_ID[k], so the
/// meaning of each comes from the compute that made it, read from the input script
/// (`--script`), or is given by hand (`--columns c_cpl[2]=fn`), or the header already uses
/// the role names below. Snapshots are matched by their TIMESTEP across every file given,
/// so multi-snapshot files and one-file-per-step dumps work alike.
///
/// Out: `to-lammps` writes a pile or a run as a LAMMPS `dump custom` text (one snapshot
/// per frame) that OVITO and VMD read.
///
/// Errors are cdpile::Error naming the file and the line or the step.
#pragma once

#include "cdpile/io/contact_table.hpp"
#include "cdpile/io/schema.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace cdpile::io::lammps {

/// One snapshot of a text dump.
struct Snapshot {
  enum class Kind { atoms, entries };
  Kind kind = Kind::atoms;
  std::int64_t step = 0;
  std::optional<double> time;           ///< ITEM: TIME, when the dump has it
  std::string units;                    ///< ITEM: UNITS, when the dump has it
  std::array<double, 6> box{};          ///< xlo xhi ylo yhi zlo zhi
  std::array<std::string, 3> boundary;  ///< "pp", "ff", "fm", ... per dimension
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;  ///< [column][row]; a cell that is not a number is NaN
  std::vector<std::size_t> line;            ///< source line of each row (1-based)
  std::string file;
  std::size_t first_line = 0;  ///< line of ITEM: TIMESTEP
  std::size_t rows() const { return line.size(); }
  std::optional<std::size_t> find(const std::string& column) const;
};

/// Every snapshot of a dump's text, in file order.
std::vector<Snapshot> parse_dump(const std::string& text, const std::string& file);

/// What an input script says about the dumps: the computes behind dump local columns,
/// the wall fixes behind per-atom columns, the pair style (its pN), the units.
struct Script {
  struct Compute {
    std::string style;              ///< pair/local, property/local, pair/gran/local, ...
    std::vector<std::string> args;  ///< the words after the style
    std::string where;              ///< FILE: line L, for messages
  };
  struct WallFix {
    char axis = 0;          ///< 'x', 'y', 'z' for a plane; 0 for another shape
    bool contacts = false;  ///< has the `contacts` keyword (per-atom output)
  };
  std::map<std::string, Compute> computes;
  std::map<std::string, WallFix> walls;
  std::string pair_style;
  std::string units;               ///< the `units` command's style (si, cgs, lj, ...)
  std::optional<double> timestep;  ///< a numeric `timestep`, if any
};

/// Reads an input script (`&` continuations, `#` comments), following `include FILE`
/// (relative to the script's folder, also inside `if ... then "..."`) when the name has
/// no variable.
void read_script(const std::string& path, Script& into);
/// The same from text (includes resolved against `folder`).
void parse_script(const std::string& text, const std::string& file, const std::string& folder,
                  Script& into);

/// The length unit of a LAMMPS units style (si: m, cgs: cm, micro: um, nano: nm, real and
/// metal: Ang); empty for lj and unknown styles.
std::string length_unit_of(const std::string& units_style);

/// The role names of dump local columns (`--columns NAME=ROLE`, or as header names):
///   id1 id2       the two atoms (LIGGGHTS wall: id1 the particle)
///   fn            normal force, positive when repulsive (LAMMPS pair/local `force`)
///   fnx fny       normal force vector on atom 1 (pair/local fx fy; LIGGGHTS force_normal)
///   ftx fty       tangential force vector on atom 1 (gran pair styles' p1 p2; force_tangential)
///   ftmag         |f_t| (gran pair styles' p4): an unsigned ft when there is no vector
///   fx fy         total contact force on atom 1 (LIGGGHTS force)
///   x1 y1 x2 y2   positions of the two atoms (LIGGGHTS pos)
///   px py         contact point (LIGGGHTS wall pos)
///   wall          wall (mesh) id (LIGGGHTS wall/gran/local id)
/// and of atom columns: id x y (also xu yu, xs ys) radius diameter mass fx fy.
const std::vector<std::string>& entry_roles();

/// The roles of the columns of one header, from explicit names, the script's computes and
/// the role names themselves. Columns with no known meaning map to "".
std::vector<std::string> entry_column_roles(
    const std::vector<std::string>& columns, const Script& script,
    const std::map<std::string, std::string>& explicit_roles, const std::string& where);

struct ConvertOptions {
  Script script;
  std::map<std::string, std::string> columns;  ///< explicit NAME -> role of dump local columns
  std::map<std::string, char> wall_axes;       ///< `--wall FIX=AXIS`: fix wall/gran IDs and axes
  std::optional<double> rate;                  ///< tilt rate [deg per time unit]
  std::optional<double> dt;                    ///< time step [time unit] (else the script's)
  std::string theta_column;                    ///< an atoms column holding the tilt [deg]
  Duplicates duplicates = Duplicates::error;
  bool check = false;             ///< rebuild each grain's force (needs mass, fx, fy)
  double gravity = 9.81;          ///< g for the check, in the dump's units
  double check_tolerance = 1e-3;  ///< largest |difference| / (m g) accepted
};

/// One contact row of the table.
struct Row {
  std::int64_t frame = 0;
  std::optional<double> theta;
  std::int64_t i = 0, j = 0;  ///< atom ids; j < 0 a wall (-1 floor, -2 left, -3 right, -4 top)
  double x = 0, y = 0, fn = 0, ft = 0;
  bool wall = false;
  std::string where;  ///< FILE: line L of the source row
};

struct FrameCheck {
  std::int64_t step = 0;
  double worst_free = 0, worst_all = 0;  ///< |table + m g - f| / (m g), off the walls / all
  std::int64_t worst_id = 0;             ///< the grain of worst_all
  std::size_t grains = 0, grains_free = 0;
};

struct Conversion {
  std::vector<Row> rows;
  std::size_t frames = 0, pair_rows = 0, wall_rows = 0, merged = 0;
  bool ft_signed = true;  ///< false: ft is |f_t| (the dumps have no tangential vector)
  bool has_theta = false;
  std::string length_unit;         ///< from the script's or the dump's units; empty if unknown
  std::vector<std::string> notes;  ///< what the table is and is not, one line each
  std::vector<FrameCheck> checks;  ///< with ConvertOptions::check
};

/// A named text input (a dump file or standard input).
struct TextFile {
  std::string name, text;
};

/// Converts the dumps. Errors: a snapshot without the columns it needs (naming them and
/// what they could be), contacts at a step without atoms, an atom id not in the atoms
/// snapshot, a pair given twice (unless merged), a failed force check.
Conversion convert(const std::vector<TextFile>& dumps, const ConvertOptions& opt);

/// The contact table (`# ` header lines with the notes and length unit, then a TSV table).
void write_table(std::ostream& os, const Conversion& c,
                 const std::vector<std::string>& header_comments);

/// to-lammps: every frame of a pile or run as a `dump custom` snapshot with columns
/// id type x y z radius vx vy vz omegaz mass (id = grain index + 1, type = species + 1,
/// z = vz = 0). The box is the cdpile box (0 to its width) in x, and in y the extent of
/// the floor and the grains of the frame; z is one largest diameter thick, centred on 0.
struct ExportOptions {
  std::optional<std::size_t> first, last;  ///< frame range (inclusive), default all
  std::size_t every = 1;
};
std::size_t write_dump(std::ostream& os, const RunReader& run, const ExportOptions& opt = {});

/// to-lammps --contacts: the same frames' grain-grain contacts as `dump local` snapshots
/// (ITEM: NUMBER OF ENTRIES, ITEM: ENTRIES id1 id2 fn ft critical), the force network as
/// bonds for OVITO's Load trajectory modifier: id1, id2 the atom ids of write_dump (grain
/// index + 1), fn >= 0 and ft signed along the contact's tangent [N/m], critical 1 when
/// where `critical(fn, ft)` says so (decided by the analysis layer: reading/views.hpp, the
/// view's rule). Wall contacts are left out (no second atom). The box bounds are the atoms
/// dump's. Returns the number of snapshots.
using IsCritical = std::function<bool(double fn, double ft)>;
std::size_t write_contacts_dump(std::ostream& os, const RunReader& run, const ExportOptions& opt,
                                const IsCritical& critical);

}  // namespace cdpile::io::lammps
