#include "cdpile/cli/command.hpp"

#include "cdpile/cli/fields.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/schema.hpp"

#include <boost/program_options.hpp>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <typeinfo>

namespace po = boost::program_options;

namespace cdpile::cli {

namespace {

std::string g_tool = "cdpile";
bool g_quiet = false;
std::atomic<bool> g_deferred{false};
volatile std::sig_atomic_t g_interrupted = 0;

// The first SIGINT or SIGTERM is the one the tool reports (exit 128 + it). While a tool
// defers signals (it is stepping, or writing the checkpoint of its last completed step),
// every signal only asks it to stop: a scheduler signals the tool and its parent make
// together, and make forwards its SIGTERM, so a second signal is the rule there, not a
// user's impatience; ending at it would lose the checkpoint being written. The tool then
// stops within a second (it polls interrupted() within every step). Otherwise the tool
// has nothing to save and ends at once.
extern "C" void on_signal(int sig) {
  if (g_interrupted == 0) g_interrupted = sig;
  if (g_deferred.load()) return;
  io::remove_temporaries();
  _exit(128 + g_interrupted);
}

std::string format_number(double x) {
  if (x == std::floor(x) && std::fabs(x) < 1e15)  // integers as integers: 100000, not 1e+05
    return std::to_string(static_cast<long long>(x));
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

std::string range_text(const OptionSpec& o) {
  const bool lo = o.min > -1e307, hi = o.max < 1e307;
  if (lo && hi) return "in [" + format_number(o.min) + ", " + format_number(o.max) + "]";
  if (lo) return ">= " + format_number(o.min);
  if (hi) return "<= " + format_number(o.max);
  return "";
}

const char* kind_word(Kind k) {
  switch (k) {
    case Kind::integer: return "an integer";
    case Kind::real: return "a finite number";
    case Kind::real_list: return "a list of numbers (A,B,C or FIRST:STEP:LAST)";
    default: return "a value";
  }
}

[[noreturn]] void bad_value(const OptionSpec& o, const std::string& v,
                            const std::string& why = "") {
  std::string want = kind_word(o.kind);
  const std::string range = range_text(o);
  if (!range.empty()) want += " " + range;
  throw UsageError("--" + o.name + ": expected " + want + ", got '" + v + "'" +
                   (why.empty() ? "" : " (" + why + ")"));
}

double parse_real(const OptionSpec& o, const std::string& v) {
  double x = 0;
  const char* b = v.data();
  const char* e = b + v.size();
  if (!v.empty() && *b == '+') ++b;
  auto r = std::from_chars(b, e, x);
  if (v.empty() || r.ec != std::errc() || r.ptr != e || !std::isfinite(x)) bad_value(o, v);
  if (x < o.min || x > o.max) bad_value(o, v, "out of range");
  return x;
}

std::int64_t parse_integer(const OptionSpec& o, const std::string& v) {
  std::int64_t x = 0;
  const char* b = v.data();
  const char* e = b + v.size();
  if (!v.empty() && *b == '+') ++b;
  auto r = std::from_chars(b, e, x);
  if (v.empty() || r.ec != std::errc() || r.ptr != e) bad_value(o, v);
  if (static_cast<double>(x) < o.min || static_cast<double>(x) > o.max)
    bad_value(o, v, "out of range");
  return x;
}

std::vector<double> parse_list(const OptionSpec& o, const std::string& v) {
  std::vector<double> out;
  OptionSpec item = o;
  item.kind = Kind::real;
  if (v.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::stringstream ss(v);
    for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
    if (parts.size() != 3) bad_value(o, v, "a range is FIRST:STEP:LAST");
    OptionSpec any = item;
    any.min = -1e308;
    any.max = 1e308;
    const double first = parse_real(item, parts[0]), step = parse_real(any, parts[1]),
                 last = parse_real(item, parts[2]);
    if (!(step > 0) || last < first) bad_value(o, v, "the step must be positive and LAST >= FIRST");
    const auto n = static_cast<std::size_t>(std::floor((last - first) / step * (1 + 1e-12))) + 1;
    if (n > 1000000) bad_value(o, v, "more than 10^6 values");
    for (std::size_t k = 0; k < n; ++k) out.push_back(first + static_cast<double>(k) * step);
    return out;
  }
  std::stringstream ss(v);
  for (std::string p; std::getline(ss, p, ',');) out.push_back(parse_real(item, p));
  if (out.empty()) bad_value(o, v);
  return out;
}

void validate(const OptionSpec& o, const std::string& v) {
  switch (o.kind) {
    case Kind::integer: parse_integer(o, v); break;
    case Kind::real: parse_real(o, v); break;
    case Kind::real_list: parse_list(o, v); break;
    default: break;
  }
}

// An option with a fixed set of values (Usage::text, Usage::text_list): every value, or
// every item of a list, must be one of them. The one check of all enumerated options.
void check_choices(const Usage& usage, const OptionSpec& o, const std::string& v) {
  auto ch = usage.choices_.find(o.name);
  if (ch == usage.choices_.end() || ch->second.empty()) return;
  const auto& allowed = ch->second;
  const std::vector<std::string> items =
      o.kind == Kind::text_list ? split_list(v) : std::vector<std::string>{v};
  for (const std::string& item : items) {
    if (std::find(allowed.begin(), allowed.end(), item) != allowed.end()) continue;
    std::string list;
    for (const auto& c : allowed) list += (list.empty() ? "" : ", ") + c;
    if (o.kind == Kind::text_list)
      throw UsageError("--" + o.name + ": expected one or more of " + list +
                       " (comma-separated), got '" + item + "'");
    throw UsageError("--" + o.name + ": expected one of " + list + ", got '" + v + "'");
  }
}

std::string shell_quote(const std::string& s) {
  if (!s.empty() &&
      s.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=:,+@%") ==
          std::string::npos)
    return s;
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string metavar(const OptionSpec& o) {
  switch (o.kind) {
    case Kind::flag: return "";
    case Kind::integer: return "N";
    case Kind::real: return "X";
    case Kind::real_list: return "LIST";
    case Kind::text_list: return "LIST";
    case Kind::path_out: return "FILE";
    case Kind::path_in: return "FILE";
    default: return "TEXT";
  }
}

std::string wrap(const std::string& text, std::size_t indent, std::size_t width = 80) {
  std::string out, line;
  std::istringstream ss(text);
  const std::string pad(indent, ' ');
  for (std::string w; ss >> w;) {
    if (!line.empty() && line.size() + 1 + w.size() > width - indent) {
      out += pad + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + w;
  }
  if (!line.empty()) out += pad + line + "\n";
  return out;
}

std::string option_detail(const OptionSpec& o) {
  std::string d = o.help;
  std::vector<std::string> extra;
  if (!o.unit.empty()) extra.push_back("unit: " + o.unit);
  if (o.kind != Kind::flag && o.has_default)
    extra.push_back("default: " + (o.default_text.empty() ? std::string("''") : o.default_text));
  if (o.required) extra.push_back("required");
  const std::string range =
      (o.kind == Kind::integer || o.kind == Kind::real || o.kind == Kind::real_list) ? range_text(o)
                                                                                     : "";
  if (!range.empty()) extra.push_back(range);
  if (!extra.empty()) {
    d += " (";
    for (std::size_t k = 0; k < extra.size(); ++k) d += (k ? "; " : "") + extra[k];
    d += ")";
  }
  return d;
}

std::string option_label(const OptionSpec& o) {
  std::string s = o.short_name ? std::string("-") + o.short_name + ", " : "    ";
  s += "--" + o.name;
  const std::string m = metavar(o);
  if (!m.empty()) s += " " + m;
  return s;
}

void add_standard_options(Usage& u) {
  u.group("Standard options");
  u.flag("force", "replace an existing output file (otherwise it is never overwritten)");
  u.flag("quiet",
         "print no progress or information on stderr (warnings and errors are still printed)");
  if (u.writes_hdf5)
    u.text_opt("author",
               "the author recorded in HDF5 output (/h5md/author), 'NAME' or 'NAME <EMAIL>' "
               "(default: $CDPILE_AUTHOR, else your full name from the password database)");
  u.flag("help", "print this help and exit", 'h');
  u.flag("version", "print the version and exit");
}

}  // namespace

// ----------------------------------------------------------------------------------------
// Usage

Usage& Usage::add(OptionSpec s) {
  s.group = current_group_;
  for (const auto& o : options)
    if (o.name == s.name) throw std::logic_error("option --" + s.name + " declared twice");
  options.push_back(std::move(s));
  return *this;
}

Usage& Usage::argument(const std::string& n, const std::string& help, bool repeats, bool required) {
  OptionSpec s;
  s.name = n;
  s.help = help;
  s.kind = Kind::path_in;
  s.required = required;
  positionals.push_back(s);
  last_positional_repeats = repeats;
  return *this;
}

Usage& Usage::flag(const std::string& n, const std::string& help, char short_name) {
  OptionSpec s;
  s.name = n;
  s.help = help;
  s.kind = Kind::flag;
  s.short_name = short_name;
  return add(s);
}

Usage& Usage::integer(const std::string& n, std::int64_t def, const std::string& help,
                      std::int64_t min, std::int64_t max, const std::string& unit) {
  OptionSpec s;
  s.name = n;
  s.help = help;
  s.kind = Kind::integer;
  s.unit = unit;
  s.default_text = std::to_string(def);
  s.has_default = true;
  s.min = min == INT64_MIN ? -1e308 : static_cast<double>(min);
  s.max = max == INT64_MAX ? 1e308 : static_cast<double>(max);
  return add(s);
}

Usage& Usage::integer_opt(const std::string& n, const std::string& help, std::int64_t min,
                          std::int64_t max, const std::string& unit) {
  integer(n, 0, help, min, max, unit);
  options.back().has_default = false;
  options.back().default_text.clear();
  return *this;
}

Usage& Usage::real(const std::string& n, double def, const std::string& help,
                   const std::string& unit, double min, double max) {
  OptionSpec s;
  s.name = n;
  s.help = help;
  s.kind = Kind::real;
  s.unit = unit;
  s.default_text = format_number(def);
  s.has_default = true;
  s.min = min;
  s.max = max;
  return add(s);
}

Usage& Usage::real_opt(const std::string& n, const std::string& help, const std::string& unit,
                       double min, double max) {
  real(n, 0, help, unit, min, max);
  options.back().has_default = false;
  options.back().default_text.clear();
  return *this;
}

Usage& Usage::real_list(const std::string& n, const std::string& def, const std::string& help,
                        const std::string& unit, double min, double max) {
  OptionSpec s;
  s.name = n;
  s.help = help;
  s.kind = Kind::real_list;
  s.unit = unit;
  s.default_text = def;
  s.has_default = !def.empty();  // an empty list: absent means none
  s.min = min;
  s.max = max;
  return add(s);
}

Usage& Usage::text(const std::string& n, const std::string& def, const std::string& help,
                   const std::vector<std::string>& choices) {
  OptionSpec s;
  s.name = n;
  s.kind = Kind::text;
  s.default_text = def;
  s.has_default = true;
  s.help = help;
  if (!choices.empty()) {
    s.help += "; one of:";
    for (std::size_t k = 0; k < choices.size(); ++k) s.help += (k ? ", " : " ") + choices[k];
    s.unit.clear();
  }
  add(s);
  choices_[n] = choices;
  return *this;
}

Usage& Usage::text_opt(const std::string& n, const std::string& help) {
  OptionSpec s;
  s.name = n;
  s.kind = Kind::text;
  s.help = help;
  return add(s);
}

Usage& Usage::text_list(const std::string& n, const std::string& help,
                        const std::vector<std::string>& choices) {
  OptionSpec s;
  s.name = n;
  s.kind = Kind::text_list;
  s.help = help + "; comma-separated, each one of:";
  for (std::size_t k = 0; k < choices.size(); ++k) s.help += (k ? ", " : " ") + choices[k];
  add(s);
  choices_[n] = choices;
  return *this;
}

Usage& Usage::declare(const OptionDeclaration& d) {
  group(d.group);
  // The library's messages name the field by this option (fields.hpp, option_of_field).
  if (!d.field.empty()) spell_field(d.field, "--" + d.name);
  if (!d.choices.empty()) {
    text(d.name, std::get<std::string>(d.default_value), d.help, d.choices);
  } else {
    OptionSpec s;
    s.name = d.name;
    s.help = d.help;
    s.unit = d.unit;
    s.kind = d.integer ? Kind::integer : Kind::real;
    // The default's text as integer() and real() write it.
    if (auto* x = std::get_if<double>(&d.default_value)) s.default_text = format_number(*x);
    if (auto* i = std::get_if<std::int64_t>(&d.default_value)) s.default_text = std::to_string(*i);
    s.has_default = !std::holds_alternative<std::monostate>(d.default_value);
    s.min = d.min;
    s.max = d.max;
    add(s);
  }
  if (!d.old_name.empty()) alias(d.old_name, d.name);
  return *this;
}

Usage& Usage::declare(const std::string& title, const std::vector<OptionDeclaration>& declared) {
  group(title);
  for (const OptionDeclaration& d : declared)
    if (d.group == title) declare(d);
  // Then those listed elsewhere than in the declarations' order.
  auto at = [&](const std::string& n) {
    return std::find_if(options.begin(), options.end(),
                        [&](const OptionSpec& o) { return o.name == n; });
  };
  for (const OptionDeclaration& d : declared) {
    if (d.group != title || d.after.empty()) continue;
    const auto moved = at(d.name), before = at(d.after);
    if (before == options.end())
      throw std::logic_error("--" + d.name + " after an undeclared --" + d.after);
    if (moved < before)
      std::rotate(moved, moved + 1, before + 1);
    else
      std::rotate(before + 1, moved, moved + 1);
  }
  return *this;
}

Usage& Usage::place_after(const std::string& n) {
  const auto at = std::find_if(options.begin(), options.end(),
                               [&](const OptionSpec& o) { return o.name == n; });
  if (at == options.end() || at + 1 == options.end())
    throw std::logic_error("--" + options.back().name + " placed after --" + n +
                           ", not declared before it");
  std::rotate(at + 1, options.end() - 1, options.end());
  return *this;
}

Usage& Usage::output(const std::string& help, const std::string& def) {
  OptionSpec s;
  s.name = "output";
  s.short_name = 'o';
  s.kind = Kind::path_out;
  s.help = help;
  if (!def.empty()) {
    s.default_text = def;
    s.has_default = true;
  }
  return add(s);
}

Usage& Usage::seed(const std::string& help) { return integer("seed", 1, help, 0); }

Usage& Usage::group(const std::string& title) {
  current_group_ = title;
  return *this;
}

Usage& Usage::alias(const std::string& old_name, const std::string& n) {
  const bool declared =
      std::any_of(options.begin(), options.end(), [&](const OptionSpec& o) { return o.name == n; });
  if (!declared) throw std::logic_error("alias --" + old_name + " of an undeclared option --" + n);
  aliases_[old_name] = n;
  return *this;
}

Usage& Usage::example(const std::string& title, const std::string& command,
                      const std::string& explanation) {
  examples.push_back({title, command, explanation});
  return *this;
}

// ----------------------------------------------------------------------------------------
// Args

bool Args::has(const std::string& n) const { return values_.count(n) > 0; }
bool Args::given(const std::string& n) const {
  auto it = given_.find(n);
  return it != given_.end() && it->second;
}
bool Args::flag(const std::string& n) const { return given(n); }

namespace {
const OptionSpec& spec_for(const std::map<std::string, Kind>& kinds, const std::string& n) {
  static thread_local OptionSpec s;
  auto it = kinds.find(n);
  if (it == kinds.end()) throw std::logic_error("option --" + n + " was not declared");
  s = OptionSpec{};
  s.name = n;
  s.kind = it->second;
  return s;
}
}  // namespace

std::int64_t Args::integer(const std::string& n) const {
  auto v = integer_opt(n);
  if (!v) throw UsageError("--" + n + " is required");
  return *v;
}
std::optional<std::int64_t> Args::integer_opt(const std::string& n) const {
  const OptionSpec& s = spec_for(kinds_, n);
  auto it = values_.find(n);
  if (it == values_.end()) return std::nullopt;
  return parse_integer(s, it->second);
}
double Args::real(const std::string& n) const {
  auto v = real_opt(n);
  if (!v) throw UsageError("--" + n + " is required");
  return *v;
}
std::optional<double> Args::real_opt(const std::string& n) const {
  const OptionSpec& s = spec_for(kinds_, n);
  auto it = values_.find(n);
  if (it == values_.end()) return std::nullopt;
  return parse_real(s, it->second);
}
std::vector<double> Args::real_list(const std::string& n) const {
  const OptionSpec& s = spec_for(kinds_, n);
  auto it = values_.find(n);
  if (it == values_.end()) return {};
  return parse_list(s, it->second);
}
const std::string& Args::text(const std::string& n) const {
  static const std::string empty;
  auto it = values_.find(n);
  return it == values_.end() ? empty : it->second;
}
std::vector<std::string> Args::text_list(const std::string& n) const { return split_list(text(n)); }
const std::vector<std::string>& Args::arguments(const std::string& n) const {
  static const std::vector<std::string> none;
  auto it = positional_.find(n);
  return it == positional_.end() ? none : it->second;
}
const std::string& Args::argument(const std::string& n) const {
  static const std::string empty;
  const auto& v = arguments(n);
  return v.empty() ? empty : v.front();
}
const std::string& Args::output() const { return text("output"); }

// ----------------------------------------------------------------------------------------
// Parsing

OptionValues option_values(const Args& a, const std::vector<OptionDeclaration>& declared) {
  OptionValues v;
  for (const OptionDeclaration& d : declared)
    if (a.has(d.name))
      v[d.name] = !d.choices.empty() ? OptionValue(a.text(d.name))
                  : d.integer        ? OptionValue(a.integer(d.name))
                                     : OptionValue(a.real(d.name));
  return v;
}

Args parse(const Usage& usage, const std::vector<std::string>& argv) {
  po::options_description desc;
  for (const auto& o : usage.options) {
    const std::string key = o.short_name ? o.name + "," + o.short_name : o.name;
    if (o.kind == Kind::flag)
      desc.add_options()(key.c_str(), po::bool_switch());
    else
      desc.add_options()(key.c_str(), po::value<std::string>());
  }
  for (const auto& alias : usage.aliases_) {
    const std::string& old_name = alias.first;
    const std::string& n = alias.second;  // a plain reference: clang 14 (the sanitizer builds) cannot capture a structured binding
    const auto o = std::find_if(usage.options.begin(), usage.options.end(),
                                [&](const OptionSpec& x) { return x.name == n; });
    if (o->kind == Kind::flag)
      desc.add_options()(old_name.c_str(), po::bool_switch());
    else
      desc.add_options()(old_name.c_str(), po::value<std::string>());
  }
  po::positional_options_description pos;
  for (std::size_t k = 0; k < usage.positionals.size(); ++k) {
    const bool last = k + 1 == usage.positionals.size();
    desc.add_options()(usage.positionals[k].name.c_str(), po::value<std::vector<std::string>>());
    pos.add(usage.positionals[k].name.c_str(), last && usage.last_positional_repeats ? -1 : 1);
  }
  // No prefix guessing: an abbreviation that works today would break when a new
  // option sharing the prefix is added, silently, inside someone's Makefile.
  const int style = po::command_line_style::unix_style ^ po::command_line_style::allow_guessing;
  po::variables_map vm;
  try {
    std::vector<std::string> args(argv.begin() + 1, argv.end());
    po::store(po::command_line_parser(args).options(desc).positional(pos).style(style).run(), vm);
  } catch (const po::too_many_positional_options_error&) {
    throw UsageError("too many arguments");
  } catch (const po::error& e) {
    throw UsageError(e.what());
  }
  // An old spelling stands for its option; both together are the option given twice.
  for (const auto& [old_name, n] : usage.aliases_) {
    const bool is_flag = vm.count(old_name) && vm[old_name].value().type() == typeid(bool);
    const bool used = vm.count(old_name) && (!is_flag || vm[old_name].as<bool>());
    if (!used) continue;
    const bool also = vm.count(n) && (!is_flag || vm[n].as<bool>());
    if (also) throw UsageError("--" + n + " given twice (also as --" + old_name + ")");
    warn("--" + old_name + " is deprecated and will be removed; use --" + n);
    vm.erase(n);
    vm.insert({n, vm[old_name]});
  }
  Args a;
  a.tool_ = usage.name;
  for (const auto& s : argv)
    a.command_line_ += (a.command_line_.empty() ? "" : " ") + shell_quote(s);
  for (const auto& o : usage.options) {
    a.kinds_[o.name] = o.kind;
    if (o.kind == Kind::flag) {
      a.given_[o.name] = vm.count(o.name) && vm[o.name].as<bool>();
      continue;
    }
    if (vm.count(o.name)) {
      const std::string v = vm[o.name].as<std::string>();
      validate(o, v);
      check_choices(usage, o, v);
      a.values_[o.name] = v;
      a.given_[o.name] = true;
    } else if (o.has_default) {
      a.values_[o.name] = o.default_text;
    } else if (o.required) {
      throw UsageError("--" + o.name + " is required");
    }
  }
  for (std::size_t k = 0; k < usage.positionals.size(); ++k) {
    const auto& p = usage.positionals[k];
    if (vm.count(p.name)) {
      a.positional_[p.name] = vm[p.name].as<std::vector<std::string>>();
    } else if (p.required) {
      throw UsageError("missing argument " + p.name);
    }
  }
  return a;
}

// ----------------------------------------------------------------------------------------
// Help

namespace {
std::string usage_line(const Usage& u) {
  std::string s = "Usage: " + u.name + " [options]";
  for (const auto& p : u.positionals) {
    std::string n = p.name;
    for (auto& c : n) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (&p == &u.positionals.back() && u.last_positional_repeats) n += "...";
    s += p.required ? " " + n : " [" + n + "]";
  }
  return s;
}
const char* kExitCodes =
    "Exit status: 0 success; 1 runtime or data error (bad input file, failed write); "
    "2 usage error (unknown option, bad value, missing argument); 130 interrupted by "
    "Ctrl-C (SIGINT), 143 by SIGTERM. Errors are one line on stderr: "
    "'tool: FILE: WHERE: WHAT'.";
}  // namespace

std::string help_text(const Usage& u) {
  std::ostringstream out;
  out << u.name << ": " << u.synopsis << "\n\n" << usage_line(u) << "\n\n";
  for (const auto& para : u.description) out << wrap(para, 0) << "\n";
  if (!u.positionals.empty()) {
    out << "Arguments:\n";
    for (const auto& p : u.positionals) {
      std::string n = p.name;
      for (auto& c : n) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      out << "  " << n << "\n" << wrap(p.help, 10);
    }
    out << "\n";
  }
  std::string group;
  for (const auto& o : u.options) {
    if (o.group != group) {
      out << (group.empty() ? "" : "\n") << o.group << ":\n";
      group = o.group;
    }
    out << "  " << option_label(o) << "\n" << wrap(option_detail(o), 10);
  }
  if (!u.examples.empty()) {
    out << "\nExamples:\n";
    for (const auto& e : u.examples)
      out << "  " << e.title << ":\n      $ " << e.command << "\n" << wrap(e.explanation, 6);
  }
  out << "\n" << wrap(kExitCodes, 0);
  return out.str();
}

std::string help_markdown(const Usage& u) {
  std::ostringstream out;
  out << "# " << u.name << "\n\n" << u.synopsis << "\n\n```\n" << usage_line(u) << "\n```\n\n";
  for (const auto& para : u.description) out << para << "\n\n";
  if (!u.positionals.empty()) {
    out << "## Arguments\n\n| argument | meaning |\n|---|---|\n";
    for (const auto& p : u.positionals) out << "| `" << p.name << "` | " << p.help << " |\n";
    out << "\n";
  }
  std::string group;
  for (const auto& o : u.options) {
    if (o.group != group) {
      group = o.group;
      out << "## " << group << "\n\n| option | meaning | unit | default |\n|---|---|---|---|\n";
    }
    std::string label =
        (o.short_name ? std::string("-") + o.short_name + ", " : "") + "--" + o.name;
    const std::string m = metavar(o);
    if (!m.empty()) label += " " + m;
    std::string help = o.help;
    const std::string range =
        (o.kind == Kind::integer || o.kind == Kind::real || o.kind == Kind::real_list)
            ? range_text(o)
            : "";
    if (!range.empty()) help += " (" + range + ")";
    out << "| `" << label << "` | " << help << " | " << o.unit << " | "
        << (o.has_default ? "`" + o.default_text + "`" : (o.required ? "required" : "")) << " |\n";
    if (&o == &u.options.back() ||
        u.options[static_cast<std::size_t>(&o - u.options.data()) + 1].group != group)
      out << "\n";
  }
  if (!u.examples.empty()) {
    out << "## Examples\n\n";
    for (const auto& e : u.examples)
      out << "**" << e.title << "**\n\n```sh\n"
          << e.command << "\n```\n\n"
          << e.explanation << "\n\n";
  }
  out << "## Exit status\n\n" << kExitCodes << "\n";
  return out.str();
}

namespace {
// Text as roff: a backslash is \e, a dash \- (so that man prints and searches a
// minus, not a hyphen), and a line starting with . or ' is escaped by \&.
std::string roff(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}
std::string upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

std::string help_man(const Usage& u) {
  std::ostringstream out;
  out << ".TH " << upper(u.name) << " 1 \"\" \"cdpile " << CDPILE_VERSION << "\" \"cdpile\"\n";
  out << ".SH NAME\n" << roff(u.name) << " \\- " << roff(u.synopsis) << "\n";
  out << ".SH SYNOPSIS\n" << roff(usage_line(u).substr(std::string("Usage: ").size())) << "\n";
  out << ".SH DESCRIPTION\n";
  for (const auto& para : u.description) out << ".PP\n" << roff(para) << "\n";
  if (!u.positionals.empty()) {
    out << ".SH ARGUMENTS\n";
    for (const auto& p : u.positionals)
      out << ".TP\n.B " << roff(upper(p.name)) << "\n" << roff(p.help) << "\n";
  }
  std::string group;
  for (const auto& o : u.options) {
    if (o.group != group) {
      group = o.group;
      out << ".SH " << roff(upper(group)) << "\n";
    }
    std::string label = option_label(o);
    label.erase(0, label.find_first_not_of(' '));
    out << ".TP\n.B " << roff(label) << "\n" << roff(option_detail(o)) << "\n";
  }
  if (!u.examples.empty()) {
    out << ".SH EXAMPLES\n";
    for (const auto& e : u.examples)
      out << ".PP\n"
          << roff(e.title) << ":\n.IP\n.nf\n"
          << roff(e.command) << "\n.fi\n.PP\n"
          << roff(e.explanation) << "\n";
  }
  out << ".SH EXIT STATUS\n" << roff(kExitCodes) << "\n";
  out << ".SH SEE ALSO\nThe cdpile manuals (docs/cli.md, docs/tools/" << roff(u.name)
      << ".md) and \\fB" << roff(u.name) << " \\-\\-help\\fR.\n";
  return out.str();
}

// ----------------------------------------------------------------------------------------
// Running

void check_output_is_not_an_input(const Args& a) {
  // Only an existing output can be an input; --force would otherwise replace the input
  // with the product read from it. Inputs are the arguments and the files named by text
  // options (--nu, --script A,B): a text option that is not a file never matches.
  const std::string& out = a.output();
  std::error_code ec;
  if (out.empty() || out == "-" || !std::filesystem::exists(out, ec)) return;
  std::vector<std::string> inputs;
  for (const auto& [name, values] : a.positional_)
    inputs.insert(inputs.end(), values.begin(), values.end());
  for (const auto& [name, kind] : a.kinds_)
    if (kind == Kind::text && name != "output")
      for (const auto& item : split_list(a.text(name))) inputs.push_back(item);
  for (const auto& in : inputs) {
    if (in.empty() || in == "-") continue;
    if (std::filesystem::equivalent(in, out, ec))
      throw UsageError("-o " + out + ": is also an input (" + in + "); write to another file");
  }
}

void refuse_output_named_twice(const Args& a, const std::string& option) {
  namespace fs = std::filesystem;
  const std::string &path = a.text(option), &out = a.output();
  if (path == out ||
      (path != "-" && !out.empty() && out != "-" &&  // no -o, or -o -: standard output
       fs::absolute(path).lexically_normal() == fs::absolute(out).lexically_normal()))
    throw UsageError("--" + option + " and -o name the same file " + path);
}

const std::string& tool_name() { return g_tool; }

void warn(const std::string& what) {
  std::cerr << g_tool << ": warning: " << printable(what) << std::endl;
}
void info(const std::string& what) {
  if (!g_quiet) std::cerr << g_tool << ": " << printable(what) << std::endl;
}

void defer_interrupts() { g_deferred.store(true); }
void end_deferral() { g_deferred.store(false); }
bool interrupted() { return g_interrupted != 0; }
int interrupt_exit_code() { return g_interrupted != 0 ? 128 + g_interrupted : 0; }

int run_tool(int argc, char** argv, const std::function<void(Usage&)>& declare, const Body& body) {
  std::string name = argc > 0 ? argv[0] : "cdpile";
  if (auto slash = name.rfind('/'); slash != std::string::npos) name = name.substr(slash + 1);
  g_tool = name;
  std::signal(SIGPIPE,
              SIG_IGN);  // a closed pipe is io::BrokenPipe: temporaries removed, then SIGPIPE
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  io::h5::silence_errors();
  set_field_spelling(option_of_field);  // the library's messages name fields by their options

  Usage usage;
  usage.name = name;
  try {
    declare(usage);
    add_standard_options(usage);
    if (usage.synopsis.empty()) throw std::logic_error("tool declares no synopsis");
  } catch (const std::exception& e) {
    std::cerr << name << ": internal error in the usage declaration: " << e.what() << std::endl;
    return 1;
  }
  std::vector<std::string> args(argv, argv + argc);
  for (std::size_t k = 1; k < args.size(); ++k) {
    if (args[k] == "--") break;
    if (args[k] == "--help" || args[k] == "-h") {
      std::cout << help_text(usage);
      return 0;
    }
    if (args[k] == "--help-markdown") {
      std::cout << help_markdown(usage);
      return 0;
    }
    if (args[k] == "--help-man") {
      std::cout << help_man(usage);
      return 0;
    }
    if (args[k] == "--version") {
      std::cout << name << " (cdpile) " << CDPILE_VERSION << "\n";
      return 0;
    }
  }
  try {
    Args a = parse(usage, args);
    check_output_is_not_an_input(a);
    g_quiet = a.quiet();
    if (a.given("author")) {
      if (io::parse_author(a.text("author")).name.empty())
        throw UsageError("--author: expected a name, got '" + a.text("author") + "'");
      io::set_author(a.text("author"));
    }
    const int code = body(a);
    if (std::fflush(stdout) != 0 || !std::cout.flush()) {
      if (errno == EPIPE) throw io::BrokenPipe();
      throw Error("stdout", "", "write failed");
    }
    return code;
  } catch (const io::BrokenPipe&) {
    // The reader has what it wanted (`| head`): end quietly, as coreutils do, with the
    // shell's status for SIGPIPE (141), which `set -o pipefail` treats like theirs.
    io::remove_temporaries();
    std::signal(SIGPIPE, SIG_DFL);
    std::raise(SIGPIPE);
    return 128 + SIGPIPE;
  } catch (const UsageError& e) {
    std::cerr << name << ": " << printable(e.what()) << " (see '" << name << " --help')"
              << std::endl;
    io::remove_temporaries();
    return 2;
  } catch (const Error& e) {
    std::cerr << name << ": " << printable(e.what()) << std::endl;
    io::remove_temporaries();
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << name << ": out of memory" << std::endl;
    io::remove_temporaries();
    return 1;
  } catch (const std::exception& e) {
    std::cerr << name << ": " << printable(e.what()) << std::endl;
    io::remove_temporaries();
    return 1;
  }
}

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  if (s.empty()) return out;
  std::size_t k = 0;
  while (true) {
    const std::size_t e = s.find(',', k);
    out.push_back(s.substr(k, e == std::string::npos ? std::string::npos : e - k));
    if (e == std::string::npos) break;
    k = e + 1;
  }
  return out;
}

}  // namespace cdpile::cli
