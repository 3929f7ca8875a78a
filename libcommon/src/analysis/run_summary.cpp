// A run's summary: its RunRecord and its localnu part as tables, and back
// (analysis/run_summary.hpp; docs/analysis.md, "Summaries").
#include "cdpile/analysis/run_summary.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace cdpile::analysis {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

std::string text_of(const Value& v) {
  if (auto* s = std::get_if<std::string>(&v)) return *s;
  char buf[32];
  std::to_chars_result r{};
  if (auto* i = std::get_if<std::int64_t>(&v))
    r = std::to_chars(buf, buf + sizeof buf, *i);
  else
    r = std::to_chars(buf, buf + sizeof buf, std::get<double>(v));
  return std::string(buf, r.ptr);
}

// Values compared as numbers when both are (1e-3 and 0.001, an integer and a real: the
// same double), else as text.
bool same(const Value& a, const Value& b) {
  const auto num = [](const Value& v) -> std::optional<double> {
    if (auto* d = std::get_if<double>(&v)) return *d;
    if (auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
    return std::nullopt;
  };
  const auto x = num(a), y = num(b);
  if (x && y) return *x == *y;
  return text_of(a) == text_of(b);
}

std::string list_text(const std::vector<double>& v) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : ",") + text_of(Value(x));
  return s;
}

double opt_value(const std::optional<double>& v) { return v ? *v : nan; }
std::optional<double> opt_of(const Column& c, std::size_t r) { return c.get(r); }

// ---- the tables of a RunRecord: one row per column, with its getter and its setter ----

struct StepColumn {
  const char* name;
  const char* unit;
  ColumnKind kind;
  std::vector<std::int64_t> RunSteps::*ints;
  std::vector<double> RunSteps::*reals;
  bool optional;
};

// RunSteps, column by column (the series that are absent are left out of the table).
const std::vector<StepColumn>& step_columns() {
  static const std::vector<StepColumn> c = {
      {"step", "", ColumnKind::integer, &RunSteps::step, nullptr, false},
      {"theta", "deg", ColumnKind::real, nullptr, &RunSteps::theta, false},
      {"contacts", "", ColumnKind::integer, &RunSteps::contacts, nullptr, false},
      {"critical", "", ColumnKind::integer, &RunSteps::critical, nullptr, true},
      {"sliding", "", ColumnKind::integer, &RunSteps::sliding, nullptr, true},
      {"kinetic_energy", "J/m", ColumnKind::real, nullptr, &RunSteps::kinetic_energy, true},
      {"rotational_energy", "J/m", ColumnKind::real, nullptr, &RunSteps::rotational_energy, true},
      {"converged", "", ColumnKind::integer, &RunSteps::converged, nullptr, true},
      {"max_speed", "m/s", ColumnKind::real, nullptr, &RunSteps::max_speed, true},
      {"grains_without_contact", "", ColumnKind::integer, &RunSteps::grains_without_contact,
       nullptr, true},
      {"sweeps", "", ColumnKind::integer, &RunSteps::sweeps, nullptr, true},
      {"substeps", "", ColumnKind::integer, &RunSteps::substeps, nullptr, true},
  };
  return c;
}

// FrameRecord, column by column: a value (NaN = empty) and how to put it back.
struct FrameColumn {
  std::string name;
  const char* unit;
  ColumnKind kind;
  std::function<double(const FrameRecord&)> get;
  std::function<void(FrameRecord&, std::optional<double>)> set;
};

std::int64_t as_int(std::optional<double> v) { return v ? static_cast<std::int64_t>(*v) : 0; }
std::optional<std::int64_t> opt_int(std::optional<double> v) {
  if (!v) return std::nullopt;
  return static_cast<std::int64_t>(*v);
}
double int_value(const std::optional<std::int64_t>& v) {
  return v ? static_cast<double>(*v) : nan;
}

#define CDPILE_INT(field) \
  [](const FrameRecord& f) { return static_cast<double>(f.field); }, \
      [](FrameRecord& f, std::optional<double> v) { f.field = as_int(v); }
#define CDPILE_OPT(field) \
  [](const FrameRecord& f) { return opt_value(f.field); }, \
      [](FrameRecord& f, std::optional<double> v) { f.field = v; }
#define CDPILE_OPT_INT(field) \
  [](const FrameRecord& f) { return int_value(f.field); }, \
      [](FrameRecord& f, std::optional<double> v) { f.field = opt_int(v); }

const std::vector<FrameColumn>& frame_columns() {
  using K = ColumnKind;
  static const std::vector<FrameColumn> c = [] {
    std::vector<FrameColumn> cols = {
        {"frame", "", K::integer, CDPILE_INT(frame)},
        {"step", "", K::integer, CDPILE_INT(step)},
        {"theta", "deg", K::real,
         [](const FrameRecord& f) { return f.theta; },
         [](FrameRecord& f, std::optional<double> x) { f.theta = x.value_or(nan); }},
        {"N", "", K::integer, CDPILE_INT(state.contacts)},
        {"Nc", "", K::integer, CDPILE_INT(state.critical)},
        {"sliding", "", K::integer, CDPILE_INT(state.sliding)},
        {"grains", "", K::integer, CDPILE_INT(state.grains)},
        {"loaded_grains", "", K::integer, CDPILE_INT(state.loaded_grains)},
        {"nu", "", K::real, CDPILE_OPT(state.nu)},
        {"nu_sliding", "", K::real, CDPILE_OPT(state.nu_sliding)},
        {"z", "", K::real, CDPILE_OPT(state.z)},
        {"z_all", "", K::real, CDPILE_OPT(state.z_all)},
        {"lambda", "m", K::real, CDPILE_OPT(state.lambda)},
        {"kinetic_energy", "J/m", K::real, CDPILE_OPT(kinetic_energy)},
        {"bound_contacts", "", K::integer,
         [](const FrameRecord& f) { return f.bound ? static_cast<double>(f.bound->contacts) : nan; },
         [](FrameRecord& f, std::optional<double> x) {
           if (x) (f.bound ? *f.bound : f.bound.emplace()).contacts = as_int(x);
         }},
        {"bound_grains", "", K::integer,
         [](const FrameRecord& f) { return f.bound ? static_cast<double>(f.bound->grains) : nan; },
         [](FrameRecord& f, std::optional<double> x) {
           if (x) (f.bound ? *f.bound : f.bound.emplace()).grains = as_int(x);
         }},
        {"bound_critical", "", K::integer,
         [](const FrameRecord& f) { return f.bound ? static_cast<double>(f.bound->critical) : nan; },
         [](FrameRecord& f, std::optional<double> x) {
           if (x) (f.bound ? *f.bound : f.bound.emplace()).critical = as_int(x);
         }},
        {"agitation", "J/m", K::real, CDPILE_OPT(agitation)},
        {"max_speed", "m/s", K::real, CDPILE_OPT(max_speed)},
        {"grains_without_contact", "", K::integer, CDPILE_INT(grains_without_contact)},
        {"z_paper", "", K::real, CDPILE_OPT(z_paper)},
        {"slipping", "", K::integer, CDPILE_OPT_INT(slipping)},
        {"critical_slipping", "", K::integer, CDPILE_OPT_INT(critical_slipping)},
        {"contacts_at_rest", "", K::integer, CDPILE_OPT_INT(contacts_at_rest)},
        {"critical_at_rest", "", K::integer, CDPILE_OPT_INT(critical_at_rest)},
    };
    // the mobilisation histogram, a column per bin, NA when it was not computed
    for (std::size_t b = 0; b < mobilisation_bins; ++b) {
      cols.push_back({"mobilisation_" + std::to_string(b), "", K::integer,
                   [b](const FrameRecord& f) {
                     return f.mobilisation.empty() ? nan
                                                   : static_cast<double>(f.mobilisation[b]);
                   },
                   [b](FrameRecord& f, std::optional<double> x) {
                     if (!x) return;
                     f.mobilisation.resize(mobilisation_bins, 0);
                     f.mobilisation[b] = as_int(x);
                   }});
    }
    return cols;
  }();
  return c;
}

#undef CDPILE_INT
#undef CDPILE_OPT
#undef CDPILE_OPT_INT

// A table of `p` copied under another name.
void copy_table(Product& into, const Product& from, const std::string& name,
                const std::string& as) {
  Table t = from.table(name);
  t.name = as;
  into.tables.push_back(std::move(t));
}

const std::string& text_parameter(const Product& p, const std::string& key) {
  auto it = p.parameters.find(key);
  if (it == p.parameters.end() || !std::holds_alternative<std::string>(it->second))
    throw Error(p.source, "/parameters", "a summary without its text parameter " + key);
  return std::get<std::string>(it->second);
}

double number(const Values& v, const std::string& key, const std::string& source,
              const char* where) {
  if (auto x = detail::number(v, key)) return *x;
  throw Error(source, where, "a summary without " + key);
}

}  // namespace

Values critical_reading(const CriticalRule& rule, const Friction& mu, RattlerRule rattlers,
                        double slip_speed, double rest_speed) {
  return {{"reading_definitions", summary_definitions},
          {"reading_eps", rule.eps},
          {"reading_walls", std::int64_t{rule.include_walls}},
          {"reading_floor_grains", std::string(rule.floor_grains_are_walls ? "wall" : "grain")},
          {"reading_mu", mu.grain},
          {"reading_mu_wall", mu.wall},
          {"reading_rattlers", std::string(rattlers == RattlerRule::exclude ? "exclude" : "include")},
          {"reading_slip_speed", slip_speed},
          {"reading_rest_speed", rest_speed}};
}

Values localnu_reading(const LocalNuOptions& opt, const CriticalRule& rule, const Friction& mu,
                       const AvalancheRule& avalanche, std::optional<double> theta_c,
                       std::optional<double> diameter) {
  Values v = {{"reading_definitions", summary_definitions},
              {"reading_eps", rule.eps},
              {"reading_walls", std::int64_t{rule.include_walls}},
              {"reading_floor_grains", std::string(rule.floor_grains_are_walls ? "wall" : "grain")},
              {"reading_mu", mu.grain},
              {"reading_mu_wall", mu.wall},
              {"reading_radii", list_text(opt.radii)},
              {"reading_exclude_self", std::int64_t{opt.exclude_self}},
              {"reading_edge", std::string(opt.edge == EdgeRule::keep ? "keep" : "exclude")},
              {"reading_pdf_radius", opt.pdf_radius},
              {"reading_pdf_bins", static_cast<std::int64_t>(opt.pdf_bins)},
              {"reading_pdf_from", opt.pdf_theta ? text_of(Value(opt.pdf_theta->lo)) : "loading"},
              {"reading_pdf_to", opt.pdf_theta ? text_of(Value(opt.pdf_theta->hi)) : "loading"},
              {"reading_theta_c", theta_c ? text_of(Value(*theta_c)) : std::string("rule")},
              {"reading_avalanche_ek", avalanche.threshold},
              {"reading_avalanche_hold", avalanche.hold},
              {"reading_diameter", diameter ? text_of(Value(*diameter)) : std::string("run")},
              {"reading_map_radius", opt.map_radius},
              {"reading_map_spacing", opt.map_spacing}};
  return v;
}

Friction summary_friction(const Product& s) {
  return {number(s.parameters, "reading_mu", s.source, "/parameters"),
          number(s.parameters, "reading_mu_wall", s.source, "/parameters")};
}

void require_reading(const Product& s, const Values& asked) {
  for (const auto& [key, want] : asked) {
    auto it = s.parameters.find(key);
    if (it == s.parameters.end())
      throw Error(s.source, "/parameters",
                  "a summary without " + key + ": summarise the run again");
    if (!same(it->second, want))  // the setting named as its option: reading_eps is --eps
      throw Error(s.source, "/parameters",
                  "made with " + field(key.substr(std::string("reading_").size())) + " " +
                      text_of(it->second) + ", asked " + text_of(want) +
                      ": summarise the run again with these settings, or ask for the summary's");
  }
}

std::optional<std::string> engine_difference(const Product& a, const Product& b) {
  // What differs from run to run of one study: the seed and what it draws (the grains glued
  // to the floor; the stiffness in N/m^2, k m g / D of the run's own grains, whose setting
  // is run_contact_stiffness_mgD).
  static const std::vector<std::string> per_run = {"run_seed", "run_floor_grains",
                                                   "run_contact_stiffness_N_m2"};
  auto engine = [&](const Product& p) {
    Values v;
    for (const auto& [k, x] : p.parameters)
      if (k.rfind("run_", 0) == 0 && k != "run_name" &&
          std::find(per_run.begin(), per_run.end(), k) == per_run.end())
        v[k] = x;
    return v;
  };
  const Values ea = engine(a), eb = engine(b);
  for (const auto& [k, x] : ea) {
    auto it = eb.find(k);
    if (it == eb.end()) return k + " " + text_of(x) + " in " + a.source + ", none in " + b.source;
    if (!same(x, it->second))
      return k + " " + text_of(x) + " in " + a.source + ", " + text_of(it->second) + " in " +
             b.source;
  }
  for (const auto& [k, x] : eb)
    if (!ea.count(k)) return k + " " + text_of(x) + " in " + b.source + ", none in " + a.source;
  return std::nullopt;
}

void require_same_engine(const Product& first, const Product& s, const std::string& name) {
  if (auto d = engine_difference(first, s))
    throw Error(name, "/parameters", "its run was made otherwise than the first summary's: " + *d);
}

Product make_summary(const RunRecord& run, const Values& critical, const Product& localnu,
                     const Values& localnu_settings, const std::vector<double>& map_thetas,
                     const std::vector<Product>& maps, const Values& run_parameters) {
  if (maps.size() != map_thetas.size()) throw Error("make_summary: a map per angle");
  Product p;
  p.kind = summary_kind;
  for (const auto& [k, v] : critical) p.parameters[k] = v;
  for (const auto& [k, v] : localnu_settings) {
    auto it = p.parameters.find(k);
    if (it != p.parameters.end() && !same(it->second, v))
      throw Error(run.name, "", "critical and localnu read it with different " + k);
    p.parameters[k] = v;
  }
  for (const auto& [k, v] : run_parameters) p.parameters["run_" + k] = v;
  p.parameters["run_name"] = run.name;
  // The stiffness as it was given, in m g/D (the run records k m g / D in N/m^2, with D its
  // diameter_mean_m and m its grains' mean mass, as tilt-cd converts it), to 6 digits: what
  // tells one study's engine from another's.
  const double d = detail::number(run_parameters, "diameter_mean_m").value_or(run.diameter);
  if (auto k = detail::number(run_parameters, "contact_stiffness_N_m2");
      k && run.mean_mass > 0.0 && run.gravity > 0.0) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", *k * d / (run.mean_mass * run.gravity));
    p.parameters["run_contact_stiffness_mgD"] = std::stod(buf);
  }
  p.parameters["reading_map_theta"] = list_text(map_thetas);
  p.notes = {"the per-run quantities of one run, from which critical and localnu make the "
             "ensemble products they make from the runs (docs/analysis.md, \"Summaries\")"};

  p.results["free_grains"] = run.free_grains;
  p.results["diameter_m"] = run.diameter;
  p.results["mean_mass_kg_m"] = run.mean_mass;
  p.results["gravity_m_s2"] = run.gravity;
  if (run.recorded_avalanche) p.results["avalanche_recorded_deg"] = *run.recorded_avalanche;
  if (run.recorded_rule.eps) p.results["recorded_eps"] = *run.recorded_rule.eps;
  if (run.recorded_rule.mu_grain) p.results["recorded_mu_grain"] = *run.recorded_rule.mu_grain;
  if (run.recorded_rule.mu_wall) p.results["recorded_mu_wall"] = *run.recorded_rule.mu_wall;

  Table& steps = p.add_table("steps", "the run's per-step observables, as critical reads them");
  for (const StepColumn& c : step_columns()) {
    const std::size_t n =
        c.ints ? (run.steps.*c.ints).size() : (run.steps.*c.reals).size();
    if (c.optional && n == 0) continue;  // a series the run does not record
    Column& col = steps.add_column(c.name, c.unit, c.kind);
    if (c.ints)
      for (std::int64_t v : run.steps.*c.ints) col.add_int(v);
    else
      for (double v : run.steps.*c.reals) col.num.push_back(v);
  }
  Table& frames = p.add_table("frames", "the run's frames, as critical reads them");
  for (const FrameColumn& c : frame_columns()) {
    Column& col = frames.add_column(c.name, c.unit, c.kind);
    for (const FrameRecord& f : run.frames) col.num.push_back(c.get(f));
  }

  copy_table(p, localnu, "frames", "localnu_frames");
  copy_table(p, localnu, "states", "localnu_states");
  // nu_bar and se follow from n, sum and sum2 (LocalNuStudy::add_summary): not kept
  Table& states = p.tables.back();
  std::erase_if(states.columns,
                [](const Column& c) { return c.name == "nu_bar" || c.name == "se"; });
  copy_table(p, localnu, "pdf", "localnu_pdf");
  if (localnu.find("map")) copy_table(p, localnu, "map", "localnu_map");
  for (const auto& [k, v] : localnu.results)
    p.results["localnu_" + k] = v;
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const std::string name = "map" + std::to_string(m + 1);
    copy_table(p, maps[m], "map", name);
    p.results[name + "_asked_deg"] = map_thetas[m];
    for (const auto& [k, v] : maps[m].results)
      if (k.rfind("map_", 0) == 0) p.results[name + "_" + k.substr(4)] = v;
  }
  return p;
}

RunRecord summary_run_record(const Product& s) {
  if (s.kind != summary_kind)
    throw Error(s.source, "", "is a '" + s.kind + "' product, expected a 'summary'");
  RunRecord r;
  r.name = text_parameter(s, "run_name");
  const char* res = "/results";
  r.free_grains = static_cast<std::int64_t>(number(s.results, "free_grains", s.source, res));
  r.diameter = number(s.results, "diameter_m", s.source, res);
  r.mean_mass = number(s.results, "mean_mass_kg_m", s.source, res);
  r.gravity = number(s.results, "gravity_m_s2", s.source, res);
  r.recorded_avalanche = s.result("avalanche_recorded_deg");
  r.recorded_rule = {s.result("recorded_eps"), s.result("recorded_mu_grain"),
                     s.result("recorded_mu_wall")};
  r.mu = summary_friction(s);

  const Table& steps = s.table("steps");
  const std::size_t n = steps.rows();
  for (const StepColumn& c : step_columns()) {
    const Column* col = steps.find(c.name);
    if (!col) {
      if (c.optional) continue;
      throw Error(s.source, "/tables/steps", std::string("no column ") + c.name);
    }
    for (std::size_t k = 0; k < n; ++k) {
      const auto v = col->get(k);
      if (!v) throw Error(s.source, "/tables/steps", std::string(c.name) + ": NA in row " + std::to_string(k));
      if (c.ints)
        (r.steps.*c.ints).push_back(static_cast<std::int64_t>(*v));
      else
        (r.steps.*c.reals).push_back(*v);
    }
  }
  const Table& frames = s.table("frames");
  const std::size_t m = frames.rows();
  r.frames.resize(m);
  for (const FrameColumn& c : frame_columns()) {
    const Column* col = frames.find(c.name);
    if (!col) throw Error(s.source, "/tables/frames", "no column " + c.name);
    for (std::size_t k = 0; k < m; ++k) c.set(r.frames[k], opt_of(*col, k));
  }
  return r;
}

std::optional<std::pair<Table, Values>> summary_map(const Product& s, std::optional<double> theta) {
  auto map_values = [&](const std::string& prefix) {
    Values v;
    for (const auto& [k, x] : s.results)
      if (k.rfind(prefix, 0) == 0 && k != prefix + "asked_deg")
        v["map_" + k.substr(prefix.size())] = x;
    return v;
  };
  if (!theta) {
    const Table* t = s.find("localnu_map");
    if (!t) return std::nullopt;
    Table map = *t;
    map.name = "map";
    return std::make_pair(map, map_values("localnu_map_"));
  }
  for (std::size_t m = 1;; ++m) {
    const std::string name = "map" + std::to_string(m);
    const Table* t = s.find(name);
    if (!t) return std::nullopt;
    const auto asked = s.result(name + "_asked_deg");
    if (asked && same(Value(*asked), Value(*theta))) {
      Table map = *t;
      map.name = "map";
      return std::make_pair(map, map_values(name + "_"));
    }
  }
}

}  // namespace cdpile::analysis
