#include "cdpile/io/schema.hpp"

#include "cdpile/parameter_keys.hpp"

#include "cdpile_commit.h"  // generated: CDPILE_COMMIT (cmake/source_commit.cmake)

#include <pwd.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <iterator>
#include <limits>
#include <optional>

namespace cdpile::io {

namespace {

constexpr const char* kGrains = "/particles/grains";
constexpr const char* kContacts = "/contacts";
constexpr const char* kObservables = "/observables";

// Chunking: one frame of grain state per chunk (N x 2 doubles: 64 KiB at N = 4000);
// contacts and per-step series in chunks of 16384 and 4096 rows. Deflate with the
// shuffle filter: measured in docs/schema.md ("Compression").
constexpr h5::Layout kFrameLayout{1, 4};
constexpr h5::Layout kContactLayout{16384, 4};
constexpr h5::Layout kSeriesLayout{4096, 4};

std::string grain_path(const std::string& element) { return std::string(kGrains) + "/" + element; }

[[noreturn]] void bad(const h5::File& f, const std::string& where, const std::string& what) {
  throw Error(f.name(), where, what);
}

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

// The ranges of the schema's values (docs/schema.md, "Ranges"): each bound is stated there
// once with its reason, and checked here, where the value is read.

/// The largest integer a double holds exactly: steps (time = step h), counts and ids are
/// computed with as doubles somewhere, so none may exceed it.
constexpr double kExactInteger = 9007199254740992.0;  // 2^53

/// deposit's largest pile, in its diameters: 1e7 wide (--width), 1e8 grains in a column
/// (--grains). A box edge beyond 1e8 of its largest diameters is no pile's.
constexpr double kBoxInDiameters = 1e8;

/// deposit's --density range [1e-12, 1e12] kg/m^3: a grain's mass per unit thickness is
/// rho pi r^2, rho within it (to 1e-9, the rounding of m / (pi r^2)).
constexpr double kDensityMin = 1e-12, kDensityMax = 1e12;

/// The tilt of a frame or a step: tilt-cd's --from, --to and --max-angle are in [-90, 90].
constexpr double kTiltMaxDeg = 90.0;

/// How far a unit normal's length may be from 1 (the writer divides by the norm).
constexpr double kUnitTolerance = 1e-6;

/// "WHERE: VALUE is outside RANGE", the one form of every range refusal.
[[noreturn]] void out_of_range(const h5::File& f, const std::string& path, const std::string& where,
                               const std::string& value, const std::string& range) {
  bad(f, path, where + ": " + value + " is outside " + range);
}

std::string integer_text(std::int64_t x) { return std::to_string(x); }

/// A value as read, every digit that tells it apart (the shortest text that reads back as it).
std::string exact_text(double x) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return ec == std::errc() ? std::string(buf, end) : number_text(x);
}

/// Steps: integers in [0, 2^53], in order (non-decreasing: a resume keeps the frames up to a
/// step by their order); times: in [0, inf).
void check_clock(const h5::File& f, const std::string& step_path,
                 const std::vector<std::int64_t>& step, const std::string& time_path,
                 const std::vector<double>& time, const char* row) {
  for (std::size_t k = 0; k < step.size(); ++k) {
    const std::string where = row + std::string(" ") + std::to_string(k);
    if (step[k] < 0 || static_cast<double>(step[k]) > kExactInteger)
      out_of_range(f, step_path, where, integer_text(step[k]), "[0, 2^53]");
    if (k > 0 && step[k] < step[k - 1])
      out_of_range(f, step_path, where, integer_text(step[k]),
                   "[" + integer_text(step[k - 1]) + ", 2^53] (steps are in order)");
  }
  for (std::size_t k = 0; k < time.size(); ++k) {
    const std::string where = row + std::string(" ") + std::to_string(k);
    if (!(time[k] >= 0)) out_of_range(f, time_path, where, exact_text(time[k]) + " s", "[0, inf) s");
  }
}

std::vector<Vec2> to_vec2(const std::vector<double>& xy) {
  std::vector<Vec2> out(xy.size() / 2);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = Vec2(xy[2 * k], xy[2 * k + 1]);
  return out;
}

/// Creates a time-dependent H5MD element (step, time, value), its step and time linked
/// to `clock` (an element that already has them) unless it is the clock itself.
void make_element_links(const h5::File& f, const std::string& element, const std::string& clock) {
  h5::create_group(f, element);
  h5::hard_link(f, clock + "/step", element + "/step");
  h5::hard_link(f, clock + "/time", element + "/time");
}

}  // namespace

double as_real(const Values& v, const std::string& key, const std::string& file) {
  auto it = v.find(key);
  if (it == v.end()) throw Error(file, "/parameters", "missing parameter '" + key + "'");
  if (auto* d = std::get_if<double>(&it->second)) return *d;
  if (auto* i = std::get_if<std::int64_t>(&it->second)) return static_cast<double>(*i);
  throw Error(file, "/parameters", "parameter '" + key + "' is not a number");
}

std::int64_t as_int(const Values& v, const std::string& key, const std::string& file) {
  auto it = v.find(key);
  if (it == v.end()) throw Error(file, "/parameters", "missing parameter '" + key + "'");
  if (auto* i = std::get_if<std::int64_t>(&it->second)) return *i;
  throw Error(file, "/parameters", "parameter '" + key + "' is not an integer");
}

double process_cpu_s() {
  rusage ru{};
  if (::getrusage(RUSAGE_SELF, &ru) != 0) return -1.0;
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

Provenance provenance_now(const std::string& tool, const std::string& command_line,
                          const std::string& inputs) {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  // the version and the commit that made the file: "0.1.0+8795282abcde" (docs/schema.md)
  return {tool, CDPILE_VERSION "+" CDPILE_COMMIT, command_line, inputs, buf, "", process_cpu_s()};
}

std::vector<Provenance> merge_histories(
    const std::vector<std::pair<std::string, std::vector<Provenance>>>& inputs) {
  if (inputs.size() == 1) return inputs.front().second;
  std::vector<Provenance> out;
  for (const auto& [name, history] : inputs) {
    for (Provenance p : history) {
      p.via = p.via.empty() ? name : name + " > " + p.via;
      out.push_back(std::move(p));
    }
  }
  return out;
}

namespace {
std::optional<Author> g_author;

std::string trim_blanks(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}
}  // namespace

Author parse_author(const std::string& text) {
  Author a;
  const std::string t = trim_blanks(text);
  const auto lt = t.rfind('<');
  if (lt != std::string::npos && !t.empty() && t.back() == '>') {
    a.name = trim_blanks(t.substr(0, lt));
    a.email = trim_blanks(t.substr(lt + 1, t.size() - lt - 2));
  } else {
    a.name = t;
  }
  return a;
}

void set_author(const std::string& text) { g_author = parse_author(text); }

Author author() {
  if (g_author && !g_author->name.empty()) return *g_author;
  if (const char* env = std::getenv("CDPILE_AUTHOR"); env && *env) {
    Author a = parse_author(env);
    if (!a.name.empty()) return a;
  }
  if (const passwd* pw = getpwuid(getuid())) {
    std::string gecos = pw->pw_gecos ? pw->pw_gecos : "";
    gecos = trim_blanks(gecos.substr(0, gecos.find(',')));  // the full name comes first
    if (!gecos.empty()) return {gecos, ""};
    if (pw->pw_name && *pw->pw_name) return {pw->pw_name, ""};
  }
  return {"unknown", ""};
}

void declare_units_module(const h5::File& f) {
  h5::create_group(f, "/h5md/modules/units");
  h5::set_attr(f, "/h5md/modules/units", "version", std::vector<std::int64_t>{1, 0});
  h5::set_attr_ascii(f, "/h5md/modules/units", "system", "SI");
}

void set_unit(const h5::File& f, const std::string& path, const std::string& unit) {
  if (!unit.empty()) h5::set_attr_ascii(f, path, "unit", unit);
}

void Series::clear() {
  step.clear();
  time.clear();
  for (auto& [k, v] : real) v.clear();
  for (auto& [k, v] : integer) v.clear();
}

void write_values(const h5::File& f, const std::string& group, const Values& v) {
  h5::create_group(f, group);
  for (const auto& [name, value] : v)  // name bound by reference: clang 14 cannot capture a binding
    std::visit([&, &key = name](const auto& x) { h5::set_attr(f, group, key, x); }, value);
}

Values read_values(const h5::File& f, const std::string& group) {
  Values out;
  if (!h5::exists(f, group)) return out;
  for (const auto& name : h5::attr_names(f, group)) {
    switch (h5::attr_class(f, group, name)) {
      case H5T_INTEGER: out[name] = h5::attr_int(f, group, name); break;
      case H5T_FLOAT: out[name] = h5::attr_double(f, group, name); break;
      case H5T_STRING: out[name] = h5::attr_string(f, group, name); break;
      default: bad(f, group, "attribute '" + name + "' has an unsupported type");
    }
  }
  return out;
}

void append_provenance(const h5::File& f, const Provenance& p) {
  h5::create_group(f, "/provenance");
  char key[16];
  std::snprintf(key, sizeof key, "%03zu", h5::members(f, "/provenance").size());
  const std::string g = std::string("/provenance/") + key;
  h5::create_group(f, g);
  h5::set_attr(f, g, "tool", p.tool);
  h5::set_attr(f, g, "version", p.version);
  h5::set_attr(f, g, "command_line", p.command_line);
  h5::set_attr(f, g, "inputs", p.inputs);
  h5::set_attr(f, g, "date", p.date);
  if (!p.via.empty()) h5::set_attr(f, g, "via", p.via);  // only in files made from several inputs
  if (p.cpu_s >= 0.0) h5::set_attr(f, g, "cpu_s", p.cpu_s);
}

void set_last_cpu(const h5::File& f, double cpu_s) {
  if (cpu_s < 0.0 || !h5::exists(f, "/provenance")) return;
  const auto entries = h5::members(f, "/provenance");
  if (entries.empty()) return;
  h5::set_attr(f, "/provenance/" + entries.back(), "cpu_s", cpu_s);
}

void write_header(const h5::File& f, const RunHeader& h) {
  h5::set_attr(f, "/", "schema", std::string("cdpile"));
  h5::set_attr(f, "/", "schema_version", schema_version);
  h5::set_attr(f, "/", "kind", h.kind);
  // H5MD 1.1 mandatory metadata; its texts are fixed-length strings, as the specification
  // asks (files written before were variable-length: the readers take both).
  h5::create_group(f, "/h5md/author");
  h5::create_group(f, "/h5md/creator");
  h5::set_attr(f, "/h5md", "version", std::vector<std::int64_t>{1, 1});
  const Author a = author();
  h5::set_attr_fixed(f, "/h5md/author", "name", a.name);
  if (!a.email.empty()) h5::set_attr_fixed(f, "/h5md/author", "email", a.email);
  h5::set_attr_fixed(f, "/h5md/creator", "name", std::string("cdpile"));
  h5::set_attr_fixed(f, "/h5md/creator", "version", std::string(CDPILE_VERSION));
  write_values(f, "/parameters", h.parameters);
  write_values(f, "/results", h.results);
  for (const auto& p : h.provenance) append_provenance(f, p);
}

RunHeader read_header(const h5::File& f, const std::string& expected_kind) {
  if (!h5::has_attr(f, "/", "schema") || h5::attr_class(f, "/", "schema") != H5T_STRING ||
      h5::attr_string(f, "/", "schema") != "cdpile")
    bad(f, "/", "not a cdpile file (no schema = \"cdpile\" attribute)");
  if (!h5::has_attr(f, "/", "schema_version")) bad(f, "/", "missing attribute 'schema_version'");
  const std::int64_t v = h5::attr_int(f, "/", "schema_version");
  if (v != schema_version)
    bad(f, "/",
        "schema version " + std::to_string(v) + ", this build reads version " +
            std::to_string(schema_version));
  RunHeader h;
  h.kind = h5::attr_string(f, "/", "kind");
  if (!expected_kind.empty() && h.kind != expected_kind)
    bad(f, "/", "is a '" + h.kind + "' file, expected '" + expected_kind + "'");
  if (!h5::exists(f, "/h5md")) bad(f, "/h5md", "missing group");
  h.parameters = read_values(f, "/parameters");
  h.results = read_values(f, "/results");
  if (h5::exists(f, "/provenance")) {
    for (const auto& k : h5::members(f, "/provenance")) {
      const std::string g = "/provenance/" + k;
      h.provenance.push_back(
          {h5::attr_string(f, g, "tool"), h5::attr_string(f, g, "version"),
           h5::attr_string(f, g, "command_line"), h5::attr_string(f, g, "inputs"),
           h5::attr_string(f, g, "date"),
           h5::has_attr(f, g, "via") ? h5::attr_string(f, g, "via") : std::string(),
           h5::has_attr(f, g, "cpu_s") ? h5::attr_double(f, g, "cpu_s") : -1.0});
    }
  }
  return h;
}

// ---------------------------------------------------------------------------------------
// Writer

RunWriter::RunWriter(h5::File& f, const RunHeader& header, const Grains& g) : f_(&f) {
  write_header(f, header);
  declare_units_module(f);
  grains_ = g.size();
  const std::string box = grain_path("box");
  h5::create_group(f, box);
  h5::set_attr(f, box, "dimension", std::int64_t{2});
  h5::set_attr_fixed(f, box, "boundary", std::vector<std::string>{"none", "none"});
  const std::vector<double> edges{header.box.width, header.box.height};
  h5::write(f, box + "/edges", edges);
  set_unit(f, box + "/edges", "m");
  // The walls are planes n.x = offset in the box frame; their ids appear in /contacts/j.
  h5::set_attr(f, box, "wall_names", std::vector<std::string>{"floor", "left", "right"});
  h5::set_attr(f, box, "wall_ids", std::vector<std::int64_t>{wall_floor, wall_left, wall_right});
  h5::set_attr(f, box, "wall_normals", std::vector<double>{0, 1, 1, 0, -1, 0});
  h5::set_attr(f, box, "wall_offsets", std::vector<double>{0, 0, -header.box.width});

  auto fixed = [&](const char* name, const std::vector<double>& v, const char* unit) {
    h5::write(f, grain_path(name), v);
    set_unit(f, grain_path(name), unit);
  };
  fixed("radius", g.radius, "m");
  fixed("mass", g.mass, "kg m-1");
  fixed("inertia", g.inertia, "kg m");
  std::vector<std::uint8_t> species(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) species[k] = static_cast<std::uint8_t>(g.species[k]);
  h5::write(f, grain_path("species"), species);
  h5::set_attr(f, grain_path("species"), "meaning",
               std::string("0 free grain, 1 grain glued to the floor"));
}

RunWriter RunWriter::reopen(h5::File& f, std::int64_t last_step) {
  RunReader r(f);
  RunWriter w(f);
  w.grains_ = r.grain_count();
  // Keep the frames with step <= last_step.
  std::size_t keep = 0;
  while (keep < r.frame_count() && r.frame_steps()[keep] <= last_step) ++keep;
  std::int64_t contacts = 0;
  if (keep > 0) {
    auto off = h5::read_rows<std::int64_t>(f, std::string(kContacts) + "/offset", keep - 1, 1);
    auto cnt = h5::read_rows<std::int64_t>(f, std::string(kContacts) + "/count", keep - 1, 1);
    contacts = off[0] + cnt[0];
  }
  if (r.frame_count() > 0) {
    for (const char* e : {"position", "velocity", "orientation", "angular_velocity"}) {
      h5::truncate_rows(f, grain_path(e) + "/value", keep);
      if (std::string(e) == "position") {
        h5::truncate_rows(f, grain_path(e) + "/step", keep);
        h5::truncate_rows(f, grain_path(e) + "/time", keep);
      }
    }
    for (const char* e : {"step", "time", "tilt_angle", "offset", "count"})
      h5::truncate_rows(f, std::string(kContacts) + "/" + e, keep);
    for (const char* e : {"i", "j", "point", "normal", "fn", "ft", "gap", "status"})
      h5::truncate_rows(f, std::string(kContacts) + "/" + e, static_cast<hsize_t>(contacts));
  }
  w.frames_ = keep;
  w.contacts_ = contacts;
  // Observables: keep the rows with step <= last_step.
  if (h5::exists(f, kObservables)) {
    auto names = h5::members(f, kObservables);
    if (!names.empty()) {
      const std::string clock = std::string(kObservables) + "/" + names.front();
      auto steps = h5::read<std::int64_t>(f, clock + "/step", {h5::any});
      hsize_t rows = 0;
      while (rows < steps.size() && steps[rows] <= last_step) ++rows;
      for (const auto& n : names)
        h5::truncate_rows(f, std::string(kObservables) + "/" + n + "/value", rows);
      h5::truncate_rows(f, clock + "/step", rows);
      h5::truncate_rows(f, clock + "/time", rows);
    }
  }
  return w;
}

void RunWriter::append_frame(const Frame& fr) { append_frames({fr}); }

namespace {
/// The values of one vector member of every frame, one frame after another.
template <class T, class Get>
std::vector<T> gather(const std::vector<Frame>& frames, Get get) {
  std::vector<T> out;
  for (const Frame& fr : frames) {
    const auto& v = get(fr);
    out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}
/// 2-vectors as the (x, y) doubles they are stored as.
const double* flat(const std::vector<Vec2>& v) { return v.empty() ? nullptr : v[0].data(); }
}  // namespace

void RunWriter::append_frames(const std::vector<Frame>& frames) {
  if (frames.empty()) return;
  h5::File& f = *f_;
  for (const Frame& fr : frames)
    if (fr.grains.size() != grains_)
      throw Error(f.name(), kGrains,
                  "frame has " + std::to_string(fr.grains.size()) + " grains, file has " +
                      std::to_string(grains_));
  const hsize_t n = grains_, nf = frames.size();
  const std::string pos = grain_path("position");
  const bool first = !h5::exists(f, pos + "/step");
  std::vector<std::int64_t> step, count, offset;
  std::vector<double> time, tilt_deg;
  for (const Frame& fr : frames) {
    step.push_back(fr.step);
    time.push_back(fr.time);
    tilt_deg.push_back(fr.tilt_angle * 180.0 / M_PI);
    offset.push_back(contacts_);
    count.push_back(static_cast<std::int64_t>(fr.contacts.size()));
    contacts_ += count.back();
  }
  h5::append(f, pos + "/step", step.data(), {nf}, {1024, 0});
  h5::append(f, pos + "/time", time.data(), {nf}, {1024, 0});
  h5::append(f, pos + "/value",
             flat(gather<Vec2>(
                 frames, [](const Frame& x) -> const auto& { return x.grains.position; })),
             {nf, n, 2}, kFrameLayout);
  h5::append(f, grain_path("velocity") + "/value",
             flat(gather<Vec2>(
                 frames, [](const Frame& x) -> const auto& { return x.grains.velocity; })),
             {nf, n, 2}, kFrameLayout);
  h5::append(f, grain_path("orientation") + "/value",
             gather<double>(
                 frames, [](const Frame& x) -> const auto& { return x.grains.orientation; })
                 .data(),
             {nf, n}, kFrameLayout);
  h5::append(f, grain_path("angular_velocity") + "/value",
             gather<double>(
                 frames, [](const Frame& x) -> const auto& { return x.grains.angular_velocity; })
                 .data(),
             {nf, n}, kFrameLayout);
  if (first) {
    for (const char* e : {"velocity", "orientation", "angular_velocity"})
      make_element_links(f, grain_path(e), pos);
    set_unit(f, pos + "/value", "m");
    set_unit(f, pos + "/time", "s");
    set_unit(f, grain_path("velocity") + "/value", "m s-1");
    set_unit(f, grain_path("orientation") + "/value", "rad");
    set_unit(f, grain_path("angular_velocity") + "/value", "rad s-1");
  }

  const std::string cg = kContacts;
  const auto k = static_cast<hsize_t>(contacts_ - offset.front());  // contacts of these frames
  h5::append(f, cg + "/step", step.data(), {nf}, {1024, 0});
  h5::append(f, cg + "/time", time.data(), {nf}, {1024, 0});
  h5::append(f, cg + "/tilt_angle", tilt_deg.data(), {nf}, {1024, 0});
  h5::append(f, cg + "/offset", offset.data(), {nf}, {1024, 0});
  h5::append(f, cg + "/count", count.data(), {nf}, {1024, 0});
  h5::append(f, cg + "/i",
             gather<std::int32_t>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.i; })
                 .data(),
             {k}, kContactLayout);
  h5::append(f, cg + "/j",
             gather<std::int32_t>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.j; })
                 .data(),
             {k}, kContactLayout);
  h5::append(f, cg + "/point",
             flat(gather<Vec2>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.point; })),
             {k, 2}, kContactLayout);
  h5::append(f, cg + "/normal",
             flat(gather<Vec2>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.normal; })),
             {k, 2}, kContactLayout);
  h5::append(f, cg + "/fn",
             gather<double>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.fn; })
                 .data(),
             {k}, kContactLayout);
  h5::append(f, cg + "/ft",
             gather<double>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.ft; })
                 .data(),
             {k}, kContactLayout);
  h5::append(f, cg + "/gap",
             gather<double>(
                 frames, [](const Frame& x) -> const auto& { return x.contacts.gap; })
                 .data(),
             {k}, kContactLayout);
  const auto status = gather<ContactStatus>(
      frames, [](const Frame& x) -> const auto& { return x.contacts.status; });
  h5::append(f, cg + "/status", reinterpret_cast<const std::int8_t*>(status.data()), {k},
             kContactLayout);
  if (first) {
    h5::set_attr(
        f, cg, "description",
        std::string(
            "ragged table: frame k's contacts are rows offset[k] .. offset[k]+count[k]-1 of the "
            "flat "
            "datasets; j < 0 is a wall (-1 floor, -2 left, -3 right); normal points from j to i; "
            "tangent t = (-n_y, n_x); fn, ft are impulse / time step"));
    set_unit(f, cg + "/time", "s");
    set_unit(f, cg + "/tilt_angle", "degree");
    set_unit(f, cg + "/point", "m");
    set_unit(f, cg + "/fn", "N m-1");
    set_unit(f, cg + "/ft", "N m-1");
    set_unit(f, cg + "/gap", "m");
    h5::set_attr(f, cg + "/status", "meaning", std::string("0 open, 1 stick, 2 slide"));
  }
  frames_ += nf;
}

void RunWriter::append_series(const Series& s) {
  h5::File& f = *f_;
  const hsize_t rows = s.size();
  if (s.time.size() != rows)
    throw Error(f.name(), kObservables, "series: step and time differ in length");
  std::vector<std::string> names;
  for (const auto& [name, v] : s.real) names.push_back(name);
  for (const auto& [name, v] : s.integer) names.push_back(name);
  if (names.empty()) return;
  std::string clock;
  if (h5::exists(f, kObservables) && !h5::members(f, kObservables).empty()) {
    clock = std::string(kObservables) + "/" + h5::members(f, kObservables).front();
    for (const auto& n : names)
      if (!h5::exists(f, std::string(kObservables) + "/" + n))
        throw Error(f.name(), std::string(kObservables) + "/" + n,
                    "a column cannot be added to an existing series");
  } else {
    clock = std::string(kObservables) + "/" + names.front();
    h5::append(f, clock + "/step", s.step.data(), {0}, kSeriesLayout);
    h5::append(f, clock + "/time", s.time.data(), {0}, kSeriesLayout);
    set_unit(f, clock + "/time", "s");
    for (const auto& n : names)
      if (std::string(kObservables) + "/" + n != clock)
        make_element_links(f, std::string(kObservables) + "/" + n, clock);
  }
  h5::append(f, clock + "/step", s.step.data(), {rows}, kSeriesLayout);
  h5::append(f, clock + "/time", s.time.data(), {rows}, kSeriesLayout);
  auto unit_of = [&](const std::string& n) {
    auto it = s.unit.find(n);
    return it == s.unit.end() ? std::string() : it->second;
  };
  for (const auto& [name, v] : s.real) {
    if (v.size() != rows)
      throw Error(f.name(), std::string(kObservables) + "/" + name,
                  "column length differs from step");
    const std::string p = std::string(kObservables) + "/" + name + "/value";
    const bool fresh = !h5::exists(f, p);
    h5::append(f, p, v.data(), {rows}, kSeriesLayout);
    if (fresh) set_unit(f, p, unit_of(name));
  }
  for (const auto& [name, v] : s.integer) {
    if (v.size() != rows)
      throw Error(f.name(), std::string(kObservables) + "/" + name,
                  "column length differs from step");
    const std::string p = std::string(kObservables) + "/" + name + "/value";
    const bool fresh = !h5::exists(f, p);
    h5::append(f, p, v.data(), {rows}, kSeriesLayout);
    if (fresh) set_unit(f, p, unit_of(name));
  }
}

void RunWriter::set_result(const std::string& name, const Value& v) {
  h5::create_group(*f_, "/results");
  std::visit([&](const auto& x) { h5::set_attr(*f_, "/results", name, x); }, v);
}

void RunWriter::add_provenance(const Provenance& p) { append_provenance(*f_, p); }

void RunWriter::set_last_cpu(double cpu_s) { io::set_last_cpu(*f_, cpu_s); }

void RunWriter::flush() {
  if (H5Fflush(f_->id(), H5F_SCOPE_GLOBAL) < 0)
    throw Error(f_->name(), "", "cannot flush (disk full?)");
}

// ---------------------------------------------------------------------------------------
// Reader

RunReader::RunReader(const h5::File& f) : f_(&f) {
  header_ = read_header(f);
  if (header_.kind != "pile" && header_.kind != "run")
    bad(f, "/", "is a '" + header_.kind + "' file, expected a pile or a run");
  const std::string box = grain_path("box");
  if (!h5::exists(f, kGrains)) bad(f, kGrains, "missing group");
  if (!h5::exists(f, box)) bad(f, box, "missing group");
  if (h5::attr_int(f, box, "dimension") != 2)
    bad(f, box,
        "dimension is " + std::to_string(h5::attr_int(f, box, "dimension")) + ", expected 2");
  auto edges = h5::read<double>(f, box + "/edges", {2});
  header_.box = {edges[0], edges[1]};
  if (!(header_.box.width > 0)) bad(f, box + "/edges", "box width must be positive");
  if (!(header_.box.height >= 0))
    out_of_range(f, box + "/edges", "element 1 (height)", exact_text(header_.box.height) + " m",
                 "[0, inf) m");

  std::vector<hsize_t> dims;
  grains_.radius = h5::read<double>(f, grain_path("radius"), {h5::any}, &dims);
  n_ = dims[0];
  grains_.mass = h5::read<double>(f, grain_path("mass"), {n_});
  grains_.inertia = h5::read<double>(f, grain_path("inertia"), {n_});
  auto species = h5::read<std::uint8_t>(f, grain_path("species"), {n_});
  const double width = header_.box.width;
  for (std::size_t k = 0; k < n_; ++k) {
    if (!(grains_.radius[k] > 0))
      bad(f, grain_path("radius"), "radius of grain " + std::to_string(k) + " is not positive");
    if (grains_.radius[k] > width / 2)
      bad(f, grain_path("radius"),
          "radius of grain " + std::to_string(k) + " is " + number_text(grains_.radius[k]) +
              " m, more than half the box width " + number_text(width) + " m");
    if (!(grains_.mass[k] > 0))
      bad(f, grain_path("mass"), "mass of grain " + std::to_string(k) + " is not positive");
    if (!(grains_.inertia[k] > 0))
      bad(f, grain_path("inertia"), "inertia of grain " + std::to_string(k) + " is not positive");
    // rho pi r^2 with rho in deposit's --density range; at most m r^2 (a ring: no body
    // within a radius r turns harder). Both to 1e-9, the rounding of the writer's products.
    const double r = grains_.radius[k], disk = M_PI * r * r;
    if (!(grains_.mass[k] >= kDensityMin * disk * (1 - 1e-9) &&
          grains_.mass[k] <= kDensityMax * disk * (1 + 1e-9)))
      out_of_range(f, grain_path("mass"), "grain " + std::to_string(k),
                   exact_text(grains_.mass[k]) + " kg/m",
                   "[" + number_text(kDensityMin * disk) + ", " + number_text(kDensityMax * disk) +
                       "] kg/m (rho pi r^2, r = " + number_text(r) +
                       " m, rho in [1e-12, 1e12] kg/m^3)");
    if (!(grains_.inertia[k] <= grains_.mass[k] * r * r * (1 + 1e-9)))
      out_of_range(f, grain_path("inertia"), "grain " + std::to_string(k),
                   exact_text(grains_.inertia[k]) + " kg m",
                   "(0, " + number_text(grains_.mass[k] * r * r) + "] kg m (at most m r^2)");
    if (species[k] > 1)
      bad(f, grain_path("species"),
          "unknown species " + std::to_string(species[k]) + " of grain " + std::to_string(k));
  }
  if (n_ > 0) {
    const double d_max = 2 * *std::max_element(grains_.radius.begin(), grains_.radius.end());
    const double edge_max = kBoxInDiameters * d_max;
    for (std::size_t e = 0; e < 2; ++e)
      if (!(edges[e] <= edge_max))
        out_of_range(f, box + "/edges", std::string("element ") + std::to_string(e) +
                                            (e ? " (height)" : " (width)"),
                     exact_text(edges[e]) + " m",
                     "[0, " + number_text(edge_max) + "] m (1e8 of the largest diameter, " +
                         number_text(d_max) + " m)");
  }
  grains_.species.resize(n_);
  for (std::size_t k = 0; k < n_; ++k) grains_.species[k] = static_cast<Species>(species[k]);
  grains_.position.assign(n_, Vec2::Zero());
  grains_.velocity.assign(n_, Vec2::Zero());
  grains_.orientation.assign(n_, 0.0);
  grains_.angular_velocity.assign(n_, 0.0);

  const std::string pos = grain_path("position");
  if (!h5::exists(f, pos)) return;  // a file with no frame yet
  frame_steps_ = h5::read<std::int64_t>(f, pos + "/step", {h5::any}, &dims);
  const hsize_t frames = dims[0];
  frame_time_ = h5::read<double>(f, pos + "/time", {frames});
  for (const char* e : {"position", "velocity"}) {
    auto d = h5::shape(f, grain_path(e) + "/value");
    if (d.size() != 3 || d[0] != frames || d[1] != n_ || d[2] != 2)
      bad(f, grain_path(e) + "/value",
          "expected shape [" + std::to_string(frames) + " x " + std::to_string(n_) + " x 2]");
  }
  for (const char* e : {"orientation", "angular_velocity"}) {
    auto d = h5::shape(f, grain_path(e) + "/value");
    if (d.size() != 2 || d[0] != frames || d[1] != n_)
      bad(f, grain_path(e) + "/value",
          "expected shape [" + std::to_string(frames) + " x " + std::to_string(n_) + "]");
  }
  const std::string cg = kContacts;
  check_clock(f, pos + "/step", frame_steps_, pos + "/time", frame_time_, "frame");
  frame_tilt_ = h5::read<double>(f, cg + "/tilt_angle", {frames});
  for (std::size_t q = 0; q < frames; ++q)
    if (!(std::fabs(frame_tilt_[q]) <= kTiltMaxDeg))
      out_of_range(f, cg + "/tilt_angle", "frame " + std::to_string(q),
                   exact_text(frame_tilt_[q]) + " deg", "[-90, 90] deg");
  for (auto& t : frame_tilt_) t *= M_PI / 180.0;
  offset_ = h5::read<std::int64_t>(f, cg + "/offset", {frames});
  count_ = h5::read<std::int64_t>(f, cg + "/count", {frames});
  auto csteps = h5::read<std::int64_t>(f, cg + "/step", {frames});
  if (csteps != frame_steps_) bad(f, cg + "/step", "differs from " + pos + "/step");
  const auto rows = h5::shape(f, cg + "/i");
  if (rows.size() != 1)
    bad(f, cg + "/i",
        "expected one dimension (the contacts), found " + std::to_string(rows.size()));
  const auto k = static_cast<std::int64_t>(rows[0]);
  std::int64_t expect = 0;
  for (std::size_t q = 0; q < frames; ++q) {
    if (offset_[q] != expect || count_[q] < 0)
      bad(f, cg + "/offset", "frame " + std::to_string(q) + ": offset and count are inconsistent");
    expect += count_[q];
  }
  if (expect != k)
    bad(f, cg + "/i",
        "holds " + std::to_string(k) + " contacts, the frames count " + std::to_string(expect));
  for (const char* e : {"j", "fn", "ft", "gap", "status"})
    if (h5::shape(f, cg + "/" + e) != std::vector<hsize_t>{static_cast<hsize_t>(k)})
      bad(f, cg + "/" + e, "expected " + std::to_string(k) + " rows");
  for (const char* e : {"point", "normal"})
    if (h5::shape(f, cg + "/" + e) != std::vector<hsize_t>{static_cast<hsize_t>(k), 2})
      bad(f, cg + "/" + e, "expected shape [" + std::to_string(k) + " x 2]");
}

namespace {
/// A contact of two grains is the same whichever is i; a wall contact is (grain, wall).
std::uint64_t unordered_pair(std::int32_t i, std::int32_t j) {
  const auto a = j < 0 ? i : std::max(i, j), b = j < 0 ? j : std::min(i, j);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}
}  // namespace

double RunReader::length_scale() const { return std::max(header_.box.width, header_.box.height); }

double RunReader::speed_bound() const {
  double g = 9.81;
  if (auto it = header_.parameters.find(keys::gravity_m_s2); it != header_.parameters.end())
    if (const double* v = std::get_if<double>(&it->second); v && *v > 0 && std::isfinite(*v))
      g = *v;
  return 1e3 * std::sqrt(g * length_scale());
}

double RunReader::contact_reach() const {
  double h = 1e-4;
  if (auto it = header_.parameters.find("time_step_s"); it != header_.parameters.end())
    if (const double* v = std::get_if<double>(&it->second); v && *v > 0 && std::isfinite(*v))
      h = *v;
  return 10 * length_scale() + h * speed_bound();
}

double RunReader::force_bound() const {
  double h = 1e-4, mass = 0.0;
  if (auto it = header_.parameters.find("time_step_s"); it != header_.parameters.end())
    if (const double* v = std::get_if<double>(&it->second); v && *v > 0 && std::isfinite(*v))
      h = std::max(*v, 1e-9);
  for (double m : grains_.mass) mass += m;
  return mass * speed_bound() / h;
}

Contacts RunReader::contacts(std::size_t k) const {
  const h5::File& f = *f_;
  if (k >= frame_count()) bad(f, kContacts, "no frame " + std::to_string(k));
  const auto first = static_cast<hsize_t>(offset_[k]);
  const auto n = static_cast<hsize_t>(count_[k]);
  const std::string cg = kContacts;
  Contacts c;
  c.i = h5::read_rows<std::int32_t>(f, cg + "/i", first, n);
  c.j = h5::read_rows<std::int32_t>(f, cg + "/j", first, n);
  c.point = to_vec2(h5::read_rows<double>(f, cg + "/point", first, n));
  c.normal = to_vec2(h5::read_rows<double>(f, cg + "/normal", first, n));
  c.fn = h5::read_rows<double>(f, cg + "/fn", first, n);
  c.ft = h5::read_rows<double>(f, cg + "/ft", first, n);
  c.gap = h5::read_rows<double>(f, cg + "/gap", first, n);
  auto st = h5::read_rows<std::int8_t>(f, cg + "/status", first, n);
  c.status.resize(n);
  const auto grains = static_cast<std::int64_t>(n_);
  const double fmax = force_bound(), reach = contact_reach(), w = header_.box.width,
               ht = header_.box.height;
  for (std::size_t q = 0; q < n; ++q) {
    const std::string row = "row " + std::to_string(first + q);
    for (auto [force, name] : {std::pair{c.fn[q], "fn"}, std::pair{c.ft[q], "ft"}})
      if (!(std::fabs(force) <= fmax))
        bad(f, cg + "/" + name,
            row + ": a force of " + number_text(force) +
                " N/m, more than stops the whole pile moving at 1000 sqrt(g L) in one step (" +
                number_text(fmax) + " N/m)");
    if (c.i[q] < 0 || c.i[q] >= grains)
      bad(f, cg + "/i", row + ": grain id " + std::to_string(c.i[q]) + " out of range");
    if (c.j[q] < wall_right || c.j[q] >= grains || c.j[q] == c.i[q])
      bad(f, cg + "/j",
          row + ": id " + std::to_string(c.j[q]) + " is neither another grain nor a wall");
    if (c.fn[q] < 0) bad(f, cg + "/fn", row + ": negative normal force");
    if (!(std::fabs(c.gap[q]) <= reach))
      out_of_range(f, cg + "/gap", row, exact_text(c.gap[q]) + " m",
                   "[-" + number_text(reach) + ", " + number_text(reach) +
                       "] m (10 L + h times the speed bound)");
    const Vec2& p = c.point[q];
    if (!(p.x() >= -reach && p.x() <= w + reach && p.y() >= -reach && p.y() <= ht + reach))
      out_of_range(f, cg + "/point", row,
                   "(" + exact_text(p.x()) + ", " + exact_text(p.y()) + ") m",
                   "the box [0, " + number_text(w) + "] x [0, " + number_text(ht) +
                       "] m enlarged by " + number_text(reach) +
                       " m (10 L + h times the speed bound)");
    const double length = std::hypot(c.normal[q].x(), c.normal[q].y());  // no overflow
    if (!(std::fabs(length - 1) <= kUnitTolerance))
      out_of_range(f, cg + "/normal", row,
                   "(" + exact_text(c.normal[q].x()) + ", " + exact_text(c.normal[q].y()) + ")",
                   "the unit vectors (its length is " + number_text(length) +
                       ", not 1 to within 1e-6)");
    if (st[q] < 0 || st[q] > 2)
      bad(f, cg + "/status", row + ": unknown status " + std::to_string(st[q]));
    c.status[q] = static_cast<ContactStatus>(st[q]);
  }
  // One contact per pair: a pair listed twice would be counted twice by critical and
  // would give the engine two warm starts for one contact.
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(n);
  for (std::size_t q = 0; q < n; ++q) keys[q] = {unordered_pair(c.i[q], c.j[q]), q};
  std::sort(keys.begin(), keys.end());
  for (std::size_t q = 1; q < n; ++q)
    if (keys[q].first == keys[q - 1].first) {
      const std::size_t a = keys[q - 1].second, b = keys[q].second;
      bad(f, cg + "/i",
          "rows " + std::to_string(first + a) + " and " + std::to_string(first + b) +
              ": the contact of " + std::to_string(c.i[a]) + " and " + std::to_string(c.j[a]) +
              " is listed twice in frame " + std::to_string(k));
    }
  return c;
}

// Magnitudes a pile can have (docs/cli.md, "What is refused"): every centre inside the
// box enlarged by L = max(width, height) on every side, and no grain faster than
// 1000 sqrt(g L) (1000 times the speed of a fall through the box), its rim included.
// Beyond them the engine's cell grid would need more cells than memory holds.
void RunReader::check_grain_state(const Grains& g, const std::string& path,
                                  const std::string& velocity_path, const std::string& what) const {
  const h5::File& f = *f_;
  const double w = header_.box.width, h = header_.box.height, L = length_scale(),
               vmax = speed_bound();
  for (std::size_t q = 0; q < g.size(); ++q) {
    const Vec2& x = g.position[q];
    if (x.x() < -L || x.x() > w + L || x.y() < -L || x.y() > h + L)
      bad(f, path,
          what + ": grain " + std::to_string(q) + " at (" + number_text(x.x()) + ", " +
              number_text(x.y()) + ") m is outside the box [0, " + number_text(w) + "] x [0, " +
              number_text(h) + "] m enlarged by " + number_text(L) + " m");
    const double v = g.velocity[q].norm() + std::fabs(g.angular_velocity[q]) * g.radius[q];
    if (!(v <= vmax))
      bad(f, velocity_path,
          what + ": grain " + std::to_string(q) + " moves at " + number_text(v) +
              " m/s (its rim included), more than 1000 sqrt(g L) = " + number_text(vmax) + " m/s");
  }
}

Frame RunReader::frame(std::size_t k) const {
  const h5::File& f = *f_;
  if (k >= frame_count()) bad(f, kGrains, "no frame " + std::to_string(k));
  Frame fr;
  fr.step = frame_steps_[k];
  fr.time = frame_time_[k];
  fr.tilt_angle = frame_tilt_[k];
  fr.grains = grains_;
  fr.grains.position = to_vec2(h5::read_rows<double>(f, grain_path("position") + "/value", k, 1));
  fr.grains.velocity = to_vec2(h5::read_rows<double>(f, grain_path("velocity") + "/value", k, 1));
  fr.grains.orientation = h5::read_rows<double>(f, grain_path("orientation") + "/value", k, 1);
  fr.grains.angular_velocity =
      h5::read_rows<double>(f, grain_path("angular_velocity") + "/value", k, 1);
  check_grain_state(fr.grains, grain_path("position") + "/value",
                    grain_path("velocity") + "/value", "frame " + std::to_string(k));
  fr.contacts = contacts(k);
  return fr;
}

void RunReader::check_observables() const {
  // A finished run always records its per-step observables; a pile may lack them, and a
  // run being written (OUTPUT.partial) has none before its first checkpoint, which is why
  // the constructor does not check this.
  if (header_.kind != "run") return;
  if (!h5::exists(*f_, kObservables))
    bad(*f_, kObservables, "missing group (a run records its per-step observables)");
  if (h5::members(*f_, kObservables).empty())
    bad(*f_, kObservables, "no observable (a run records its per-step observables)");
}

namespace {
/// The range of each standard observable (docs/schema.md, "Standard observables" and
/// "Ranges"): counts are integers in [0, 2^53] (the readers turn them into doubles and
/// back), converged is 0 or 1, energies, residuals and magnitudes are >= 0, the tilt is in
/// [-90, 90] degrees. A column the table does not name is only finite.
struct ObservableRange {
  const char* name;
  double min, max;
  bool integer;
};
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr ObservableRange kObservableRanges[] = {
    {"tilt_angle", -kTiltMaxDeg, kTiltMaxDeg, false},
    {"kinetic_energy", 0, kInf, false},
    {"rotational_energy", 0, kInf, false},
    {"contacts", 0, kExactInteger, true},
    {"contacts_grain", 0, kExactInteger, true},
    {"sliding", 0, kExactInteger, true},
    {"sweeps", 0, kExactInteger, true},
    {"substeps", 0, kExactInteger, true},
    {"finishes", 0, kExactInteger, true},
    {"residual", 0, kInf, false},
    {"residual_rms", 0, kInf, false},
    {"law_residual", 0, kInf, false},
    {"law_residual_rms", 0, kInf, false},
    {"converged", 0, 1, true},
    {"max_overlap", 0, kInf, false},
    {"max_speed", 0, kInf, false},
    {"grains_without_contact", 0, kExactInteger, true},
    {"critical", 0, kExactInteger, true},
    {"critical_grain", 0, kExactInteger, true},
};

std::string range_text(const ObservableRange& r) {
  auto end = [](double x) { return x == kExactInteger ? std::string("2^53") : exact_text(x); };
  return std::string(r.integer ? "the integers of " : "") + "[" + end(r.min) + ", " +
         (r.max == kInf ? std::string("inf)") : end(r.max) + "]");
}

void check_observable(const h5::File& f, const std::string& name, const std::string& path,
                      const Series& s) {
  const auto* r = std::find_if(std::begin(kObservableRanges), std::end(kObservableRanges),
                               [&](const ObservableRange& x) { return name == x.name; });
  if (r == std::end(kObservableRanges)) return;
  auto check = [&](std::size_t k, double v, const std::string& text) {
    if (!(v >= r->min && v <= r->max) || (r->integer && v != std::floor(v)))
      out_of_range(f, path, "row " + std::to_string(k), text, range_text(*r));
  };
  if (auto it = s.integer.find(name); it != s.integer.end())
    for (std::size_t k = 0; k < it->second.size(); ++k)
      check(k, static_cast<double>(it->second[k]), integer_text(it->second[k]));
  if (auto it = s.real.find(name); it != s.real.end())
    for (std::size_t k = 0; k < it->second.size(); ++k)
      check(k, it->second[k], exact_text(it->second[k]));
}
}  // namespace

Series RunReader::series() const {
  const h5::File& f = *f_;
  check_observables();
  Series s;
  if (!h5::exists(f, kObservables)) return s;
  auto names = h5::members(f, kObservables);
  if (names.empty()) return s;
  const std::string clock = std::string(kObservables) + "/" + names.front();
  std::vector<hsize_t> dims;
  s.step = h5::read<std::int64_t>(f, clock + "/step", {h5::any}, &dims);
  s.time = h5::read<double>(f, clock + "/time", {dims[0]});
  check_clock(f, clock + "/step", s.step, clock + "/time", s.time, "row");
  for (const auto& n : names) {
    const std::string p = std::string(kObservables) + "/" + n + "/value";
    if (!h5::exists(f, p)) bad(f, std::string(kObservables) + "/" + n, "missing value dataset");
    hid_t d = H5Dopen2(f.id(), p.c_str(), H5P_DEFAULT);
    h5::Handle dh(d);
    h5::Handle t(H5Dget_type(d));
    if (H5Tget_class(t.id()) == H5T_INTEGER)
      s.integer[n] = h5::read<std::int64_t>(f, p, {dims[0]});
    else
      s.real[n] = h5::read<double>(f, p, {dims[0]});
    s.unit[n] = h5::has_attr(f, p, "unit") ? h5::attr_string(f, p, "unit") : "";
    check_observable(f, n, p, s);
  }
  return s;
}

}  // namespace cdpile::io
