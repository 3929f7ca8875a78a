#include "cdpile/io/contact_table.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <string_view>
#include <tuple>

namespace cdpile::io {

std::optional<std::size_t> TextTable::find(const std::string& column) const {
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k] == column) return k;
  return std::nullopt;
}

std::optional<double> parse_number(const std::string& cell) {
  if (cell.empty()) return std::nullopt;
  const char* b = cell.data();
  const char* e = b + cell.size();
  if (*b == '+') ++b;  // from_chars refuses a leading '+'
  double v = 0.0;
  auto [p, ec] = std::from_chars(b, e, v, std::chars_format::general);
  if (ec != std::errc() || p != e || !std::isfinite(v)) return std::nullopt;
  return v;
}

namespace {

enum class Sep { tab, comma, space };

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string> split(std::string_view line, Sep sep) {
  std::vector<std::string> out;
  if (sep == Sep::space) {
    std::size_t k = 0;
    while (k < line.size()) {
      while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
      if (k >= line.size()) break;
      std::size_t e = k;
      while (e < line.size() && line[e] != ' ' && line[e] != '\t') ++e;
      out.emplace_back(line.substr(k, e - k));
      k = e;
    }
    return out;
  }
  const char c = sep == Sep::tab ? '\t' : ',';
  std::size_t k = 0;
  while (true) {
    const std::size_t e = line.find(c, k);
    out.emplace_back(
        trim(line.substr(k, e == std::string_view::npos ? std::string_view::npos : e - k)));
    if (e == std::string_view::npos) break;
    k = e + 1;
  }
  return out;
}

std::string format_cell(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string where(std::size_t line, const std::string& column = "") {
  std::string w = "line " + std::to_string(line);
  if (!column.empty()) w += ", column " + column;
  return w;
}

}  // namespace

std::vector<TextTable> parse_text_tables(const std::string& text, const std::string& file,
                                         const TextTableOptions& opt) {
  std::vector<TextTable> tables;
  TextTable cur;
  bool in_table = false;  // header seen
  Sep sep = Sep::tab;
  std::size_t lineno = 0;
  std::vector<bool> is_text;

  auto finish = [&]() {
    if (in_table) tables.push_back(std::move(cur));
    cur = TextTable();
    in_table = false;
  };

  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t e = text.find('\n', pos);
    if (e == std::string::npos) e = text.size();
    std::string_view raw(text.data() + pos, e - pos);
    pos = e + 1;
    ++lineno;
    if (raw.find('\0') != std::string_view::npos)
      throw Error(file, where(lineno), "binary data in a text table");
    const std::string_view line = trim(raw);
    if (line.empty()) {
      if (in_table) finish();
      if (pos > text.size()) break;
      continue;
    }
    if (line.front() == '#') {
      if (in_table) finish();  // a comment after rows starts the next table
      std::string_view c = trim(line.substr(1));
      if (c.rfind("table:", 0) == 0) cur.name = std::string(trim(c.substr(6)));
      cur.comments.emplace_back(c);
      continue;
    }
    if (!in_table) {
      // the header
      sep = line.find('\t') != std::string_view::npos  ? Sep::tab
            : line.find(',') != std::string_view::npos ? Sep::comma
                                                       : Sep::space;
      cur.columns = split(line, sep);
      cur.first_line = lineno;
      for (std::size_t k = 0; k < cur.columns.size(); ++k) {
        if (cur.columns[k].empty())
          throw Error(file, where(lineno), "empty column name in the header");
        for (std::size_t q = 0; q < k; ++q)
          if (cur.columns[q] == cur.columns[k])
            throw Error(file, where(lineno), "column '" + cur.columns[k] + "' appears twice");
      }
      is_text.assign(cur.columns.size(), false);
      auto listed = [&](const std::vector<std::string>& v, const std::string& c) {
        return std::find(v.begin(), v.end(), c) != v.end();
      };
      for (std::size_t k = 0; k < cur.columns.size(); ++k)
        is_text[k] = listed(opt.text_columns, cur.columns[k]) ||
                     (!opt.numeric_columns.empty() && !listed(opt.numeric_columns, cur.columns[k]));
      cur.values.assign(cur.columns.size(), {});
      cur.text.assign(cur.columns.size(), {});
      in_table = true;
      continue;
    }
    const std::vector<std::string> cells = split(line, sep);
    if (cells.size() != cur.columns.size())
      throw Error(file, where(lineno),
                  std::to_string(cells.size()) + " fields, the header has " +
                      std::to_string(cur.columns.size()));
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (is_text[k]) {
        cur.text[k].push_back(cells[k]);
        cur.values[k].push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      if (opt.allow_missing && cells[k] == missing_marker) {
        cur.values[k].push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      auto v = parse_number(cells[k]);
      if (!v) {
        std::string why = "'" + cells[k] + "' is not a finite number";
        if (cells[k] == missing_marker) why = "missing value (NA) where a number is required";
        throw Error(file, where(lineno, cur.columns[k]), why);
      }
      cur.values[k].push_back(*v);
    }
    cur.line.push_back(lineno);
  }
  finish();
  return tables;
}

// ---------------------------------------------------------------------------------

ContactTable read_contact_table(const std::string& text, const std::string& file,
                                const ContactTableOptions& opt, std::optional<double> diameter) {
  // Only the known columns are numbers; any other column is ignored whatever it holds.
  TextTableOptions topt;
  topt.numeric_columns = {"x", "y", "fn", "ft", "i", "j", "wall", "frame", "theta", "status"};
  auto tables = parse_text_tables(text, file, topt);
  if (tables.empty()) throw Error(file, "", "no table (expected a header line: x y fn ft ...)");
  if (tables.size() > 1)
    throw Error(file, where(tables[1].first_line),
                "a second table after a blank line (a contact table is one table)");
  const TextTable& t = tables.front();
  ContactTable out;
  out.file = file;
  out.columns = t.columns;
  for (const std::string& c : t.comments)
    if (c.rfind("length_unit:", 0) == 0) {
      std::string u = c.substr(12);
      u.erase(0, u.find_first_not_of(" \t"));
      u.erase(u.find_last_not_of(" \t") + 1);
      out.length_unit = u;
    }
  auto need = [&](const char* name) {
    auto k = t.find(name);
    if (!k) {
      std::string have;
      for (const auto& c : t.columns) have += (have.empty() ? "" : " ") + c;
      throw Error(file, where(t.first_line),
                  std::string("missing column '") + name + "' (the header has: " + have + ")");
    }
    return *k;
  };
  const std::size_t cx = need("x"), cy = need("y"), cfn = need("fn"), cft = need("ft");
  const auto ci = t.find("i"), cj = t.find("j"), cw = t.find("wall"), cf = t.find("frame"),
             ct = t.find("theta"), cs = t.find("status");
  out.has_ids = ci && cj;
  out.has_walls = cw.has_value() || cj.has_value();
  out.has_theta = ct.has_value();
  out.has_status = cs.has_value();

  auto integer = [&](std::size_t col, std::size_t row, const char* what) -> std::int64_t {
    const double v = t.values[col][row];
    if (v != std::floor(v) || std::abs(v) > 9.0e15)
      throw Error(file, where(t.line[row], t.columns[col]),
                  std::string(what) + " must be an integer");
    return static_cast<std::int64_t>(v);
  };

  std::map<std::int64_t, std::size_t> frame_index;  // frame id -> position in out.frames
  // Per frame: the key of each contact (ids, or the point's bits) -> the row it came from.
  using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t>;
  std::vector<std::map<Key, std::size_t>> seen;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const std::int64_t fid = cf ? integer(*cf, r, "frame") : 0;
    auto it = frame_index.find(fid);
    if (it == frame_index.end()) {
      it = frame_index.emplace(fid, out.frames.size()).first;
      ContactTableFrame fr;
      fr.frame = fid;
      fr.first_line = t.line[r];
      if (ct) fr.theta = t.values[*ct][r];
      out.frames.push_back(std::move(fr));
      seen.emplace_back();
    }
    ContactTableFrame& fr = out.frames[it->second];
    if (ct && t.values[*ct][r] != *fr.theta)
      throw Error(file, where(t.line[r], "theta"),
                  "theta differs from the value on line " + std::to_string(fr.first_line) +
                      " of the same frame");
    std::int32_t i = -1, j = -1;
    auto id32 = [&](std::size_t col, const char* what) {
      const std::int64_t v = integer(col, r, what);
      if (v < std::numeric_limits<std::int32_t>::min() ||
          v > std::numeric_limits<std::int32_t>::max())
        throw Error(file, where(t.line[r], t.columns[col]), std::string(what) + " out of range");
      return static_cast<std::int32_t>(v);
    };
    if (ci) i = id32(*ci, "id");
    if (cj) j = id32(*cj, "id");
    if (cw) {
      const std::int64_t w = integer(*cw, r, "wall");
      if (w != 0 && w != 1) throw Error(file, where(t.line[r], "wall"), "wall must be 0 or 1");
      if (w == 1 && j >= 0) j = wall_floor;
      if (w == 0 && !cj) j = 0;  // a grain of unknown id
    } else if (!cj) {
      j = 0;  // no wall information: every contact is a grain-grain contact
    }
    ContactStatus st = ContactStatus::stick;
    if (cs) {
      const std::int64_t s = integer(*cs, r, "status");
      if (s < 0 || s > 2) throw Error(file, where(t.line[r], "status"), "status must be 0, 1 or 2");
      st = static_cast<ContactStatus>(s);
    }
    // A contact given twice: the same bodies (in either order), or without ids the same
    // contact point, in one frame.
    const double x = t.values[cx][r], y = t.values[cy][r];
    if (diameter)
      for (auto [v, col] : {std::pair{x, cx}, std::pair{y, cy}})
        if (!(std::abs(v) <= 1e9 * *diameter))
          throw Error(file, where(t.line[r], t.columns[col]),
                      format_cell(v) + " is outside [-1e9 D, 1e9 D] (D = " +
                          format_cell(*diameter) + ")");
    Key key;
    std::string what;
    if (out.has_ids) {
      const std::int64_t a = j < 0 ? i : std::min(i, j), b = j < 0 ? j : std::max(i, j);
      key = {0, a, b};
      what = "contact " + std::to_string(i) + "-" + std::to_string(j);
    } else {
      key = {1, std::bit_cast<std::int64_t>(x + 0.0), std::bit_cast<std::int64_t>(y + 0.0)};
      what = "contact point (" + format_cell(x) + ", " + format_cell(y) + ")";
    }
    auto [it_seen, fresh] = seen[it->second].emplace(key, r);
    if (!fresh) {
      const std::size_t q = it_seen->second;
      const std::string frame_text = cf ? " of frame " + std::to_string(fid) : "";
      if (opt.duplicates == Duplicates::error)
        throw Error(file, where(t.line[r]),
                    what + frame_text + " is also on line " + std::to_string(t.line[q]) +
                        " (give each contact once, or merge repeated rows: " + field("duplicates") +
                        " merge)");
      const double scale =
          std::max({std::abs(t.values[cfn][q]), std::abs(t.values[cfn][r]), 1e-300});
      const double lscale = std::max(
          {std::abs(x), std::abs(y), std::abs(t.values[cx][q]), std::abs(t.values[cy][q]), 1e-300});
      if (std::abs(t.values[cfn][q] - t.values[cfn][r]) > 1e-9 * scale ||
          std::abs(std::abs(t.values[cft][q]) - std::abs(t.values[cft][r])) > 1e-9 * scale ||
          std::abs(t.values[cx][q] - x) > 1e-9 * lscale ||
          std::abs(t.values[cy][q] - y) > 1e-9 * lscale)
        throw Error(file, where(t.line[r]),
                    what + frame_text + " is also on line " + std::to_string(t.line[q]) +
                        " with another point or other forces: not a repeat, cannot merge");
      ++out.merged;
      continue;
    }
    fr.contacts.push_back(i, j, Vec2(x, y), Vec2::Zero(), t.values[cfn][r], t.values[cft][r], 0.0,
                          st);
  }
  std::sort(
      out.frames.begin(), out.frames.end(),
      [](const ContactTableFrame& a, const ContactTableFrame& b) { return a.frame < b.frame; });
  return out;
}

}  // namespace cdpile::io
