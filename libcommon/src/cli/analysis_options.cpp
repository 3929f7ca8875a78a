#include "cdpile/cli/analysis_options.hpp"

#include "cdpile/analysis/critical_option.hpp"
#include "cdpile/io/products.hpp"

#include <algorithm>
#include <filesystem>

namespace cdpile::cli {

void declare_product_output(Usage& u, const std::vector<std::string>& tables) {
  u.output("output: HDF5 product, or TSV if FILE ends in .tsv (default: TSV on standard output)");
  u.text("format", "auto", "output format", {"auto", "tsv", "hdf5"});
  u.text_list("table",
              "write only these tables to TSV (without the commented file header unless --header)",
              tables);
  u.flag(
      "header",
      "with --table, write the commented file header too (provenance, parameters, results, notes), "
      "as a product read back by another tool needs");
  u.integer_opt("digits",
                "significant digits of the numbers in TSV tables and results (default: 6 on "
                "standard output without -o, for people; full precision with -o, a product "
                "another tool reads back; 0: full precision, the shortest text that reads back "
                "to the same double)",
                0, 17);
}

void refuse_table_if(const Args& a, const std::string& table, bool left_out,
                     const std::string& why) {
  if (!left_out) return;
  const std::vector<std::string> only = a.text_list("table");
  if (std::find(only.begin(), only.end(), table) != only.end())
    throw UsageError("--table " + table + " " + why);
}

void emit_product(const Args& a, const analysis::Product& p,
                  const std::vector<io::Provenance>& history) {
  for (const std::string& why : p.not_computed)
    info(why);  // not only in a '# note:' line of the output
  // A table for people prints the digits its numbers carry (a tilt angle summed in steps of
  // 0.01 is 13.12, not 13.120000000000001); a product for the next tool keeps every bit.
  const int digits = static_cast<int>(a.integer_opt("digits").value_or(a.output().empty() ? 6 : 0));
  io::emit(p, history, a.output(), a.force(), io::parse_format(a.text("format")),
           a.text_list("table"), a.text_list("table").empty() || a.flag("header"), digits);
}

void refuse_repeated_inputs(const std::vector<std::string>& paths) {
  if (std::count(paths.begin(), paths.end(), "-") > 1)
    throw UsageError("'-' (standard input) given twice");
  for (std::size_t i = 0; i < paths.size(); ++i)
    for (std::size_t j = i + 1; j < paths.size(); ++j) {
      std::error_code ec;
      if (paths[i] != "-" && paths[j] != "-" && std::filesystem::equivalent(paths[i], paths[j], ec))
        throw UsageError(paths[j] + ": the same file as " + paths[i] +
                         "; an ensemble counts each run once");
    }
}

void check_output(const Args& a) {
  const bool hdf5 =
      io::resolve_format(a.output(), io::parse_format(a.text("format"))) == io::Format::hdf5;
  if (!a.text_list("table").empty() && hdf5)
    throw UsageError("--table chooses tables of TSV output; an HDF5 product (-o " + a.output() +
                     ") holds them all (use a .tsv name or --format tsv)");
  io::Output check(a.output().empty() ? "-" : a.output(), a.force(), hdf5);
}

void declare_critical_rule(Usage& u, const std::string& mu_help) {
  u.declare(analysis::eps_option("Critical contacts"));
  declare_friction(u, mu_help,
                   "grain-wall friction coefficient (default: the run's mu_wall, else --mu)");
  u.flag("walls", "count contacts with walls (and glued floor grains)");
  u.text("floor-grains", "wall", "contacts with grains glued to the floor count as",
         {"wall", "grain"});
}

analysis::CriticalRule critical_rule(const Args& a) {
  analysis::CriticalRule r;
  r.eps = a.real("eps");
  r.include_walls = a.flag("walls");
  r.floor_grains_are_walls = a.text("floor-grains") == "wall";
  return r;
}

}  // namespace cdpile::cli
