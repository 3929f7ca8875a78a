#include "cdpile/io/products.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/contact_table.hpp"

#include <hdf5.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>

namespace cdpile::io {

using analysis::Column;
using analysis::ColumnKind;
using analysis::Product;
using analysis::Table;

std::string format_number(double v, int digits) {
  if (!std::isfinite(v)) return missing_marker;
  if (v == 0.0) return "0";  // also -0
  char buf[64];
  if (digits > 0) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
  }
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  if (ec != std::errc()) return missing_marker;
  return std::string(buf, p);
}

namespace {

std::string clean(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return s;
}

std::string value_text(const analysis::Value& v, int digits = 0) {
  if (auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (auto* d = std::get_if<double>(&v)) return format_number(*d, digits);
  return clean(std::get<std::string>(v));
}

analysis::Value parse_value(const std::string& s) {
  if (auto d = parse_number(s)) {
    if (s.find_first_of(".eE") == std::string::npos && std::abs(*d) < 9e15)
      return static_cast<std::int64_t>(*d);
    return *d;
  }
  return s;
}

void write_header_lines(std::ostream& os, const Product& p, const std::vector<Provenance>& history,
                        int digits) {
  if (!history.empty()) {
    const Provenance& me = history.back();
    os << "# tool: " << clean(me.tool) << ' ' << clean(me.version) << '\n';
    os << "# command: " << clean(me.command_line) << '\n';
    os << "# input: " << clean(me.inputs) << '\n';
  } else {
    os << "# tool: " << p.kind << '\n';
  }
  os << "# kind: " << p.kind << '\n';
  for (const Provenance& h : history) {
    os << "# provenance: " << clean(h.tool) << '\t' << clean(h.version) << '\t' << clean(h.date)
       << '\t' << clean(h.inputs) << '\t' << clean(h.command_line);
    if (!h.via.empty()) os << '\t' << clean(h.via);  // a sixth field, only after a merge
    os << '\n';
  }
  for (const auto& [k, v] : p.parameters)
    os << "# parameter " << k << " = " << value_text(v) << '\n';
  for (const auto& [k, v] : p.results)
    os << "# result " << k << " = " << value_text(v, digits) << '\n';
  for (const auto& n : p.notes) os << "# note: " << clean(n) << '\n';
}

void write_table(std::ostream& os, const Table& t, int digits) {
  const std::size_t rows = t.rows();
  os << "# table: " << t.name << '\n';
  if (!t.title.empty()) os << "# about: " << clean(t.title) << '\n';
  os << "# columns:";
  for (const Column& c : t.columns)
    os << ' ' << c.name << " ["
       << (c.kind == ColumnKind::text ? "text"
           : c.unit.empty()           ? "-"
                                      : c.unit)
       << ']';
  os << '\n';
  for (std::size_t k = 0; k < t.columns.size(); ++k) os << (k ? "\t" : "") << t.columns[k].name;
  os << '\n';
  std::string line;
  for (std::size_t r = 0; r < rows; ++r) {
    line.clear();
    for (std::size_t k = 0; k < t.columns.size(); ++k) {
      const Column& c = t.columns[k];
      if (k) line += '\t';
      if (c.kind == ColumnKind::text) {
        line += c.text[r].empty() ? std::string("-") : clean(c.text[r]);
      } else if (c.kind == ColumnKind::integer && std::isfinite(c.num[r])) {
        line += std::to_string(static_cast<std::int64_t>(c.num[r]));
      } else {
        line += format_number(c.num[r], digits);
      }
    }
    line += '\n';
    os << line;
  }
}

}  // namespace

void write_tsv(std::ostream& os, const Product& p, const std::vector<Provenance>& history,
               const std::vector<std::string>& only, bool header, int digits) {
  for (const auto& name : only) p.table(name);  // error if unknown
  auto written = [&](const Table& t) {
    return only.empty() || std::find(only.begin(), only.end(), t.name) != only.end();
  };
  bool first = true;
  if (header) {
    write_header_lines(os, p, history, digits);
    // The tables and their row counts, so a reader can tell a file cut at a line boundary
    // (a table short of rows, or missing) from a whole one.
    os << "# tables:";
    for (const Table& t : p.tables)
      if (written(t)) os << ' ' << t.name << '=' << t.rows();
    os << '\n';
    first = false;
  }
  for (const Table& t : p.tables) {
    if (!written(t)) continue;
    if (!first) os << "\n\n";  // gnuplot's index counts blocks separated by two blank lines
    first = false;
    write_table(os, t, digits);
  }
}

// ---------------------------------------------------------------------------------

void write_hdf5(const h5::File& f, const Product& p, const std::vector<Provenance>& history) {
  RunHeader h;
  h.kind = p.kind;
  h.parameters = p.parameters;
  h.results = p.results;
  h.provenance = history;
  write_header(f, h);
  h5::create_group(f, "/tables");
  std::vector<std::string> names;
  for (const Table& t : p.tables) names.push_back(t.name);
  h5::set_attr(f, "/tables", "tables", names);
  h5::set_attr(f, "/tables", "notes", p.notes);
  for (const Table& t : p.tables) {
    const std::size_t rows = t.rows();
    const std::string g = "/tables/" + t.name;
    h5::create_group(f, g);
    h5::set_attr(f, g, "title", t.title);
    std::vector<std::string> cols;
    for (const Column& c : t.columns) cols.push_back(c.name);
    h5::set_attr(f, g, "columns", cols);
    h5::Layout layout;
    if (rows >= 1024) layout = {4096, 4};
    const std::vector<hsize_t> dims = {static_cast<hsize_t>(rows)};
    for (const Column& c : t.columns) {
      const std::string path = g + "/" + c.name;
      if (c.kind == ColumnKind::text) {
        std::vector<std::string> labels;
        std::vector<std::uint8_t> code(rows);
        for (std::size_t r = 0; r < rows; ++r) {
          auto it = std::find(labels.begin(), labels.end(), c.text[r]);
          if (it == labels.end()) {
            if (labels.size() == 255) throw Error(f.name(), path, "more than 255 distinct labels");
            labels.push_back(c.text[r]);
            it = labels.end() - 1;
          }
          code[r] = static_cast<std::uint8_t>(it - labels.begin());
        }
        h5::write(f, path, code.data(), dims, layout);
        h5::set_attr(f, path, "labels", labels);
        h5::set_attr(f, path, "unit", std::string(""));
        continue;
      }
      std::vector<std::uint8_t> defined(rows, 1);
      bool any_missing = false;
      for (std::size_t r = 0; r < rows; ++r)
        if (!std::isfinite(c.num[r])) {
          defined[r] = 0;
          any_missing = true;
        }
      if (c.kind == ColumnKind::integer) {
        std::vector<std::int64_t> v(rows);
        for (std::size_t r = 0; r < rows; ++r)
          v[r] = defined[r] ? static_cast<std::int64_t>(c.num[r]) : 0;
        h5::write(f, path, v.data(), dims, layout);
      } else {
        std::vector<double> v(rows);
        for (std::size_t r = 0; r < rows; ++r) v[r] = defined[r] ? c.num[r] : 0.0;
        h5::write(f, path, v.data(), dims, layout);
      }
      h5::set_attr(f, path, "unit", c.unit);
      if (any_missing) {
        h5::write(f, path + "_defined", defined.data(), dims, layout);
        h5::set_attr(
            f, path, "missing",
            std::string("rows where " + c.name + "_defined is 0 have no value (stored as 0)"));
      }
    }
  }
}

ProductFile read_product_hdf5(const h5::File& f) {
  ProductFile out;
  RunHeader h = read_header(f);
  Product& p = out.product;
  p.kind = h.kind;
  p.parameters = h.parameters;
  p.results = h.results;
  p.source = f.name();
  out.provenance = h.provenance;
  if (!h5::exists(f, "/tables"))
    throw Error(f.name(), "/tables",
                "missing group (is this an analysis product? it is a '" + h.kind + "' file)");
  if (h5::has_attr(f, "/tables", "notes")) p.notes = h5::attr_strings(f, "/tables", "notes");
  const auto names = h5::has_attr(f, "/tables", "tables") ? h5::attr_strings(f, "/tables", "tables")
                                                          : h5::members(f, "/tables");
  for (const auto& name : names) {
    const std::string g = "/tables/" + name;
    if (!h5::exists(f, g)) throw Error(f.name(), g, "missing group");
    Table& t = p.add_table(name, h5::has_attr(f, g, "title") ? h5::attr_string(f, g, "title") : "");
    const auto cols = h5::attr_strings(f, g, "columns");
    std::optional<hsize_t> rows;
    for (const auto& cn : cols) {
      const std::string path = g + "/" + cn;
      if (!h5::exists(f, path)) throw Error(f.name(), path, "missing column dataset");
      std::vector<hsize_t> dims;
      const std::string unit =
          h5::has_attr(f, path, "unit") ? h5::attr_string(f, path, "unit") : "";
      ColumnKind kind = ColumnKind::real;
      if (h5::has_attr(f, path, "labels")) {
        kind = ColumnKind::text;
      } else {
        h5::Handle d(H5Dopen2(f.id(), path.c_str(), H5P_DEFAULT));
        if (!d.valid()) throw Error(f.name(), path, "cannot open dataset");
        h5::Handle ty(H5Dget_type(d.id()));
        if (H5Tget_class(ty.id()) == H5T_INTEGER) kind = ColumnKind::integer;
      }
      Column& c = t.add_column(cn, unit, kind);
      if (kind == ColumnKind::text) {
        auto code = h5::read<std::uint8_t>(f, path, {h5::any}, &dims);
        auto labels = h5::attr_strings(f, path, "labels");
        for (auto k : code) {
          if (k >= labels.size()) throw Error(f.name(), path, "label code out of range");
          c.text.push_back(labels[k]);
        }
      } else {
        c.num = h5::read<double>(f, path, {h5::any}, &dims);  // finite, or refused
        // An integer column is held as doubles, and read back as ids and counts: within
        // 2^53, where a double holds every integer (docs/schema.md, "Ranges").
        if (kind == ColumnKind::integer)
          for (std::size_t r = 0; r < c.num.size(); ++r)
            if (!(std::fabs(c.num[r]) <= 9007199254740992.0))
              throw Error(f.name(), path,
                          "row " + std::to_string(r) + ": " + format_number(c.num[r]) +
                              " is outside [-2^53, 2^53]");
        if (h5::exists(f, path + "_defined")) {
          auto def = h5::read<std::uint8_t>(f, path + "_defined", {dims[0]});
          // {0} in a shape matches any extent: an empty column needs its own check (found
          // by the structure mutator, docs/fuzzing.md)
          if (def.size() != c.num.size())
            throw Error(f.name(), path + "_defined",
                        "holds " + std::to_string(def.size()) + " rows, its column " +
                            std::to_string(c.num.size()));
          for (std::size_t r = 0; r < def.size(); ++r)
            if (!def[r]) c.num[r] = std::numeric_limits<double>::quiet_NaN();
        }
      }
      if (rows && *rows != dims[0])
        throw Error(f.name(), path, "column length differs from the table's");
      rows = dims[0];
    }
  }
  return out;
}

ProductFile read_product_tsv(const std::string& text, const std::string& name) {
  // Text columns are marked [text] in the columns lines: find them first.
  TextTableOptions opt;
  opt.allow_missing = true;
  {
    std::istringstream is(text);
    std::string line;
    while (std::getline(is, line)) {
      if (line.rfind("# columns:", 0) != 0) continue;
      std::size_t pos = 10;
      while (true) {
        const std::size_t b = line.find('[', pos);
        if (b == std::string::npos) break;
        const std::size_t e = line.find(']', b);
        if (e == std::string::npos) break;
        std::string col = line.substr(pos, b - pos);
        while (!col.empty() && col.front() == ' ') col.erase(col.begin());
        while (!col.empty() && col.back() == ' ') col.pop_back();
        if (line.substr(b + 1, e - b - 1) == "text") opt.text_columns.push_back(col);
        pos = e + 1;
      }
    }
  }
  auto tables = parse_text_tables(text, name, opt);
  ProductFile out;
  Product& p = out.product;
  p.source = name;
  bool header_seen = false;
  std::vector<std::pair<std::string, std::size_t>> declared;  // "# tables:" of the header
  for (std::size_t ti = 0; ti < tables.size(); ++ti) {
    const TextTable& tt = tables[ti];
    std::map<std::string, std::string> units;
    std::string title;
    for (const std::string& c : tt.comments) {
      auto after = [&](const char* key) -> std::optional<std::string> {
        const std::string k(key);
        if (c.rfind(k, 0) != 0) return std::nullopt;
        std::string v = c.substr(k.size());
        while (!v.empty() && v.front() == ' ') v.erase(v.begin());
        return v;
      };
      if (auto v = after("kind:")) {
        p.kind = *v;
        header_seen = true;
      } else if (auto v8 = after("tables:")) {
        std::istringstream items(*v8);
        std::string item;
        while (items >> item) {
          const auto eq = item.find('=');
          const auto rows =
              eq == std::string::npos ? std::nullopt : parse_number(item.substr(eq + 1));
          // a count of rows: an integer, and one a double holds (found by the value
          // mutations: 1e300 rows was converted to a size, docs/fuzzing.md)
          if (!rows || !(*rows >= 0 && *rows <= 9007199254740992.0) || *rows != std::floor(*rows))
            throw Error(name, "", "bad '# tables:' entry '" + item + "'");
          declared.emplace_back(item.substr(0, eq), static_cast<std::size_t>(*rows));
        }
      } else if (auto v2 = after("parameter ")) {
        const auto eq = v2->find(" = ");
        if (eq != std::string::npos)
          p.parameters[v2->substr(0, eq)] = parse_value(v2->substr(eq + 3));
      } else if (auto v3 = after("result ")) {
        const auto eq = v3->find(" = ");
        if (eq != std::string::npos) p.results[v3->substr(0, eq)] = parse_value(v3->substr(eq + 3));
      } else if (auto v4 = after("note:")) {
        p.notes.push_back(*v4);
      } else if (auto v5 = after("provenance:")) {
        std::vector<std::string> f;
        std::size_t k = 0;
        while (true) {
          const std::size_t e = v5->find('\t', k);
          f.push_back(v5->substr(k, e == std::string::npos ? std::string::npos : e - k));
          if (e == std::string::npos) break;
          k = e + 1;
        }
        if (f.size() == 5 || f.size() == 6)
          out.provenance.push_back(
              {f[0], f[1], f[4], f[3], f[2], f.size() == 6 ? f[5] : std::string()});
      } else if (auto v6 = after("about:")) {
        title = *v6;
      } else if (auto v7 = after("columns:")) {
        std::size_t pos = 0;
        while (true) {
          const std::size_t b = v7->find('[', pos);
          if (b == std::string::npos) break;
          const std::size_t e = v7->find(']', b);
          if (e == std::string::npos) break;
          std::string col = v7->substr(pos, b - pos);
          while (!col.empty() && col.front() == ' ') col.erase(col.begin());
          while (!col.empty() && col.back() == ' ') col.pop_back();
          std::string u = v7->substr(b + 1, e - b - 1);
          units[col] = (u == "-") ? "" : u;
          pos = e + 1;
        }
      }
    }
    std::string tname =
        tt.name.empty() ? (tables.size() == 1 ? std::string("table") : "table" + std::to_string(ti))
                        : tt.name;
    Table& t = p.add_table(tname, title);
    for (std::size_t k = 0; k < tt.columns.size(); ++k) {
      const bool is_text =
          !tt.text[k].empty() || std::find(opt.text_columns.begin(), opt.text_columns.end(),
                                           tt.columns[k]) != opt.text_columns.end();
      Column& c =
          t.add_column(tt.columns[k], units.count(tt.columns[k]) ? units[tt.columns[k]] : "",
                       is_text ? ColumnKind::text : ColumnKind::real);
      if (is_text)
        c.text = tt.text[k];
      else
        c.num = tt.values[k];
      if (is_text && c.text.size() != tt.rows()) c.text.resize(tt.rows());
    }
  }
  if (!header_seen && tables.empty()) throw Error(name, "", "empty input: no table");
  for (const auto& [table, rows] : declared) {
    // A structured binding cannot be captured by clang 14 (the fuzz preset's compiler).
    const auto t = std::find_if(p.tables.begin(), p.tables.end(),
                                [&wanted = table](const Table& x) { return x.name == wanted; });
    if (t == p.tables.end())
      throw Error(name, "",
                  "table '" + table + "' missing (the header lists it): a truncated file?");
    if (t->rows() != rows)
      throw Error(name, "",
                  "table '" + table + "' has " + std::to_string(t->rows()) +
                      " rows, the header says " + std::to_string(rows) + ": a truncated file?");
  }
  return out;
}

std::string tsv_product_kind(const std::string& text) {
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line) && line.rfind("#", 0) == 0)
    if (line.rfind("# kind: ", 0) == 0) return line.substr(8);
  return {};
}

ProductFile read_product(const Input& in, const std::string& expected_kind) {
  ProductFile p =
      in.is_hdf5() ? read_product_hdf5(in.hdf5()) : read_product_tsv(in.text(), in.name());
  p.product.source = in.name();
  // Tables written with --table and no --header: the blocks are there, the file header not.
  const bool bare_tables = !in.is_hdf5() && (in.text().rfind("# table: ", 0) == 0 ||
                                             in.text().find("\n# table: ") != std::string::npos);
  if (!expected_kind.empty() && p.product.kind != expected_kind)
    throw Error(in.name(), "",
                !p.product.kind.empty()
                    ? "is a '" + p.product.kind + "' product, expected '" + expected_kind + "'"
                : bare_tables
                    ? "not a cdpile " + expected_kind +
                          " product: tables without the file header "
                          "(a tool's " +
                          field("table") + " output; write it with " + field("header") + ")"
                    : "not a cdpile " + expected_kind + " product (no '# kind:' header line)");
  return p;
}

analysis::RunSteps steps_from_series(const Series& s, bool include_walls, const std::string& file) {
  analysis::RunSteps r;
  r.step = s.step;
  auto real = [&](const std::string& n) -> std::optional<std::vector<double>> {
    if (auto it = s.real.find(n); it != s.real.end()) return it->second;
    if (auto it = s.integer.find(n); it != s.integer.end())
      return std::vector<double>(it->second.begin(), it->second.end());
    return std::nullopt;
  };
  auto integer = [&](const std::string& n) -> std::optional<std::vector<std::int64_t>> {
    if (auto it = s.integer.find(n); it != s.integer.end()) return it->second;
    if (auto it = s.real.find(n); it != s.real.end()) {
      std::vector<std::int64_t> v;
      for (double x : it->second) {
        if (!std::isfinite(x) || x != std::floor(x))
          throw Error(file, "/observables/" + n, "expected integer counts");
        v.push_back(static_cast<std::int64_t>(x));
      }
      return v;
    }
    return std::nullopt;
  };
  if (s.step.empty()) return r;
  auto theta = real("tilt_angle");
  if (!theta) throw Error(file, "/observables/tilt_angle", "missing (needed for theta per step)");
  r.theta = *theta;
  const char* n_name = include_walls ? "contacts" : "contacts_grain";
  auto n = integer(n_name);
  if (!n && !include_walls) n = integer("contacts");
  if (!n)
    throw Error(file, std::string("/observables/") + n_name,
                "missing (the per-step contact count)");
  r.contacts = *n;
  if (auto c = integer(include_walls ? "critical" : "critical_grain")) r.critical = *c;
  if (auto c = integer("sliding")) r.sliding = *c;
  if (auto e = real("kinetic_energy")) r.kinetic_energy = *e;
  if (auto e = real("rotational_energy")) r.rotational_energy = *e;
  if (auto c = integer("converged")) r.converged = *c;
  if (auto v = real("max_speed")) r.max_speed = *v;
  if (auto c = integer("grains_without_contact")) r.grains_without_contact = *c;
  if (auto c = integer("sweeps")) r.sweeps = *c;
  if (auto c = integer("substeps")) r.substeps = *c;
  return r;
}

Format parse_format(const std::string& s) {
  if (s == "auto") return Format::automatic;
  if (s == "tsv") return Format::tsv;
  if (s == "hdf5") return Format::hdf5;
  throw UsageError(field("format") + ": expected auto, tsv or hdf5, got '" + s + "'");
}

namespace {
bool text_extension(const std::string& path) {
  for (const char* ext : {".tsv", ".txt", ".dat"}) {
    const std::string e(ext);
    if (path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0)
      return true;
  }
  return false;
}
}  // namespace

Format resolve_format(const std::string& output, Format format) {
  if (format != Format::automatic) return format;
  if (output.empty()) return Format::tsv;
  if (output == "-") return Format::hdf5;
  return text_extension(output) ? Format::tsv : Format::hdf5;
}

void emit(const Product& p, const std::vector<Provenance>& history, const std::string& output,
          bool force, Format format, const std::vector<std::string>& only, bool header,
          int digits) {
  std::string target = output.empty() ? "-" : output;
  const Format f = resolve_format(output, format);
  Output out(target, force);
  if (f == Format::tsv) {
    write_tsv(out.text(), p, history, only, header, digits);
  } else {
    write_hdf5(out.create_hdf5(), p, history);
  }
  out.commit();
}

}  // namespace cdpile::io
