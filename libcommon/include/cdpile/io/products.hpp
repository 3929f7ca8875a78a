/// The analysis products (critical, localnu, correlate, clusterfit) on disk, as TSV or as
/// HDF5, and read back from either (docs/analysis.md, "Formats").
///
/// TSV: a commented header, then each table as a block separated by two blank lines
/// (gnuplot's `index`):
///
///     # tool: critical 0.1.0
///     # command: critical run1.h5 run2.h5
///     # input: run1.h5 run2.h5
///     # provenance: TOOL<TAB>VERSION<TAB>DATE<TAB>INPUTS<TAB>COMMAND[<TAB>VIA]   (one per tool
///                   of the chain, this one last; VIA: Provenance::via, after a merge)
///     # parameter eps = 0.001
///     # result nu_c = 0.0812
///     # note: ...
///
///     # table: frames
///     # about: one row per frame of each run
///     # columns: run [-] theta [deg] nu [-] ...
///     run	theta	nu	...
///     0	0.5	0.012	...
///
/// Numbers are the shortest text that reads back to the same double (std::to_chars);
/// missing values are NA. A text column is marked [text] in the columns line.
///
/// HDF5: the common header (io::write_header: /h5md, /parameters, /results, /provenance,
/// root attrs schema, kind), then /tables/<table>/<column> datasets (float64, int64, or
/// uint8 codes with a `labels` attribute for text) with a `unit` attribute, and for a
/// column with missing values a uint8 `<column>_defined` dataset (0 = missing, value 0).
/// /tables has attributes `tables` (names in order) and `notes`.
#pragma once

#include "cdpile/analysis/studies.hpp"
#include "cdpile/analysis/table.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/schema.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace cdpile::io {

/// The shortest round-trip text of a double ("NA" for NaN or infinity); with `digits` > 0,
/// the double to that many significant digits (printf's %.Ng).
std::string format_number(double v, int digits = 0);

/// A product as read from a file, with the history of the tools that made it.
struct ProductFile {
  analysis::Product product;
  std::vector<Provenance> provenance;
};

/// Writes a product as TSV. `only` lists the tables to write (empty: all). `header`: the
/// commented file header (tool, command, provenance, parameters, results, notes, the
/// tables' row counts) before the tables; without it the output is the tables alone, each
/// with its own '# table:' lines, and cannot be read back as a product. `digits`: the
/// significant digits of the numbers of the tables and of the parameter and result lines
/// (0: full precision, the shortest text that reads back to the same double).
void write_tsv(std::ostream& os, const analysis::Product& p, const std::vector<Provenance>& history,
               const std::vector<std::string>& only = {}, bool header = true, int digits = 0);

/// Writes a product into a new HDF5 file.
void write_hdf5(const h5::File& f, const analysis::Product& p,
                const std::vector<Provenance>& history);

/// Reads a product from an input (HDF5 by signature, else TSV). `expected_kind` non-empty
/// refuses another kind: "FILE: is a 'localnu' product, expected 'correlate'".
ProductFile read_product(const Input& in, const std::string& expected_kind = "");
ProductFile read_product_tsv(const std::string& text, const std::string& name);
ProductFile read_product_hdf5(const h5::File& f);

/// The per-step observables of a run as the analyses read them: N from `contacts_grain`
/// (or `contacts` with walls included, or when the run has no `contacts_grain`), the
/// critical count from `critical_grain` / `critical` if recorded, `sliding` if recorded,
/// `kinetic_energy`. Error if `tilt_angle` or the contact count is missing.
analysis::RunSteps steps_from_series(const Series& s, bool include_walls, const std::string& file);

/// The kind of a TSV product ("critical", "localnu", ...) from the '# kind:' line of its
/// comment header; empty if the text has none (a plain table).
std::string tsv_product_kind(const std::string& text);

/// Output formats of the analysis tools.
enum class Format { automatic, tsv, hdf5 };
Format parse_format(const std::string& s);  ///< "auto", "tsv", "hdf5"
/// The format `emit` writes: TSV without -o or to a .tsv/.txt/.dat name, HDF5 to '-' or
/// another name, unless `format` says which.
Format resolve_format(const std::string& output, Format format);

/// Writes a product where the tool was told to: with no -o (`output` empty) TSV on
/// standard output; with -o FILE, HDF5, unless FILE ends in .tsv, .txt or .dat or the
/// format says otherwise; `-o -` is HDF5 on standard output (for pipes) unless
/// `--format tsv`. Atomic (io::Output) and refusing to overwrite without `force`. `digits`
/// as write_tsv's, for TSV.
void emit(const analysis::Product& p, const std::vector<Provenance>& history,
          const std::string& output, bool force, Format format,
          const std::vector<std::string>& only = {}, bool header = true, int digits = 0);

}  // namespace cdpile::io
