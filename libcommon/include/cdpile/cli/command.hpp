/// The one command-line layer every cdpile tool uses.
///
/// A tool file declares its usage (synopsis, description, examples, positional
/// arguments, options with type, default, unit and range) and a `run` function, then
/// ends with `CDPILE_TOOL(usage, run)`. Parsing (Boost.Program_options, no prefix
/// guessing), `--help`, `--version`, error printing and exit codes live here:
///   0  success (also for --help and --version)
///   1  runtime or data error (cdpile::Error and anything unexpected)
///   2  usage error (cdpile::UsageError: unknown option, bad value, missing argument)
/// Every message goes to stderr as one line `tool: FILE: WHERE: WHAT`.
#pragma once

#include "cdpile/error.hpp"
#include "cdpile/option.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace cdpile::cli {

/// The kinds of value an option takes; each is parsed strictly (no trailing junk,
/// no nan or inf, range checked), so `--grains 1e` or `--mu nan` is a usage error.
/// `text_list` is a comma-separated list of names from a fixed set (`--table runs,frames`).
enum class Kind { flag, integer, real, text, real_list, text_list, path_in, path_out };

struct OptionSpec {
  std::string name;     ///< long name without dashes, e.g. "grains"
  char short_name = 0;  ///< e.g. 'o', or 0
  Kind kind = Kind::text;
  std::string help;          ///< one sentence
  std::string unit;          ///< e.g. "m", "deg", "D" (mean diameters); empty if none
  std::string default_text;  ///< shown by --help; empty means "no default" (optional)
  bool has_default = false;
  bool required = false;
  double min = -1e308, max = 1e308;  ///< for integer and real values (inclusive)
  std::string group = "Options";
};

struct Example {
  std::string title, command, explanation;
};

/// The declaration of a tool's interface. Built by the tool's `usage` function.
class Usage {
 public:
  std::string name;                      ///< set by CDPILE_TOOL from the executable
  std::string synopsis;                  ///< one line
  std::vector<std::string> description;  ///< paragraphs: definitions, choices, units
  std::vector<Example> examples;
  std::vector<OptionSpec> positionals;  ///< in order; the last may repeat
  bool last_positional_repeats = false;
  /// The tool can write HDF5 (a pile, a run or a product): it gets the standard option
  /// --author, the name recorded in /h5md/author. Text-only tools set it false.
  bool writes_hdf5 = true;
  std::vector<OptionSpec> options;
  /// Allowed values of text options, and of each item of a text_list option. Checked when
  /// the command line is parsed, so a bad value is a usage error before any work starts.
  std::map<std::string, std::vector<std::string>> choices_;

  /// A positional argument (a file, "-" for standard input where the tool allows it).
  Usage& argument(const std::string& name, const std::string& help, bool repeats = false,
                  bool required = true);
  Usage& flag(const std::string& name, const std::string& help, char short_name = 0);
  Usage& integer(const std::string& name, std::int64_t def, const std::string& help,
                 std::int64_t min = INT64_MIN, std::int64_t max = INT64_MAX,
                 const std::string& unit = "");
  /// An integer option with no default: absent means "not given".
  Usage& integer_opt(const std::string& name, const std::string& help, std::int64_t min = INT64_MIN,
                     std::int64_t max = INT64_MAX, const std::string& unit = "");
  Usage& real(const std::string& name, double def, const std::string& help,
              const std::string& unit = "", double min = -1e308, double max = 1e308);
  /// A real option with no default: absent means "not given".
  Usage& real_opt(const std::string& name, const std::string& help, const std::string& unit = "",
                  double min = -1e308, double max = 1e308);
  /// A comma-separated list of reals, or a range FIRST:STEP:LAST.
  Usage& real_list(const std::string& name, const std::string& def, const std::string& help,
                   const std::string& unit = "", double min = -1e308, double max = 1e308);
  Usage& text(const std::string& name, const std::string& def, const std::string& help,
              const std::vector<std::string>& choices = {});
  Usage& text_opt(const std::string& name, const std::string& help);
  /// A comma-separated list of names, each one of `choices` (e.g. --table runs,frames);
  /// no default: absent means "all" to the tool. Read it with Args::text_list.
  Usage& text_list(const std::string& name, const std::string& help,
                   const std::vector<std::string>& choices);
  /// An option declared by the library (sim::run_parameters()), in the declaration's group
  /// of --help (a name with its choices, else a number); the current group is that group
  /// afterwards. Its field is then spelled as this option in the library's messages
  /// (cli/fields.hpp), and its old name is an alias.
  Usage& declare(const OptionDeclaration& d);
  /// Those of `declared` in `group`, in their order (one with `after` moved after that
  /// option), at this point of --help.
  Usage& declare(const std::string& group, const std::vector<OptionDeclaration>& declared);
  /// Moves the option declared last to just after the declared option `name`: a tool's own
  /// option beside one the library declares (tilt-cd's --branch-at after --from, the
  /// start it stands for). Its place in --help, and in the order values are checked.
  Usage& place_after(const std::string& name);
  /// Declares `-o FILE` / `--output FILE`. `def` "-" means standard output by default.
  Usage& output(const std::string& help, const std::string& def = "");
  /// Declares `--seed N` (default 1), the one seed option of every tool.
  Usage& seed(const std::string& help = "seed of the random number generator");
  /// Starts a new group of options in --help.
  Usage& group(const std::string& title);
  Usage& example(const std::string& title, const std::string& command,
                 const std::string& explanation);
  /// An old spelling of the declared option `name`, kept for one version: accepted as
  /// `name`, left out of --help, and warned about on stderr when used (docs/cli.md).
  Usage& alias(const std::string& old_name, const std::string& name);
  /// Old spelling -> option name.
  std::map<std::string, std::string> aliases_;

 private:
  std::string current_group_ = "Options";
  Usage& add(OptionSpec s);
};

/// The parsed command line, typed by the declaration.
class Args {
 public:
  bool has(const std::string& name) const;    ///< given on the command line or defaulted
  bool given(const std::string& name) const;  ///< given on the command line
  bool flag(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;
  double real(const std::string& name) const;
  std::optional<double> real_opt(const std::string& name) const;
  std::optional<std::int64_t> integer_opt(const std::string& name) const;
  std::vector<double> real_list(const std::string& name) const;
  const std::string& text(const std::string& name) const;
  /// The items of a text_list option (split_list of its value); empty if not given.
  std::vector<std::string> text_list(const std::string& name) const;
  /// Positional arguments by name; a repeating one gives all its values.
  const std::vector<std::string>& arguments(const std::string& name) const;
  const std::string& argument(const std::string& name) const;
  /// Output path from -o ("-" is standard output); empty if absent and no default.
  const std::string& output() const;
  bool force() const { return flag("force"); }
  bool quiet() const { return flag("quiet"); }
  std::uint64_t seed() const { return static_cast<std::uint64_t>(integer("seed")); }

  /// The full command line as typed (shell-quoted), for provenance.
  const std::string& command_line() const { return command_line_; }
  const std::string& tool() const { return tool_; }

  // Filled by parse().
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> positional_;
  std::map<std::string, bool> given_;
  std::map<std::string, Kind> kinds_;
  std::string command_line_, tool_;
};

/// The values of the library's declared options (Usage::declare): as given, else their
/// default; one neither given nor defaulted is absent.
OptionValues option_values(const Args& a, const std::vector<OptionDeclaration>& declared);

/// Parses argv against the declaration. Throws UsageError with a one-line reason.
/// `--help` and `--version` are handled by run_tool, not here.
Args parse(const Usage& usage, const std::vector<std::string>& argv);

/// A second output, the file of the text option --`option` (to-lammps' and critical's
/// --contacts): refused (UsageError) when it names the file -o names.
void refuse_output_named_twice(const Args& a, const std::string& option);

/// Refuses an output (-o) that is the same file as an input (an argument, or a file named
/// by a text option), with or without --force: a UsageError. run_tool calls it.
void check_output_is_not_an_input(const Args& a);

/// The help text: synopsis, usage line, description, arguments, options with their
/// default and unit, examples, exit codes.
std::string help_text(const Usage& usage);
/// The same declaration as a Markdown page (docs/tools/<tool>.md is generated from it).
std::string help_markdown(const Usage& usage);

/// The same declaration as a manual page (roff, man(7)): `TOOL --help-man` writes it, and
/// the build installs it as TOOL.1 beside the tool.
std::string help_man(const Usage& usage);

/// A tool's body: runs the tool and returns its exit code, 0 on success or the code of an
/// outcome that is not an error (an interrupted run's interrupt_exit_code()); errors are
/// thrown. A tool never calls std::exit: the runner flushes and cleans up for every code.
using Body = std::function<int(const Args&)>;

/// The one main() of every tool: builds the usage, parses, runs, prints errors and
/// returns the exit code. Adds the standard options (--help, --version, --force,
/// --quiet, and --author to a tool that writes HDF5) to every tool.
int run_tool(int argc, char** argv, const std::function<void(Usage&)>& declare, const Body& body);
/// The same for a body that returns nothing: 0 once it returns.
template <class Run,
          std::enable_if_t<std::is_void_v<std::invoke_result_t<Run&, const Args&>>, int> = 0>
int run_tool(int argc, char** argv, const std::function<void(Usage&)>& declare, Run run) {
  return run_tool(argc, argv, declare, Body([run](const Args& a) mutable {
                    run(a);
                    return 0;
                  }));
}

/// Splits a comma-separated option value ("frames,pdf") into its items; empty gives none.
std::vector<std::string> split_list(const std::string& s);

/// Messages on stderr, prefixed by the tool name; suppressed by --quiet except errors.
void warn(const std::string& what);
void info(const std::string& what);
const std::string& tool_name();

/// Ctrl-C and SIGTERM: by default they remove every registered temporary output and
/// exit with 128 + the signal (130, 143). A tool with a long loop calls defer_interrupts()
/// and polls interrupted() at least once a second to stop cleanly (after the current
/// step, with its checkpoint), then exits with interrupt_exit_code(); while deferred, no
/// signal, first or later, ends the process. end_deferral() returns to ending at once
/// (for what an immediate end loses nothing by: a final copy of a saved run), leaving a
/// signal already received to the tool.
void defer_interrupts();
void end_deferral();
bool interrupted();
int interrupt_exit_code();

}  // namespace cdpile::cli

#define CDPILE_TOOL(declare_fn, run_fn)                             \
  int main(int argc, char** argv) {                                 \
    return ::cdpile::cli::run_tool(argc, argv, declare_fn, run_fn); \
  }
