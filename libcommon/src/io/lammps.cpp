#include "cdpile/io/lammps.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/products.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>

namespace cdpile::io::lammps {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string> words(std::string_view s) {
  std::vector<std::string> out;
  std::size_t k = 0;
  while (k < s.size()) {
    while (k < s.size() && (s[k] == ' ' || s[k] == '\t' || s[k] == '\r')) ++k;
    if (k >= s.size()) break;
    std::size_t e = k;
    while (e < s.size() && s[e] != ' ' && s[e] != '\t' && s[e] != '\r') ++e;
    out.emplace_back(s.substr(k, e - k));
    k = e;
  }
  return out;
}

std::vector<std::string_view> split_lines(const std::string& text) {
  std::vector<std::string_view> out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t e = text.find('\n', pos);
    if (e == std::string::npos) e = text.size();
    out.emplace_back(text.data() + pos, e - pos);
    pos = e + 1;
  }
  return out;
}

std::string at_line(const std::string& file, std::size_t line) {
  return file + ": line " + std::to_string(line);
}

std::optional<std::int64_t> parse_integer(std::string_view s) {
  s = trim(s);
  std::int64_t v = 0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

bool starts_with(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }

}  // namespace

std::optional<std::size_t> Snapshot::find(const std::string& column) const {
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k] == column) return k;
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// Dumps

std::vector<Snapshot> parse_dump(const std::string& text, const std::string& file) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw Error(file, "", "empty: not a LAMMPS dump");
  if (text.find('\0') != std::string::npos)
    throw Error(file, "", "binary data: not a text LAMMPS dump");
  const auto lines = split_lines(text);
  std::vector<Snapshot> out;
  std::optional<Snapshot> cur;
  std::int64_t count = -1;  // rows announced by ITEM: NUMBER OF, -1 before it
  std::size_t k = 0;
  auto next_value = [&](const char* what) -> std::string_view {
    if (k + 1 >= lines.size())
      throw Error(at_line(file, k + 1), "", std::string("ends after ITEM: ") + what);
    return trim(lines[k + 1]);
  };
  auto need_open = [&](std::string_view item) {
    if (!cur)
      throw Error(at_line(file, k + 1), "",
                  "'" + std::string(item) + "' before any ITEM: TIMESTEP (not a LAMMPS dump?)");
  };
  while (k < lines.size()) {
    const std::string_view line = trim(lines[k]);
    if (line.empty()) {
      ++k;
      continue;
    }
    if (!starts_with(line, "ITEM:")) {
      throw Error(at_line(file, k + 1), "",
                  "expected an 'ITEM:' line, got '" + std::string(line.substr(0, 40)) + "'" +
                      (out.empty() && !cur ? " (not a LAMMPS text dump)" : ""));
    }
    const std::string_view item = trim(line.substr(5));
    if (item == "TIMESTEP") {
      const auto v = parse_integer(next_value("TIMESTEP"));
      if (!v) throw Error(at_line(file, k + 2), "", "TIMESTEP is not an integer");
      cur = Snapshot();
      cur->file = file;
      cur->first_line = k + 1;
      cur->step = *v;
      count = -1;
      k += 2;
    } else if (item == "TIME") {
      need_open(item);
      const auto v = parse_number(std::string(next_value("TIME")));
      if (!v) throw Error(at_line(file, k + 2), "", "TIME is not a number");
      cur->time = *v;
      k += 2;
    } else if (item == "UNITS") {
      need_open(item);
      cur->units = std::string(next_value("UNITS"));
      k += 2;
    } else if (starts_with(item, "NUMBER OF")) {
      need_open(item);
      const auto v = parse_integer(next_value("NUMBER OF"));
      if (!v || *v < 0)
        throw Error(at_line(file, k + 2), "", "the number of rows is not a non-negative integer");
      count = *v;
      k += 2;
    } else if (starts_with(item, "BOX BOUNDS")) {
      need_open(item);
      auto flags = words(item.substr(10));
      const bool triclinic = !flags.empty() && flags[0] == "xy";
      if (triclinic)
        flags.erase(flags.begin(), flags.begin() + std::min<std::size_t>(3, flags.size()));
      for (std::size_t d = 0; d < 3; ++d) {
        if (k + 1 + d >= lines.size())
          throw Error(at_line(file, k + 1), "", "box bounds cut short");
        const auto w = words(lines[k + 1 + d]);
        std::optional<double> lo, hi;
        if (w.size() >= 2) {
          lo = parse_number(w[0]);
          hi = parse_number(w[1]);
        }
        if (!lo || !hi) throw Error(at_line(file, k + 2 + d), "", "box bounds are not two numbers");
        cur->box[2 * d] = *lo;
        cur->box[2 * d + 1] = *hi;
        cur->boundary[d] = d < flags.size() ? flags[d] : "pp";
      }
      k += 4;
    } else if (starts_with(item, "ATOMS") || starts_with(item, "ENTRIES")) {
      need_open(item);
      const bool atoms = starts_with(item, "ATOMS");
      if (count < 0)
        throw Error(at_line(file, k + 1), "", "no 'ITEM: NUMBER OF ...' before the rows");
      cur->kind = atoms ? Snapshot::Kind::atoms : Snapshot::Kind::entries;
      cur->columns = words(item.substr(atoms ? 5 : 7));
      if (cur->columns.empty()) throw Error(at_line(file, k + 1), "", "no column names");
      for (std::size_t a = 0; a < cur->columns.size(); ++a)
        for (std::size_t b = 0; b < a; ++b)
          if (cur->columns[a] == cur->columns[b])
            throw Error(at_line(file, k + 1), "", "column '" + cur->columns[a] + "' appears twice");
      cur->values.assign(cur->columns.size(), {});
      const auto n = static_cast<std::size_t>(count);
      for (std::size_t r = 0; r < n; ++r) {
        const std::size_t at = k + 1 + r;
        if (at >= lines.size() || starts_with(trim(lines[at]), "ITEM:"))
          throw Error(at_line(file, std::min(at, lines.size()) + (at >= lines.size() ? 0 : 1)), "",
                      "step " + std::to_string(cur->step) + " ends after " + std::to_string(r) +
                          " of " + std::to_string(n) + " rows (a truncated dump?)");
        const auto w = words(lines[at]);
        if (w.size() != cur->columns.size())
          throw Error(at_line(file, at + 1), "",
                      std::to_string(w.size()) + " fields, the header has " +
                          std::to_string(cur->columns.size()));
        for (std::size_t c = 0; c < w.size(); ++c)
          cur->values[c].push_back(parse_number(w[c]).value_or(std::nan("")));
        cur->line.push_back(at + 1);
      }
      k += 1 + n;
      out.push_back(std::move(*cur));
      cur.reset();
    } else {
      // Another ITEM (a future LAMMPS): skipped to the next ITEM line.
      ++k;
      while (k < lines.size() && !starts_with(trim(lines[k]), "ITEM:")) ++k;
    }
  }
  if (cur)
    throw Error(at_line(file, cur->first_line), "",
                "step " + std::to_string(cur->step) + " has no rows section (truncated?)");
  return out;
}

// ---------------------------------------------------------------------------------------
// Scripts

namespace {

/// Words of a command line, quotes kept together (without the quotes).
std::vector<std::string> command_words(std::string_view s) {
  std::vector<std::string> out;
  std::size_t k = 0;
  while (k < s.size()) {
    while (k < s.size() && (s[k] == ' ' || s[k] == '\t' || s[k] == '\r')) ++k;
    if (k >= s.size()) break;
    if (s[k] == '"' || s[k] == '\'') {
      const char q = s[k];
      const bool triple = s.substr(k, 3) == std::string(3, q);
      const std::size_t open = triple ? 3 : 1;
      const std::size_t e = s.find(triple ? std::string(3, q) : std::string(1, q), k + open);
      out.emplace_back(s.substr(k + open, (e == std::string_view::npos ? s.size() : e) - k - open));
      k = e == std::string_view::npos ? s.size() : e + open;
      continue;
    }
    std::size_t e = k;
    while (e < s.size() && s[e] != ' ' && s[e] != '\t' && s[e] != '\r') ++e;
    out.emplace_back(s.substr(k, e - k));
    k = e;
  }
  return out;
}

std::string strip_comment(std::string_view s) {
  char quote = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (quote) {
      if (s[k] == quote) quote = 0;
    } else if (s[k] == '"' || s[k] == '\'') {
      quote = s[k];
    } else if (s[k] == '#') {
      return std::string(s.substr(0, k));
    }
  }
  return std::string(s);
}

void run_command(const std::vector<std::string>& w, const std::string& where,
                 const std::string& folder, Script& into, int depth);

void parse_lines(const std::string& text, const std::string& file, const std::string& folder,
                 Script& into, int depth) {
  const auto lines = split_lines(text);
  std::string joined;
  std::size_t first = 0;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    std::string part = strip_comment(lines[k]);
    std::string_view t = trim(part);
    if (joined.empty()) first = k + 1;
    if (!t.empty() && t.back() == '&') {
      joined += std::string(t.substr(0, t.size() - 1)) + " ";
      continue;
    }
    joined += std::string(t);
    const auto w = command_words(joined);
    joined.clear();
    if (!w.empty()) run_command(w, at_line(file, first), folder, into, depth);
  }
}

void run_command(const std::vector<std::string>& w, const std::string& where,
                 const std::string& folder, Script& into, int depth) {
  const std::string& cmd = w[0];
  if (cmd == "compute" && w.size() >= 4) {
    Script::Compute c;
    c.style = w[3];
    c.args.assign(w.begin() + 4, w.end());
    c.where = where;
    into.computes[w[1]] = c;
  } else if (cmd == "fix" && w.size() >= 4 && starts_with(w[3], "wall/gran")) {
    Script::WallFix f;
    for (std::size_t k = 4; k < w.size(); ++k) {
      if (w[k] == "xplane")
        f.axis = 'x';
      else if (w[k] == "yplane")
        f.axis = 'y';
      else if (w[k] == "zplane")
        f.axis = 'z';
      else if (w[k] == "contacts")
        f.contacts = true;
    }
    into.walls[w[1]] = f;
  } else if (cmd == "unfix" && w.size() >= 2) {
    into.walls.erase(w[1]);
  } else if (cmd == "pair_style" && w.size() >= 2) {
    into.pair_style = w[1];
  } else if (cmd == "units" && w.size() >= 2) {
    into.units = w[1];
  } else if (cmd == "timestep" && w.size() >= 2) {
    if (auto v = parse_number(w[1])) into.timestep = *v;
  } else if (cmd == "include" && w.size() >= 2 && w[1].find('$') == std::string::npos &&
             depth < 8) {
    const std::filesystem::path p = std::filesystem::path(folder) / w[1];
    if (std::filesystem::exists(p)) read_script(p.string(), into);
  } else if (cmd == "if") {
    // if "cond" then "cmd" "cmd" [elif "cond" "cmd" ...] [else "cmd" ...]: every branch's
    // commands are read (the condition is not evaluated).
    bool commands = false;
    for (std::size_t k = 2; k < w.size(); ++k) {
      if (w[k] == "then" || w[k] == "else") {
        commands = true;
        continue;
      }
      if (w[k] == "elif") {
        commands = false;
        ++k;
        commands = true;
        continue;
      }
      if (commands) parse_lines(w[k], where, folder, into, depth + 1);
    }
  }
}

}  // namespace

void parse_script(const std::string& text, const std::string& file, const std::string& folder,
                  Script& into) {
  parse_lines(text, file, folder, into, 0);
}

void read_script(const std::string& path, Script& into) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot read the input script");
  std::ostringstream ss;
  ss << in.rdbuf();
  parse_script(ss.str(), path, std::filesystem::path(path).parent_path().string(), into);
}

std::string length_unit_of(const std::string& style) {
  if (style == "si") return "m";
  if (style == "cgs") return "cm";
  if (style == "micro") return "um";
  if (style == "nano") return "nm";
  if (style == "real" || style == "metal") return "Ang";
  return "";
}

// ---------------------------------------------------------------------------------------
// Column roles

const std::vector<std::string>& entry_roles() {
  static const std::vector<std::string> r{"id1",   "id2", "fn",   "fnx",  "fny",  "ftx", "fty",
                                          "ftmag", "fx",  "fy",   "x1",   "y1",   "x2",  "y2",
                                          "px",    "py",  "wall", "dist", "delta"};
  return r;
}

namespace {

bool is_role(const std::string& s) {
  const auto& r = entry_roles();
  return std::find(r.begin(), r.end(), s) != r.end();
}

bool granular_pair_style(const std::string& s) { return starts_with(s, "gran") || s == "granular"; }

/// The roles of the values of one compute, in output order; `count` is how many columns of
/// it the header has (for LIGGGHTS' history, whose length depends on the pair style).
std::vector<std::string> compute_roles(const Script::Compute& c, const Script& s,
                                       std::size_t count) {
  std::vector<std::string> out;
  if (c.style == "property/local") {
    for (const auto& a : c.args) {
      if (a == "cutoff") break;
      out.push_back(a == "patom1" || a == "natom1"   ? "id1"
                    : a == "patom2" || a == "natom2" ? "id2"
                                                     : "");
    }
  } else if (c.style == "pair/local") {
    const bool gran = granular_pair_style(s.pair_style);
    for (const auto& a : c.args) {
      if (a == "cutoff") break;
      if (s.pair_style.empty() && a.size() > 1 && a[0] == 'p' &&
          std::isdigit(static_cast<unsigned char>(a[1])))
        throw Error(c.where, "",
                    "compute pair/local " + a +
                        ": its meaning depends on the pair style, which the "
                        "script does not set (read_restart?): give " +
                        field("pair_style"));
      if (a == "dist")
        out.push_back("dist");
      else if (a == "force")
        out.push_back("fn");
      else if (a == "fx")
        out.push_back("fnx");
      else if (a == "fy")
        out.push_back("fny");
      else if (gran && a == "p1")
        out.push_back("ftx");
      else if (gran && a == "p2")
        out.push_back("fty");
      else if (gran && a == "p4")
        out.push_back("ftmag");
      else
        out.push_back("");
    }
  } else if (c.style == "pair/gran/local" || c.style == "wall/gran/local") {
    const bool wall = c.style == "wall/gran/local";
    // LIGGGHTS (compute_pair_gran_local.cpp): without keywords pos vel id force torque
    // history contactArea; with keywords only those; values always in this order.
    std::set<std::string> on(c.args.begin(), c.args.end());
    if (c.args.empty()) on = {"pos", "vel", "id", "force", "torque", "history", "contactArea"};
    auto add = [&](std::initializer_list<const char*> v) {
      for (const char* x : v) out.push_back(x);
    };
    if (on.count("pos"))
      wall ? add({"px", "py", "", "x1", "y1", ""}) : add({"x1", "y1", "", "x2", "y2", ""});
    if (on.count("vel")) add({"", "", "", "", "", ""});
    if (on.count("id")) wall ? add({"wall", "", "id1"}) : add({"id1", "id2", ""});
    if (on.count("force")) add({"fx", "fy", ""});
    if (on.count("force_normal")) add({"fnx", "fny", ""});
    if (on.count("force_tangential")) add({"ftx", "fty", ""});
    if (on.count("torque")) add({"", "", ""});
    const std::size_t after = on.count("contactArea") + on.count("delta") + on.count("heatFlux");
    if (on.count("history"))
      for (std::size_t k = out.size(); k + after < count; ++k) out.push_back("");
    if (on.count("contactArea")) add({""});
    if (on.count("delta")) add({"delta"});
    if (on.count("heatFlux")) add({""});
  }
  return out;
}

/// "c_ID[3]" -> (ID, 3); "c_ID" -> (ID, 1); else empty.
std::optional<std::pair<std::string, std::size_t>> compute_column(const std::string& name) {
  if (!starts_with(name, "c_")) return std::nullopt;
  const auto b = name.find('[');
  if (b == std::string::npos) return std::make_pair(name.substr(2), std::size_t{1});
  if (name.back() != ']') return std::nullopt;
  const auto k = parse_integer(std::string_view(name).substr(b + 1, name.size() - b - 2));
  if (!k || *k < 1) return std::nullopt;
  return std::make_pair(name.substr(2, b - 2), static_cast<std::size_t>(*k));
}

}  // namespace

std::vector<std::string> entry_column_roles(
    const std::vector<std::string>& columns, const Script& script,
    const std::map<std::string, std::string>& explicit_roles, const std::string& where) {
  std::vector<std::string> roles(columns.size());
  std::map<std::string, std::size_t> per_compute;  // columns of each compute in this header
  for (const auto& c : columns)
    if (auto cc = compute_column(c)) ++per_compute[cc->first];
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const std::string& c = columns[k];
    if (auto it = explicit_roles.find(c); it != explicit_roles.end()) {
      roles[k] = it->second;
    } else if (is_role(c)) {
      roles[k] = c;
    } else if (auto cc = compute_column(c)) {
      auto it2 = script.computes.find(cc->first);
      if (it2 == script.computes.end()) continue;
      const auto r = compute_roles(it2->second, script, per_compute[cc->first]);
      if (cc->second > r.size())
        throw Error(where, "",
                    "column " + c + ": compute " + cc->first + " (" + it2->second.where + ") has " +
                        std::to_string(r.size()) + " values");
      roles[k] = r[cc->second - 1];
    }
  }
  for (std::size_t a = 0; a < roles.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (!roles[a].empty() && roles[a] == roles[b])
        throw Error(where, "",
                    "columns " + columns[b] + " and " + columns[a] + " both hold " + roles[a]);
  return roles;
}

// ---------------------------------------------------------------------------------------
// Conversion

namespace {

struct Vec {
  double x = 0, y = 0;
};

/// Columns of an atoms snapshot, found by name.
struct AtomColumns {
  std::size_t id = 0, x = 0, y = 0, size = 0;
  int coord = 0;  // 0 x y, 1 xu yu, 2 xs ys (scaled)
  bool diameter = false;
  std::optional<std::size_t> mass, fx, fy, theta;
};

std::string header_of(const Snapshot& s) {
  std::string h;
  for (const auto& c : s.columns) h += (h.empty() ? "" : " ") + c;
  return h;
}

AtomColumns atom_columns(const Snapshot& s, const ConvertOptions& opt) {
  AtomColumns a;
  const std::string where = at_line(s.file, s.first_line);
  auto need = [&](std::initializer_list<const char*> names,
                  const char* what) -> std::pair<std::size_t, int> {
    int k = 0;
    for (const char* n : names) {
      if (auto c = s.find(n)) return {*c, k};
      ++k;
    }
    throw Error(where, "",
                std::string("atoms of step ") + std::to_string(s.step) + " have no " + what +
                    " column (the header has: " + header_of(s) + ")");
  };
  a.id = need({"id"}, "id").first;
  auto [x, cx] = need({"x", "xu", "xs", "xsu"}, "x (x, xu or xs)");
  auto [y, cy] = need({"y", "yu", "ys", "ysu"}, "y (y, yu or ys)");
  a.x = x;
  a.y = y;
  a.coord = std::min(cx, 2);
  if (std::min(cy, 2) != a.coord)
    throw Error(where, "", "x and y are not of the same kind (scaled, unwrapped)");
  auto [r, cr] = need({"radius", "diameter"}, "radius (radius or diameter)");
  a.size = r;
  a.diameter = cr == 1;
  a.mass = s.find("mass");
  a.fx = s.find("fx");
  a.fy = s.find("fy");
  if (!opt.theta_column.empty()) {
    a.theta = s.find(opt.theta_column);
    if (!a.theta)
      throw Error(where, "",
                  "atoms of step " + std::to_string(s.step) + " have no column '" +
                      opt.theta_column + "' (" + field("theta_column") +
                      "; the header has: " + header_of(s) + ")");
  }
  return a;
}

std::string fmt(double v) { return format_number(v); }

/// Wall id from the wall's unit normal (pointing into the box): cdpile's -1 floor, -2 left,
/// -3 right, then -4 top, -5 any other wall.
std::int64_t wall_id(double nx, double ny) {
  constexpr double tol = 1e-6;
  if (std::abs(nx) < tol && ny > 1 - tol) return -1;
  if (std::abs(ny) < tol && nx > 1 - tol) return -2;
  if (std::abs(ny) < tol && nx < -1 + tol) return -3;
  if (std::abs(nx) < tol && ny < -1 + tol) return -4;
  return -5;
}

}  // namespace

namespace {

/// An atom id as LAMMPS writes it: an integer (tagint, at most 64 bits) held exactly by a
/// double; beyond 9e15 the conversion to int64 would be undefined (2.3e25 found by the
/// lammps harness, docs/fuzzing.md) or the id inexact.
bool is_atom_id(double v) { return v == std::floor(v) && std::abs(v) <= 9.0e15; }

// The stages of convert(), in its order: the snapshots of every dump sorted by step; per
// step, the atoms, the frame's tilt, the contacts of the dump local snapshots, those of the
// wall fixes' per-atom columns, the force check; last, the notes that say what the table
// is (docs/analysis.md, "LAMMPS and LIGGGHTS").

/// Every snapshot of the dumps, in the order of the files.
std::vector<Snapshot> parse_dumps(const std::vector<TextFile>& dumps) {
  std::vector<Snapshot> all;
  for (const auto& d : dumps)
    for (auto& s : parse_dump(d.text, d.name)) all.push_back(std::move(s));
  return all;
}

/// The snapshots by step: one atoms snapshot a step, any number of contact snapshots.
/// Points into the parsed snapshots, which outlive it.
struct SnapshotsByStep {
  std::map<std::int64_t, const Snapshot*> atoms;
  std::map<std::int64_t, std::vector<const Snapshot*>> entries;
};

SnapshotsByStep sort_by_step(const std::vector<Snapshot>& all, const std::vector<TextFile>& dumps) {
  SnapshotsByStep by;
  for (const Snapshot& s : all) {
    if (s.kind == Snapshot::Kind::atoms) {
      auto [it, fresh] = by.atoms.emplace(s.step, &s);
      if (!fresh)
        throw Error(at_line(s.file, s.first_line), "",
                    "a second atoms snapshot of step " + std::to_string(s.step) +
                        " (the first: " + at_line(it->second->file, it->second->first_line) + ")");
    } else {
      by.entries[s.step].push_back(&s);
    }
  }
  if (by.atoms.empty())
    throw Error(dumps.empty() ? std::string("from-lammps") : dumps.front().name, "",
                "no atoms snapshot (ITEM: ATOMS of a dump custom with id x y radius)");
  return by;
}

/// The wall fixes whose per-atom contact columns are read, with their axes: the script's
/// fixes with `contacts`, and --wall.
std::map<std::string, char> wall_fixes(const ConvertOptions& opt) {
  std::map<std::string, char> walls;
  for (const auto& [id, f] : opt.script.walls)
    if (f.contacts) walls[id] = f.axis;
  for (const auto& [id, axis] : opt.wall_axes) walls[id] = axis;
  return walls;
}

/// The steps that become frames: those with contacts, or every atoms step when no dump
/// has contacts (the walls' per-atom columns may then hold them all).
std::set<std::int64_t> frame_steps(const SnapshotsByStep& by) {
  std::set<std::int64_t> steps;
  for (const auto& [step, v] : by.entries) steps.insert(step);
  if (by.entries.empty())
    for (const auto& [step, s] : by.atoms) steps.insert(step);
  return steps;
}

/// What every frame adds to and reads from: the options, the table so far, and what the
/// notes will say of the tangential forces and the wall fixes.
struct Converting {
  const ConvertOptions& opt;
  Conversion& out;
  bool any_vector_ft = false, any_magnitude_ft = false;
  std::set<std::string> missing_walls{};  ///< wall fixes without per-atom columns
};

/// One frame being converted: its atoms (positions and radii by row, rows by id), its
/// tilt, and its rows with the force each puts on its atoms (for the force check).
struct DumpFrame {
  std::int64_t step = 0;
  const Snapshot& atoms;
  std::string where;  ///< the atoms snapshot's file and line, for messages
  AtomColumns columns{};
  std::map<std::int64_t, std::size_t> index{};  ///< atom id -> row of the atoms snapshot
  std::vector<Vec> pos{};
  std::vector<double> rad{};
  double lx = 0, ly = 0;
  bool periodic_x = false, periodic_y = false;
  std::optional<double> theta{};
  std::vector<Row> rows{};
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> seen{};  // pair -> index in rows
  std::vector<Vec> force{};    ///< the table's forces on each atom, for the check
  std::vector<bool> walled{};  ///< atoms touching a wall
};

/// The atoms of a step: their columns, ids, positions (unscaled) and radii.
DumpFrame read_frame_atoms(std::int64_t step, const Snapshot& A, const ConvertOptions& opt) {
  DumpFrame f{.step = step, .atoms = A, .where = at_line(A.file, A.first_line)};
  f.columns = atom_columns(A, opt);
  const AtomColumns& ac = f.columns;
  const std::size_t n = A.rows();
  f.pos.resize(n);
  f.rad.resize(n);
  f.force.resize(n);
  f.walled.assign(n, false);
  f.lx = A.box[1] - A.box[0];
  f.ly = A.box[3] - A.box[2];
  for (std::size_t r = 0; r < n; ++r) {
    const double idv = A.values[ac.id][r];
    if (!is_atom_id(idv))
      throw Error(at_line(A.file, A.line[r]), "",
                  "atom id " + fmt(idv) + " is not an integer of at most 9e15");
    if (!f.index.emplace(static_cast<std::int64_t>(idv), r).second)
      throw Error(at_line(A.file, A.line[r]), "",
                  "atom id " + fmt(idv) + " appears twice in step " + std::to_string(step));
    double x = A.values[ac.x][r], y = A.values[ac.y][r], s = A.values[ac.size][r];
    if (ac.coord == 2) {
      x = A.box[0] + x * f.lx;
      y = A.box[2] + y * f.ly;
    }
    if (!std::isfinite(x) || !std::isfinite(y) || !(s > 0))
      throw Error(at_line(A.file, A.line[r]), "",
                  "atom position or radius is not a finite, positive number");
    f.pos[r] = {x, y};
    f.rad[r] = ac.diameter ? 0.5 * s : s;
  }
  f.periodic_x = !A.boundary[0].empty() && A.boundary[0][0] == 'p';
  f.periodic_y = !A.boundary[1].empty() && A.boundary[1][0] == 'p';
  return f;
}

/// The tilt of a frame [deg]: rate x dt x step (or rate x the dump's TIME), or the atoms'
/// theta column, the same for every atom; none without either.
std::optional<double> frame_theta(const DumpFrame& f, const ConvertOptions& opt,
                                  std::optional<double> dt) {
  const Snapshot& A = f.atoms;
  if (opt.rate) {
    if (dt) return *opt.rate * *dt * static_cast<double>(f.step);
    if (A.time) return *opt.rate * *A.time;
    throw UsageError(field("rate") + " needs " + field("dt") +
                     " (theta = rate dt step): the script has no numeric timestep and the "
                     "dump no TIME");
  }
  if (!f.columns.theta) return std::nullopt;
  const auto& v = A.values[*f.columns.theta];
  const double theta = v.empty() ? 0.0 : v[0];
  for (std::size_t r = 0; r < A.rows(); ++r)
    if (!(v[r] == theta))
      throw Error(at_line(A.file, A.line[r]), "",
                  field("theta_column") + " " + opt.theta_column + " differs within step " +
                      std::to_string(f.step));
  return theta;
}

/// a - b, the minimum image in the box's periodic dimensions.
Vec branch(const DumpFrame& f, Vec a, Vec b) {
  Vec d{a.x - b.x, a.y - b.y};
  if (f.periodic_x && f.lx > 0) d.x -= f.lx * std::round(d.x / f.lx);
  if (f.periodic_y && f.ly > 0) d.y -= f.ly * std::round(d.y / f.ly);
  return d;
}

/// The row in the frame's atoms of the atom id `idv`, read at row r of snapshot s.
std::size_t atom_row(const DumpFrame& f, double idv, const Snapshot& s, std::size_t r) {
  if (!is_atom_id(idv))
    throw Error(at_line(s.file, s.line[r]), "",
                "atom id " + fmt(idv) + " is not an integer of at most 9e15");
  auto it = f.index.find(static_cast<std::int64_t>(idv));
  if (it == f.index.end())
    throw Error(at_line(s.file, s.line[r]), "",
                "atom " + fmt(idv) + " is not in the atoms of step " + std::to_string(f.step) +
                    " (" + f.where + ")");
  return it->second;
}

/// Adds a row between atoms a and b (b = a for a wall) with unit normal nrm from j to i.
/// A row listed twice (newton off, several ranks) is an error, or with --duplicates merge
/// is kept once if its forces agree.
void add_row(DumpFrame& f, Converting& c, Row row, std::size_t a, std::size_t b, bool pair,
             Vec nrm) {
  const std::pair<std::int64_t, std::int64_t> key =
      pair ? std::make_pair(std::min(row.i, row.j), std::max(row.i, row.j))
           : std::make_pair(row.i, row.j);
  if (auto it = f.seen.find(key); it != f.seen.end()) {
    const Row& first = f.rows[it->second];
    const std::string what = (pair ? "pair " : "wall contact ") + std::to_string(row.i) + "-" +
                             std::to_string(row.j) + " of step " + std::to_string(f.step);
    if (c.opt.duplicates == Duplicates::error)
      throw Error(row.where, "",
                  what + " is also at " + first.where +
                      " (newton off or several ranks list a pair twice: " + field("duplicates") +
                      " merge)");
    const double scale = std::max({std::abs(first.fn), std::abs(row.fn), 1e-300});
    if (std::abs(first.fn - row.fn) > 1e-9 * scale ||
        std::abs(std::abs(first.ft) - std::abs(row.ft)) > 1e-9 * scale)
      throw Error(row.where, "",
                  what + " is also at " + first.where + " with other forces: cannot merge");
    ++c.out.merged;
    return;
  }
  f.seen.emplace(key, f.rows.size());
  const Vec t{-nrm.y, nrm.x};
  const Vec force{row.fn * nrm.x + row.ft * t.x, row.fn * nrm.y + row.ft * t.y};
  f.force[a].x += force.x;
  f.force[a].y += force.y;
  if (pair) {
    f.force[b].x -= force.x;
    f.force[b].y -= force.y;
  } else {
    f.walled[a] = true;
  }
  f.rows.push_back(std::move(row));
}

/// The columns of a dump local snapshot by role (entry_column_roles, from the script or
/// --columns): the ids, the normal force (fn, its vector, or the total force), the
/// tangential force (its vector, the total force, or only its magnitude), the positions,
/// and a wall contact's point.
struct LocalColumns {
  bool wall = false;
  std::optional<std::size_t> id1, id2, fn, fnx, fny, ftx, fty, ftmag, fx, fy, x1, y1, x2, y2, px,
      py;
  bool normal_vec() const { return fnx && fny; }
  bool tangent_vec() const { return ftx && fty; }
  bool total() const { return fx && fy; }
};

LocalColumns local_columns(const Snapshot& E, const ConvertOptions& opt, const std::string& where) {
  const auto roles = entry_column_roles(E.columns, opt.script, opt.columns, where);
  auto col = [&](const char* role) -> std::optional<std::size_t> {
    for (std::size_t k = 0; k < roles.size(); ++k)
      if (roles[k] == role) return k;
    return std::nullopt;
  };
  LocalColumns k;
  k.wall = col("wall").has_value();
  k.id1 = col("id1");
  k.id2 = col("id2");
  k.fn = col("fn");
  k.fnx = col("fnx");
  k.fny = col("fny");
  k.ftx = col("ftx");
  k.fty = col("fty");
  k.ftmag = col("ftmag");
  k.fx = col("fx");
  k.fy = col("fy");
  k.x1 = col("x1");
  k.y1 = col("y1");
  k.x2 = col("x2");
  k.y2 = col("y2");
  k.px = col("px");
  k.py = col("py");
  return k;
}

/// Refuses a snapshot whose contacts lack a column they need, naming what it could be.
void require_local_columns(const LocalColumns& k, const Snapshot& E, std::int64_t step,
                           const std::string& where) {
  auto explain = [&](const std::string& what) {
    return "contacts of step " + std::to_string(step) + " have no " + what +
           " (the header has: " + header_of(E) + "; name the computes with " + field("script") +
           " or the columns with " + field("columns") + " NAME=ROLE)";
  };
  if (!k.id1 || (!k.wall && !k.id2))
    throw Error(where, "", explain(k.wall ? "particle id (id1)" : "atom ids (id1, id2)"));
  if (!k.fn && !k.normal_vec() && !k.total())
    throw Error(where, "", explain("normal force (fn, fnx fny, or the total force fx fy)"));
  if (!k.tangent_vec() && !k.total() && !k.ftmag)
    throw Error(where, "", explain("tangential force (ftx fty, ftmag, or the total force fx fy)"));
  if (k.wall && !(k.px && k.py))
    throw Error(where, "", explain("contact point of the wall contacts (px py: pos)"));
}

/// One contact of a dump local snapshot: its row, its atoms' rows a and b (b = a for a
/// wall) and its unit normal from j to i.
struct LocalContact {
  Row row;
  std::size_t a, b;
  Vec nrm;
};

/// Row r of a dump local snapshot as a contact: the normal along the branch vector (to the
/// wall's contact point, or between the centres), the contact point, and the forces
/// projected on (n, t).
LocalContact local_contact(const DumpFrame& f, const Snapshot& E, const LocalColumns& k,
                           std::size_t r) {
  auto v = [&](std::optional<std::size_t> c) {
    const double x = E.values[*c][r];
    if (!std::isfinite(x))
      throw Error(at_line(E.file, E.line[r]), "",
                  "column " + E.columns[*c] + " is not a finite number");
    return x;
  };
  const std::size_t a = atom_row(f, v(k.id1), E, r);
  Row row;
  row.frame = f.step;
  row.theta = f.theta;
  row.where = at_line(E.file, E.line[r]);
  row.i = static_cast<std::int64_t>(v(k.id1));
  const Vec p1 = k.x1 && k.y1 ? Vec{v(k.x1), v(k.y1)} : f.pos[a];
  Vec nrm, point;
  std::size_t b = a;
  if (k.wall) {
    const Vec pt{v(k.px), v(k.py)};
    const Vec d = branch(f, p1, pt);
    const double len = std::hypot(d.x, d.y);
    if (!(len > 0)) throw Error(row.where, "", "the wall contact point is the particle's centre");
    nrm = {d.x / len, d.y / len};
    point = pt;
    row.j = wall_id(nrm.x, nrm.y);
    row.wall = true;
  } else {
    b = atom_row(f, v(k.id2), E, r);
    row.j = static_cast<std::int64_t>(v(k.id2));
    if (row.j == row.i)
      throw Error(row.where, "", "a pair of atom " + std::to_string(row.i) + " with itself");
    const Vec p2 = k.x2 && k.y2 ? Vec{v(k.x2), v(k.y2)} : f.pos[b];
    const Vec d = branch(f, p1, p2);
    const double dist = std::hypot(d.x, d.y);
    if (!(dist > 0))
      throw Error(row.where, "",
                  "atoms " + std::to_string(row.i) + " and " + std::to_string(row.j) +
                      " are at the same place");
    nrm = {d.x / dist, d.y / dist};
    // The middle of the overlap on the line of centres: x_j + n (r_j - h/2).
    const double h = f.rad[a] + f.rad[b] - dist;
    const double sj = f.rad[b] - 0.5 * h;
    const Vec pj = {p1.x - d.x, p1.y - d.y};
    point = {pj.x + nrm.x * sj, pj.y + nrm.y * sj};
  }
  const Vec t{-nrm.y, nrm.x};
  row.x = point.x;
  row.y = point.y;
  if (k.fn)
    row.fn = v(k.fn);
  else if (k.normal_vec())
    row.fn = v(k.fnx) * nrm.x + v(k.fny) * nrm.y;
  else
    row.fn = v(k.fx) * nrm.x + v(k.fy) * nrm.y;
  if (k.tangent_vec())
    row.ft = v(k.ftx) * t.x + v(k.fty) * t.y;
  else if (k.total())
    row.ft = v(k.fx) * t.x + v(k.fy) * t.y;
  else
    row.ft = std::abs(v(k.ftmag));
  return {std::move(row), a, b, nrm};
}

/// The contacts of one dump local snapshot (LAMMPS pairs; LIGGGHTS pairs and mesh walls).
/// `pair_seen` and `wall_seen` refuse a second snapshot of either kind in one step.
void add_local_contacts(DumpFrame& f, Converting& c, const Snapshot& E, bool& pair_seen,
                        bool& wall_seen) {
  const std::string where = at_line(E.file, E.first_line);
  const LocalColumns k = local_columns(E, c.opt, where);
  if ((k.wall && wall_seen) || (!k.wall && pair_seen))
    throw Error(where, "",
                std::string("a second ") + (k.wall ? "wall" : "pair") +
                    " contacts snapshot of step " + std::to_string(f.step));
  (k.wall ? wall_seen : pair_seen) = true;
  require_local_columns(k, E, f.step, where);
  const bool signed_ft = k.tangent_vec() || k.total();
  (signed_ft ? c.any_vector_ft : c.any_magnitude_ft) = true;
  for (std::size_t r = 0; r < E.rows(); ++r) {
    LocalContact lc = local_contact(f, E, k, r);
    add_row(f, c, std::move(lc.row), lc.a, lc.b, !k.wall, lc.nrm);
    ++(k.wall ? c.out.wall_rows : c.out.pair_rows);
  }
}

/// The contacts of a wall fix (`fix wall/gran ... contacts`), from its per-atom columns in
/// the atoms snapshot: f_ID[1] the flag, [2..3] the force on the atom, [5..6] the contact
/// point. A fix whose columns are not dumped is an error if --wall names it, else a note.
void add_wall_fix_contacts(DumpFrame& f, Converting& c, const std::string& id, char axis) {
  const Snapshot& A = f.atoms;
  const std::string col = "f_" + id + "[";
  const auto flag = A.find(col + "1]"), wfx = A.find(col + "2]"), wfy = A.find(col + "3]"),
             wpx = A.find(col + "5]"), wpy = A.find(col + "6]");
  if (!flag || !wfx || !wfy) {
    if (c.opt.wall_axes.count(id))
      throw Error(f.where, "",
                  field("wall") + " " + id + ": the atoms of step " + std::to_string(f.step) +
                      " have no " + col + "1] " + col + "2] " + col +
                      "3] (dump them: the contact flag and the force)");
    c.missing_walls.insert(id);
    return;
  }
  const bool have_point = wpx && wpy;
  if (!have_point && axis != 'x' && axis != 'y')
    throw Error(f.where, "",
                "wall " + id + " is not a plane along x or y: dump its contact point, " + col +
                    "5] " + col + "6]");
  const double mid = axis == 'x' ? 0.5 * (A.box[0] + A.box[1]) : 0.5 * (A.box[2] + A.box[3]);
  for (std::size_t r = 0; r < A.rows(); ++r) {
    if (!(A.values[*flag][r] > 0.5)) continue;
    const Vec force{A.values[*wfx][r], A.values[*wfy][r]};
    Row row;
    row.frame = f.step;
    row.theta = f.theta;
    row.where = at_line(A.file, A.line[r]);
    row.i = static_cast<std::int64_t>(A.values[f.columns.id][r]);
    row.wall = true;
    Vec nrm, point;
    if (have_point) {
      point = {A.values[*wpx][r], A.values[*wpy][r]};
      const Vec d = branch(f, f.pos[r], point);
      const double len = std::hypot(d.x, d.y);
      if (!(len > 0)) throw Error(row.where, "", "the wall contact point is the particle's centre");
      nrm = {d.x / len, d.y / len};
    } else {
      // A plane normal to `axis`: the wall pushes the grain away from it, so the sign
      // of that force component tells the side (else the grain's side of the box).
      const double fa = axis == 'x' ? force.x : force.y, c0 = axis == 'x' ? f.pos[r].x : f.pos[r].y;
      const double sgn = fa != 0 ? (fa > 0 ? 1.0 : -1.0) : (c0 < mid ? 1.0 : -1.0);
      nrm = axis == 'x' ? Vec{sgn, 0} : Vec{0, sgn};
      point = {f.pos[r].x - f.rad[r] * nrm.x, f.pos[r].y - f.rad[r] * nrm.y};
    }
    const Vec t{-nrm.y, nrm.x};
    row.j = wall_id(nrm.x, nrm.y);
    row.x = point.x;
    row.y = point.y;
    row.fn = force.x * nrm.x + force.y * nrm.y;
    row.ft = force.x * t.x + force.y * t.y;
    c.any_vector_ft = true;
    add_row(f, c, std::move(row), r, r, false, nrm);
    ++c.out.wall_rows;
  }
}

/// --check: each atom's table forces plus its weight m g, tilted by the frame's theta,
/// against the dump's fx, fy; fails beyond the tolerance, which a contact or a wall
/// missing from the dumps, another force or the wrong tilt would exceed.
FrameCheck check_frame_forces(const DumpFrame& f, const Converting& c) {
  const ConvertOptions& opt = c.opt;
  const Snapshot& A = f.atoms;
  const AtomColumns& ac = f.columns;
  if (!ac.mass || !ac.fx || !ac.fy)
    throw Error(f.where, "",
                field("check") +
                    " needs the atoms' mass, fx and fy (the header has: " + header_of(A) + ")");
  if (c.any_magnitude_ft)
    throw Error(f.where, "",
                field("check") + " needs signed tangential forces; the contacts give only |f_t|");
  FrameCheck fc;
  fc.step = f.step;
  const double th = f.theta.value_or(0.0) * M_PI / 180.0;
  for (std::size_t r = 0; r < A.rows(); ++r) {
    const double m = A.values[*ac.mass][r];
    const double mg = m * opt.gravity;
    const Vec total{f.force[r].x + mg * std::sin(th), f.force[r].y - mg * std::cos(th)};
    const double diff =
        std::hypot(total.x - A.values[*ac.fx][r], total.y - A.values[*ac.fy][r]) / std::abs(mg);
    if (!std::isfinite(diff))
      throw Error(at_line(A.file, A.line[r]), "",
                  "mass, fx or fy is not a finite number (or the mass is 0)");
    ++fc.grains;
    if (diff > fc.worst_all) {
      fc.worst_all = diff;
      fc.worst_id = static_cast<std::int64_t>(A.values[ac.id][r]);
    }
    if (!f.walled[r]) {
      ++fc.grains_free;
      fc.worst_free = std::max(fc.worst_free, diff);
    }
  }
  if (fc.worst_all > opt.check_tolerance)
    throw Error(f.where, "",
                "step " + std::to_string(f.step) + ": atom " + std::to_string(fc.worst_id) +
                    ": the table's contact forces plus m g differ from the dump's fx, fy by " +
                    fmt(fc.worst_all) + " m g (tolerance " + fmt(opt.check_tolerance) +
                    "; a contact or a wall missing from the dumps, another force, or the wrong "
                    "tilt?)");
  return fc;
}

/// The table's notes: what its columns mean, where theta comes from, what is missing.
void add_notes(Conversion& out, const Converting& c) {
  out.notes.push_back(
      "contacts of a LAMMPS or LIGGGHTS run: frame = the LAMMPS step, i and j the atom ids; j < 0 "
      "is a wall: -1 floor, -2 left, -3 right, -4 top, -5 another wall (wall = 1)");
  out.notes.push_back(
      "x y: the contact point (pairs: the middle of the overlap on the line of centres, "
      "x_j + n (r_j - h/2); walls: on the wall); n is the unit normal from j to i");
  out.notes.push_back(out.ft_signed
                          ? "fn = F.n, ft = F.t with F the contact force on i and t = (-n_y, n_x)"
                          : "fn = F.n with F the contact force on i; ft = |f_t| (the dumps give no "
                            "tangential force vector)");
  if (out.has_theta)
    out.notes.push_back(c.opt.rate ? "theta = rate x dt x step (deg)"
                                   : "theta from the atoms column " + c.opt.theta_column);
  for (const auto& id : c.missing_walls)
    out.notes.push_back(
        "wall fix " + id +
        ": its per-atom columns are not in the atoms dump; its contacts are missing");
  if (out.merged > 0)
    out.notes.push_back(std::to_string(out.merged) + " repeated rows merged (" +
                        field("duplicates") + " merge)");
}

}  // namespace

Conversion convert(const std::vector<TextFile>& dumps, const ConvertOptions& opt) {
  Conversion out;
  const std::vector<Snapshot> all = parse_dumps(dumps);
  const SnapshotsByStep by = sort_by_step(all, dumps);
  const std::map<std::string, char> walls = wall_fixes(opt);
  const std::optional<double> dt = opt.dt ? opt.dt : opt.script.timestep;
  out.has_theta = opt.rate.has_value() || !opt.theta_column.empty();
  out.length_unit = length_unit_of(opt.script.units);
  if (out.length_unit.empty() && opt.script.units.empty())
    out.length_unit = length_unit_of(by.atoms.begin()->second->units);
  Converting c{.opt = opt, .out = out};

  for (const std::int64_t step : frame_steps(by)) {
    const auto atoms = by.atoms.find(step);
    const auto entries = by.entries.find(step);
    if (atoms == by.atoms.end()) {
      const Snapshot& e = *entries->second.front();
      throw Error(at_line(e.file, e.first_line), "",
                  "contacts of step " + std::to_string(step) +
                      " but no atoms snapshot of that step (dump the atoms "
                      "at the same steps as the contacts)");
    }
    DumpFrame f = read_frame_atoms(step, *atoms->second, opt);
    f.theta = frame_theta(f, opt, dt);
    bool pair_seen = false, wall_seen = false;
    if (entries != by.entries.end())
      for (const Snapshot* E : entries->second) add_local_contacts(f, c, *E, pair_seen, wall_seen);
    for (const auto& [id, axis] : walls) add_wall_fix_contacts(f, c, id, axis);
    if (opt.check) out.checks.push_back(check_frame_forces(f, c));
    for (auto& r : f.rows) out.rows.push_back(std::move(r));
    ++out.frames;
  }
  out.ft_signed = !c.any_magnitude_ft;
  if (c.any_magnitude_ft && c.any_vector_ft)
    throw Error(dumps.front().name, "",
                "some contacts give a signed ft and others only |f_t|: map the tangential "
                "force vector (ftx fty) for every dump");
  add_notes(out, c);
  return out;
}

void write_table(std::ostream& os, const Conversion& c,
                 const std::vector<std::string>& header_comments) {
  for (const auto& h : header_comments) os << "# " << h << '\n';
  for (const auto& n : c.notes) os << "# " << n << '\n';
  if (!c.length_unit.empty()) os << "# length_unit: " << c.length_unit << '\n';
  os << "frame\t" << (c.has_theta ? "theta\t" : "") << "i\tj\twall\tx\ty\tfn\tft\n";
  std::string line;
  for (const Row& r : c.rows) {
    line = std::to_string(r.frame) + '\t';
    if (c.has_theta) line += fmt(r.theta.value_or(0.0)) + '\t';
    line += std::to_string(r.i) + '\t' + std::to_string(r.j) + '\t' + (r.wall ? "1" : "0") + '\t' +
            fmt(r.x) + '\t' + fmt(r.y) + '\t' + fmt(r.fn) + '\t' + fmt(r.ft) + '\n';
    os << line;
  }
}

// ---------------------------------------------------------------------------------------
// Export

std::size_t write_dump(std::ostream& os, const RunReader& run, const ExportOptions& opt) {
  const std::size_t frames = run.frame_count();
  const Grains& g = run.grain_properties();
  const std::size_t n = g.size();
  double r_max = 0;
  for (double r : g.radius) r_max = std::max(r_max, r);
  const double width = run.header().box.width;
  const std::size_t first = opt.first.value_or(0),
                    last = std::min(opt.last.value_or(frames ? frames - 1 : 0),
                                    frames ? frames - 1 : 0);
  const std::size_t every = std::max<std::size_t>(opt.every, 1);
  std::size_t written = 0;
  for (std::size_t k = first; frames > 0 && k <= last; k += every) {
    const Frame fr = run.frame(k);
    double ylo = 0, yhi = run.header().box.height;
    for (std::size_t q = 0; q < n; ++q) {
      ylo = std::min(ylo, fr.grains.position[q].y() - g.radius[q]);
      yhi = std::max(yhi, fr.grains.position[q].y() + g.radius[q]);
    }
    os << "ITEM: TIMESTEP\n"
       << fr.step << "\nITEM: NUMBER OF ATOMS\n"
       << n << "\nITEM: BOX BOUNDS ff ff pp\n0 " << fmt(width) << '\n'
       << fmt(ylo) << ' ' << fmt(yhi) << '\n'
       << fmt(-r_max) << ' ' << fmt(r_max)
       << "\nITEM: ATOMS id type x y z radius vx vy vz omegaz mass\n";
    for (std::size_t q = 0; q < n; ++q) {
      os << q + 1 << ' ' << static_cast<int>(g.species[q]) + 1 << ' '
         << fmt(fr.grains.position[q].x()) << ' ' << fmt(fr.grains.position[q].y()) << " 0 "
         << fmt(g.radius[q]) << ' ' << fmt(fr.grains.velocity[q].x()) << ' '
         << fmt(fr.grains.velocity[q].y()) << " 0 " << fmt(fr.grains.angular_velocity[q]) << ' '
         << fmt(g.mass[q]) << '\n';
    }
    ++written;
  }
  return written;
}

namespace {
/// The frames an export writes: first..last (clamped to the run) every `every`.
std::vector<std::size_t> export_frames(std::size_t frames, const ExportOptions& opt) {
  std::vector<std::size_t> ks;
  if (frames == 0) return ks;
  const std::size_t last = std::min(opt.last.value_or(frames - 1), frames - 1);
  for (std::size_t k = opt.first.value_or(0); k <= last; k += std::max<std::size_t>(opt.every, 1))
    ks.push_back(k);
  return ks;
}
}  // namespace

std::size_t write_contacts_dump(std::ostream& os, const RunReader& run, const ExportOptions& opt,
                                const IsCritical& critical) {
  const Grains& g = run.grain_properties();
  const std::size_t n = g.size();
  double r_max = 0;
  for (double r : g.radius) r_max = std::max(r_max, r);
  const double width = run.header().box.width;
  std::size_t written = 0;
  for (std::size_t k : export_frames(run.frame_count(), opt)) {
    const Frame fr = run.frame(k);
    const Contacts& c = fr.contacts;
    double ylo = 0, yhi = run.header().box.height;  // the atoms dump's box, frame for frame
    for (std::size_t q = 0; q < n; ++q) {
      ylo = std::min(ylo, fr.grains.position[q].y() - g.radius[q]);
      yhi = std::max(yhi, fr.grains.position[q].y() + g.radius[q]);
    }
    std::size_t pairs = 0;
    for (std::size_t q = 0; q < c.size(); ++q) pairs += c.j[q] >= 0 ? 1 : 0;
    os << "ITEM: TIMESTEP\n"
       << fr.step << "\nITEM: NUMBER OF ENTRIES\n"
       << pairs << "\nITEM: BOX BOUNDS ff ff pp\n0 " << fmt(width) << '\n'
       << fmt(ylo) << ' ' << fmt(yhi) << '\n'
       << fmt(-r_max) << ' ' << fmt(r_max) << "\nITEM: ENTRIES id1 id2 fn ft critical\n";
    // Grain-grain contacts only: a bond needs two atoms, and a wall is none.
    for (std::size_t q = 0; q < c.size(); ++q) {
      if (c.j[q] < 0) continue;
      os << c.i[q] + 1 << ' ' << c.j[q] + 1 << ' ' << fmt(c.fn[q]) << ' ' << fmt(c.ft[q]) << ' '
         << (critical(c.fn[q], c.ft[q]) ? 1 : 0) << '\n';
    }
    ++written;
  }
  return written;
}

}  // namespace cdpile::io::lammps
