/// Options shared by the analysis tools, declared and read in one place so that critical,
/// localnu, correlate and clusterfit spell and document them the same way.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/analysis/table.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/cli/friction_options.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/io/schema.hpp"

#include <string>
#include <vector>

namespace cdpile::cli {

/// -o, --format and --table of a product: TSV on standard output by default, HDF5 with
/// -o FILE (TSV if FILE ends in .tsv). `tables` lists every table the tool can write: the
/// values --table accepts, checked when the command line is parsed (a usage error, exit 2,
/// before any input is read). A tool refuses a table its other options leave out
/// (critical --no-steps with --table steps) itself, also before reading.
void declare_product_output(Usage& u, const std::vector<std::string>& tables);

/// Refuses `--table NAME` when the tool's other options leave that table out (`left_out`):
/// a usage error "--table NAME WHY" (WHY e.g. "with --no-steps"), before any input is read.
void refuse_table_if(const Args& a, const std::string& table, bool left_out,
                     const std::string& why);

/// Writes the product where the options of declare_product_output say (io::emit).
void emit_product(const Args& a, const analysis::Product& p,
                  const std::vector<io::Provenance>& history);
/// Refuses (UsageError) an ensemble that names one input twice: '-' more than once, or
/// two paths of the same file (statistics over runs would count it twice).
void refuse_repeated_inputs(const std::vector<std::string>& paths);

/// Refuses the -o target before any work (an existing file without --force, a missing
/// folder), as emit_product would after it, and --table with HDF5 output (a usage error).
void check_output(const Args& a);

/// The "Critical contacts" group: --eps, --mu and --mu-wall (declare_friction), --walls,
/// --floor-grains.
/// `mu_help` is --mu's help (what the default is for this tool's inputs).
void declare_critical_rule(Usage& u, const std::string& mu_help);

/// The rule of declare_critical_rule's options.
analysis::CriticalRule critical_rule(const Args& a);

}  // namespace cdpile::cli
