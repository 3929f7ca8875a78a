// The tilt protocol's options, as run parameters and back, and a branch's or a resume's
// (tilt_options.hpp; docs/method.md, "Tilt"); the table of run parameters, from which the
// engine settings' parameters (common.hpp) derive too.
#include "cdpile/sim/tilt_options.hpp"

#include "cdpile/analysis/critical_option.hpp"
#include "cdpile/cd/schedule.hpp"
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/parameter_keys.hpp"
#include "cdpile/sim/avalanche.hpp"
#include "cdpile/sim/common.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>
#include <type_traits>

namespace cdpile::sim {

namespace {

// The object holding a field of class C: the options themselves, or their engine settings
// (cd::Settings and its bases TimeStepping and SolverSettings).
template <class C>
C& owner(TiltOptions& o) {
  if constexpr (std::is_same_v<C, TiltOptions>) {
    return o;
  } else {
    static_assert(std::is_base_of_v<C, cd::Settings>);
    return o.settings;
  }
}
template <class C>
const C& owner(const TiltOptions& o) {
  return owner<C>(const_cast<TiltOptions&>(o));
}

const std::string& text_of(const io::Values& v, const std::string& key, const std::string& file) {
  const auto c = v.find(key);
  const std::string* name = c == v.end() ? nullptr : std::get_if<std::string>(&c->second);
  if (!name) throw Error(file, "/parameters", "missing text parameter '" + key + "'");
  return *name;
}

// A row's accessors for a field of each recorded kind: a real, an integer (int, int64,
// the scramble seed, a bool as 0/1), an optional real (-1 for none: tilt_to_deg) and an
// enum recorded by its name.
template <class C, class M>
void bind(RunParameter& p, M C::*field) {
  p.get = [field](const TiltOptions& o) -> io::Value {
    const M& x = owner<C>(o).*field;
    if constexpr (std::is_same_v<M, double>) {
      return x;
    } else if constexpr (std::is_same_v<M, std::optional<double>>) {
      return x ? *x : -1.0;
    } else if constexpr (std::is_same_v<M, bool>) {
      return std::int64_t{x ? 1 : 0};
    } else {
      return static_cast<std::int64_t>(x);
    }
  };
  p.set = [field](TiltOptions& o, const io::Values& v, const std::string& name,
                  const std::string& file) {
    M& x = owner<C>(o).*field;
    if constexpr (std::is_same_v<M, double>) {
      x = io::as_real(v, name, file);
    } else if constexpr (std::is_same_v<M, std::optional<double>>) {
      const double d = io::as_real(v, name, file);
      x = d == -1.0 ? std::nullopt : std::optional<double>(d);  // -1: none
    } else if constexpr (std::is_same_v<M, bool>) {
      x = io::as_int(v, name, file) != 0;
    } else if constexpr (std::is_same_v<M, std::uint64_t>) {
      const std::int64_t i = io::as_int(v, name, file);
      if (i < 0) throw Error(file, "/parameters", name + " must be >= 0");
      x = static_cast<std::uint64_t>(i);
    } else {
      x = static_cast<M>(io::as_int(v, name, file));
    }
  };
  p.set_option = [field](TiltOptions& o, const std::optional<OptionValue>& v) {
    M& x = owner<C>(o).*field;
    if constexpr (std::is_same_v<M, std::optional<double>>) {
      x = v ? std::optional<double>(std::get<double>(*v)) : std::nullopt;
    } else if (v) {
      if constexpr (std::is_same_v<M, double>)
        x = std::get<double>(*v);
      else
        x = static_cast<M>(std::get<std::int64_t>(*v));
    }
  };
}

// The options' defaults: TiltOptions' own, its engine settings option_defaults().
TiltOptions option_defaults_of_tilt() {
  TiltOptions o;
  o.settings = option_defaults();
  return o;
}

// The option of a field of class C: real for a real field, else an integer, and the
// field's default value as the option's default (an empty optional: none).
template <class C, class M>
OptionDeclaration option_of(M C::*field) {
  OptionDeclaration d;
  const TiltOptions defaults = option_defaults_of_tilt();
  const M& x = owner<C>(defaults).*field;
  if constexpr (std::is_same_v<M, std::optional<double>>) {
    if (x) d.default_value = *x;
  } else if constexpr (std::is_same_v<M, double>) {
    d.default_value = x;
  } else {
    d.integer = true;
    d.default_value = static_cast<std::int64_t>(x);
  }
  return d;
}

template <class C, class E>
void bind_text(RunParameter& p, E C::*field, const char* (*to_name)(E),
               E (*from_name)(const std::string&)) {
  p.text = true;
  p.set_option = [=](TiltOptions& o, const std::optional<OptionValue>& v) {
    if (v) owner<C>(o).*field = from_name(std::get<std::string>(*v));
  };
  p.get = [=](const TiltOptions& o) -> io::Value {
    return std::string(to_name(owner<C>(o).*field));
  };
  p.set = [=](TiltOptions& o, const io::Values& v, const std::string& name,
              const std::string& file) { owner<C>(o).*field = from_name(text_of(v, name, file)); };
}

struct Row {
  RunParameter p;
  Row(const char* field, const char* key, const char* unit, const char* option,
      ParameterGroup group) {
    p.field = field;
    p.key = key;
    p.unit = unit;
    p.option = option;
    p.group = group;
    if (p.key.empty()) p.inherit = Inherit::as_asked;
  }
  OptionDeclaration declaration;  // the kind and default of the field bound by of()
  template <class C, class M>
  Row&& of(M C::*field) && {
    bind(p, field);
    declaration = option_of(field);
    return std::move(*this);
  }
  // tilt-cd's option declared here: its group in --help, help text, unit and range.
  Row&& declared(const char* group, const char* help, const char* unit, double min, double max) && {
    declaration.name = p.option;
    declaration.field = p.field;
    declaration.group = group;
    declaration.help = help;
    declaration.unit = unit;
    declaration.min = min;
    declaration.max = max;
    p.declaration = declaration;
    return std::move(*this);
  }
  // tilt-cd's option as the library declares it for other tools too: the same option, so
  // its name must be the row's and its default the field's.
  Row&& declared(OptionDeclaration shared) && {
    if (shared.name != p.option || shared.default_value != declaration.default_value)
      throw std::logic_error("--" + shared.name + " declared for the row of " + p.field +
                             " with another name or default");
    shared.field = p.field;
    declaration = shared;
    p.declaration = declaration;
    return std::move(*this);
  }
  // A name, one of `choices`, the field's default's name as the option's default.
  Row&& declared(const char* group, const char* help, std::vector<std::string> choices) && {
    declaration.choices = std::move(choices);
    return std::move(*this).declared(group, help, "", -1e308, 1e308);
  }
  template <class C, class E>
  Row&& of_text(E C::*field, const char* (*to_name)(E), E (*from_name)(const std::string&)) && {
    bind_text(p, field, to_name, from_name);
    declaration.default_value = std::string(to_name(owner<C>(option_defaults_of_tilt()).*field));
    return std::move(*this);
  }
  // The option in D or m g / D, its default in that unit.
  Row&& scaled(OptionScale scale, double option_default) && {
    p.scale = scale;
    declaration.default_value = option_default;
    return std::move(*this);
  }
  // Of the declared option: listed after `option` in --help; its old spelling.
  Row&& after(const char* option) && {
    p.declaration->after = option;
    return std::move(*this);
  }
  Row&& old_name(const char* name) && {
    p.declaration->old_name = name;
    return std::move(*this);
  }
  Row&& accepts(Accepted a) && {
    p.accepted = a;
    return std::move(*this);
  }
  // An option without a default of its own: settings_from_options sets the field from
  // the contact stiffness when the option is not given.
  Row&& defaulted_by_stiffness() && {
    declaration.default_value = std::monostate{};
    return std::move(*this);
  }
  Row&& pre_seam(io::Value v) && {
    p.pre_seam = std::move(v);
    return std::move(*this);
  }
  Row&& also(const char* option) && {
    p.also_option = option;
    return std::move(*this);
  }
  Row&& shown(io::Value v, const char* word) && {
    p.shown_as = std::make_pair(std::move(v), std::string(word));
    return std::move(*this);
  }
};

// The ranges validate() holds the fields to (RunParameter::accepted).
Accepted at_least(double low) { return {low, false, std::nullopt, false}; }
Accepted above(double low) { return {low, true, std::nullopt, false}; }
const Accepted finite = {-HUGE_VAL, false, std::nullopt, true};
const Accepted positive_finite = {0.0, true, std::nullopt, true};
const Accepted fraction = {0.0, false, 1.0, false};  // [0, 1)

std::vector<RunParameter> make_table() {
  using O = TiltOptions;
  using S = cd::Settings;
  constexpr auto tilt = ParameterGroup::tilt, engine = ParameterGroup::settings;
  std::vector<Row> rows;
  // field, file key, unit of the recorded value, tilt-cd's option, group
  // and, declared here, tilt-cd's option: its group in --help, help text, unit and range
  rows.push_back(Row("rate_deg", "tilt_rate_deg_per_step", "degree", "rate", tilt)
                     .of(&O::rate_deg)
                     .declared("Tilt", "tilt per time step", "deg", 1e-12, 90.0)
                     .accepts(positive_finite));
  rows.push_back(Row("from_deg", "tilt_from_deg", "degree", "from", tilt)
                     .of(&O::from_deg)
                     .declared("Tilt", "tilt at the start", "deg", -90.0, 90.0)
                     .accepts(finite));
  rows.push_back(
      Row("to_deg", "tilt_to_deg", "degree", "to", tilt)
          .of(&O::to_deg)
          .shown(-1.0, "none")
          .declared("Tilt",
                    "run to this tilt, avalanche or not (default: the avalanche plus --margin)",
                    "deg", -90.0, 90.0));
  rows.push_back(Row("max_deg", "tilt_max_deg", "degree", "max-angle", tilt)
                     .of(&O::max_deg)
                     .declared("Tilt", "without --to, stop here if no avalanche is detected", "deg",
                               -90.0, 90.0));
  rows.push_back(Row("margin_deg", "avalanche_margin_deg", "degree", "margin", tilt)
                     .of(&O::margin_deg)
                     .declared("Tilt", "keep tilting this much after the avalanche is confirmed",
                               "deg", 0.0, 180.0)
                     .accepts(at_least(0.0)));
  // The avalanche rule's options are declared by its bundle (cli/avalanche_options.hpp),
  // shared with critical and localnu.
  rows.push_back(Row("avalanche_energy", "avalanche_energy", "", "avalanche-ek", tilt)
                     .of(&O::avalanche_energy)
                     .accepts(above(0.0)));
  rows.push_back(Row("avalanche_hold_deg", "avalanche_hold_deg", "degree", "avalanche-hold", tilt)
                     .of(&O::avalanche_hold_deg)
                     .accepts(at_least(0.0)));
  // Declared with the analysis tools' --eps (analysis/critical_option.hpp).
  rows.push_back(Row("eps", keys::critical_eps, "", "eps", tilt)
                     .of(&O::eps)
                     .declared(analysis::eps_option("Avalanche"))
                     .accepts(fraction));
  // Two options, --frame-every and --frame-every-deg, declared and read by tilt-cd.
  rows.push_back(Row("frame_every", "frame_every_steps", "", "frame-every", tilt)
                     .of(&O::frame_every)
                     .also("frame-every-deg"));
  // The friction's options are declared by their bundle (cli/friction_options.hpp), shared
  // with the analysis tools; the engine's others, the "Solver" group, here: deposit and
  // tilt-cd declare them alike (docs/method.md gives each default's reason).
  rows.push_back(Row("mu_grain", keys::mu_grain, "", "mu", engine).of(&S::mu_grain));
  rows.push_back(Row("mu_wall", keys::mu_wall, "", "mu-wall", engine).of(&S::mu_wall));
  rows.push_back(
      Row("time_step", "time_step_s", "s", "time-step", engine)
          .of(&S::time_step)
          .declared("Solver", "time step h (h sqrt(g/D) = 0.0099 at D = 1 mm)", "s", 1e-12, 1.0));
  // The option's old spelling, beside theta the tilt everywhere else.
  rows.push_back(
      Row("theta", "theta", "", "theta-method", engine)
          .of(&S::theta)
          .declared(
              "Solver",
              "theta-method parameter of the Moreau-Jean scheme (theta, the tilt, is another)", "",
              0.5, 1.0)
          .old_name("theta"));
  rows.push_back(
      Row("tolerance", "tolerance", "", "tolerance", engine)
          .of(&S::tolerance)
          .declared("Solver",
                    "NSGS convergence threshold of --criterion, relative to the velocity scale", "",
                    1e-15, 1.0));
  // The cap and the sub-steps default by the contacts, rigid or compliant
  // (settings_from_options): absent when not given, not defaulted.
  rows.push_back(Row("max_sweeps", "max_sweeps", "", "max-sweeps", engine)
                     .of(&S::max_sweeps)
                     .defaulted_by_stiffness()
                     .declared("Solver",
                               "cap of NSGS sweeps per step (hitting it is counted and reported); "
                               "default 2000, 100000 with --stiffness 0, whose steps are not "
                               "split (docs/method.md, \"Sub-steps\")",
                               "", 1, 100000000));
  rows.push_back(
      Row("criterion", "criterion", "", "criterion", engine)
          .of_text(&S::criterion, cd::criterion_name, cd::criterion_from_name)
          .declared("Solver",
                    "when NSGS stops: 'maxm', every contact's velocity correction <= tolerance; "
                    "'quad', their root mean square <= tolerance; 'qm16', quad and every "
                    "correction <= 16.66 tolerance (LMGC90's names); 'law', the contact law's "
                    "residual <= tolerance g h, whatever the solver; 'err', the error estimated "
                    "from the largest correction and the measured contraction per sweep <= "
                    "tolerance (docs/method.md)",
                    {"maxm", "quad", "qm16", "law", "err"}));
  rows.push_back(Row("check_every", "check_every", "", "check-every", engine)
                     .of(&S::check_every)
                     .pre_seam(std::int64_t{1})
                     .declared("Solver",
                               "sweeps between two tests of --criterion (LMGC90 tests every 50)",
                               "", 1, 100000000));
  rows.push_back(
      Row("solver", "solver", "", "solver", engine)
          .of_text(&S::solver, cd::solver_name, cd::solver_from_name)
          .pre_seam(std::string("nsgs"))
          .declared("Solver",
                    "contact solver: 'nsgs', non-smooth Gauss-Seidel; 'nncg', NSGS with a "
                    "nonlinear conjugate-gradient step after each sweep; 'pcg', NSGS alternating "
                    "with conjugate gradients on the contacts' active set, for compliant "
                    "contacts; 'newton', NSGS alternating with exact Newton steps on the active "
                    "set by a sparse LU, for compliant contacts; 'admm', ADMM on the step's "
                    "problem with one sparse Cholesky factor, then pcg (measured slower than "
                    "pcg at every stiffness, rigid included: docs/method.md)",
                    {"nsgs", "nncg", "pcg", "newton", "admm"}));
  // The option is in m g / D, by default compliant contacts whose steps converge
  // (docs/method.md, "Defaults and their reasons"); the record in N/m^2.
  rows.push_back(
      Row("contact_stiffness", "contact_stiffness_N_m2", "N m-2", "stiffness", engine)
          .of(&S::contact_stiffness)
          .pre_seam(0.0)
          .scaled(OptionScale::weight_per_diameter, 1e6)
          .declared("Solver",
                    "contact stiffness k of the force-selection rule, in m g / D (m the mean "
                    "grain mass, D the mean diameter): the compliance 1/(k h^2) anchored at the "
                    "previous step's impulses picks the step's forces near the previous ones; 0 "
                    "for rigid contacts, whose steps are not split by default (--max-substeps) "
                    "(docs/method.md, \"Force selection\")",
                    "m g/D", 0.0, 1e300));
  // Files made before it was a parameter had no dashpot (0).
  rows.push_back(
      Row("contact_damping_ratio", "contact_damping_ratio", "", "damping-ratio", engine)
          .of(&S::contact_damping_ratio)
          .pre_seam(0.0)
          .declared("Solver",
                    "damping ratio zeta of a contact dashpot beside the --stiffness spring, for "
                    "a contact of two grains of the mean mass m (eta = 2 zeta sqrt(k m / 2); "
                    "1: critical, no rebound); 0: none, the spring alone (docs/method.md, "
                    "\"The contact dashpot\")",
                    "", 0.0, 1e6));
  rows.push_back(
      Row("scramble", "scramble_seed", "", "scramble", engine)
          .of(&S::scramble)
          .pre_seam(std::int64_t{0})
          .declared("Solver",
                    "0: sweeps in pair order; else the seed of a random sweep order drawn anew "
                    "every step (LMGC90's quick scramble): another solver path through the same "
                    "steps",
                    "", 0, 1e308)
          .after("substep-after"));
  rows.push_back(
      Row("max_substeps", "max_substeps", "", "max-substeps", engine)
          .of(&S::max_substeps)
          .pre_seam(std::int64_t{1})
          .defaulted_by_stiffness()
          .declared("Solver",
                    "adaptive sub-steps: a step not converged after --substep-after sweeps is "
                    "done again as two half steps under the same gravity, recursively, down to h "
                    "/ this (a power of two; 1: none); default 64, 1 with --stiffness 0, whose "
                    "conditioning halving h does not improve (docs/method.md, \"Sub-steps\")",
                    "", 1, cd::max_substeps_limit));
  rows.push_back(
      Row("substep_after", "substep_after", "", "substep-after", engine)
          .of(&S::substep_after)
          .pre_seam(std::int64_t{100})
          .declared("Solver",
                    "sweeps a step may take before it is split into two (with --max-substeps > 1)",
                    "", 1, 100000000));
  // Files made before it was a parameter started each step at the last one's level.
  rows.push_back(
      Row("substep_start", "substep_start", "", "substep-start", engine)
          .of_text(&S::substep_start, cd::substep_start_name, cd::substep_start_from_name)
          .pre_seam(std::string("last"))
          .declared("Solver",
                    "with --max-substeps > 1, the sub-steps a step starts with: 'last', the "
                    "level the last step ended at (one coarser once its sub-steps came easily); "
                    "'h', the whole step every time, so that the pile is at h wherever a step "
                    "converges there (docs/method.md, \"Sub-steps\")",
                    {"last", "h"}));
  // Files made before it was a parameter never finished a step so (0).
  rows.push_back(
      Row("finish_after", "finish_after", "", "finish-after", engine)
          .of(&S::finish_after)
          .pre_seam(std::int64_t{0})
          .declared("Solver",
                    "sweeps and iterations after which a step not yet converged is handed to "
                    "the active-set Newton on its problem (a sparse LU per set of contact "
                    "statuses; its solution kept only if it solves the contact law, else the "
                    "solver goes on); 0: never (docs/method.md, \"Finishing a step by its "
                    "active set\")",
                    "", 0, 100000000));
  rows.push_back(
      Row("sweep_order", "sweep_order", "", "sweep-order", engine)
          .of_text(&S::sweep_order, cd::sweep_order_name, cd::sweep_order_from_name)
          .pre_seam(std::string("pair"))
          .declared(
              "Solver",
              "the order of the sweeps: 'pair', the contacts in pair order (or --scramble's); "
              "'strips', the box cut into --strips vertical strips, the even strips then "
              "the odd ones, which --threads share "
              "(docs/method.md, \"Threads\")",
              {"pair", "strips"}));
  // Files made before it was a parameter took as many as fit (0).
  rows.push_back(
      Row("strips", "strips", "", "strips", engine)
          .of(&S::strips)
          .pre_seam(std::int64_t{0})
          .declared("Solver",
                    "with --sweep-order strips, the box's strips: this many, or as many as "
                    "fit two largest diameters wide if fewer do; 0: as many as fit. Fewer "
                    "strips take fewer sweeps; each thread takes whole strips of each parity, "
                    "so give about 8 per thread (docs/method.md, \"Threads\")",
                    "", 0, cd::max_strips));
  // The option is in D; the record in m.
  rows.push_back(
      Row("alert_distance", "alert_distance_m", "m", "alert", engine)
          .of(&S::alert_distance)
          .scaled(OptionScale::diameter, 0.1)
          .declared("Solver", "alert distance: contact candidates within this gap", "D", 0.0, 10.0)
          .after("threads"));
  // No option: the pile's gravity; the sweeps alternate in every run.
  rows.push_back(Row("gravity", keys::gravity_m_s2, "m s-2", "", engine).of(&S::gravity));
  rows.push_back(
      Row("symmetric_sweeps", "symmetric_sweeps", "", "", engine).of(&S::symmetric_sweeps));
  // Not recorded: how fast a run goes, not what it computes (docs/method.md, "Threads").
  rows.push_back(
      Row("threads", "", "", "threads", engine)
          .of(&S::threads)
          .declared("Solver",
                    "threads that share the strips of a sweep (with --sweep-order strips): the run "
                    "is the same, bit for bit, on any number; not recorded, so a run resumes or "
                    "branches on any (docs/method.md, \"Threads\")",
                    "", 1, cd::max_threads));
  rows.push_back(
      Row("checkpoint_every", "", "", "checkpoint-every", tilt)
          .of(&O::checkpoint_every)
          .declared("Recording", "steps between checkpoints of OUTPUT.partial", "steps", 1, 1e12)
          .accepts(at_least(1.0)));
  std::vector<RunParameter> table;
  for (Row& r : rows) table.push_back(std::move(r.p));
  return table;
}

}  // namespace

const std::vector<RunParameter>& run_parameters() {
  static const std::vector<RunParameter> table = make_table();
  return table;
}

const std::string& parameter_key(const std::string& field) {
  for (const RunParameter& p : run_parameters())
    if (p.field == field) return p.key;
  throw std::logic_error("no run parameter of the field " + field);
}

namespace {
// A recorded value as the messages and the help write it.
std::string value_text(const io::Value& v) {
  if (auto* d = std::get_if<double>(&v)) return io::format_number(*d);
  if (auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  return std::get<std::string>(v);
}
}  // namespace

std::string recorded_keys(ParameterGroup group) {
  std::string text;
  for (const RunParameter& p : run_parameters()) {
    if (p.group != group || p.key.empty()) continue;
    text += (text.empty() ? "" : ", ") + p.key;
    // a value recorded for a word: tilt_to_deg (-1 if none)
    if (p.shown_as)
      text += " (" + value_text(p.shown_as->first) + " if " + p.shown_as->second + ")";
  }
  return text;
}

io::Values settings_parameters(const cd::Settings& s) {
  TiltOptions o;
  o.settings = s;
  io::Values v;
  for (const RunParameter& p : run_parameters())
    if (p.group == ParameterGroup::settings && !p.key.empty()) v[p.key] = p.get(o);
  return v;
}

io::Values pre_seam_settings() {
  io::Values v;
  for (const RunParameter& p : run_parameters())
    if (p.pre_seam) v[p.key] = *p.pre_seam;
  return v;
}

io::Values with_pre_seam_settings(io::Values v) {
  for (const auto& [k, value] : pre_seam_settings()) v.insert({k, value});  // keeps what v has
  return v;
}

cd::Settings settings_from_parameters(const io::Values& given, const std::string& file) {
  const io::Values v = with_pre_seam_settings(given);
  TiltOptions o;
  auto recorded = [](const RunParameter& p) {
    return p.group == ParameterGroup::settings && !p.key.empty();
  };
  // The numbers, then the names: every text present before any is interpreted.
  for (const RunParameter& p : run_parameters())
    if (recorded(p) && !p.text) p.set(o, v, p.key, file);
  for (const RunParameter& p : run_parameters())
    if (recorded(p) && p.text) text_of(v, p.key, file);
  try {
    for (const RunParameter& p : run_parameters())
      if (recorded(p) && p.text) p.set(o, v, p.key, file);
    cd::validate(o.settings);
  } catch (const UsageError& e) {
    throw Error(file, "/parameters", e.what());
  }
  return o.settings;
}

std::vector<OptionDeclaration> declared_options() {
  std::vector<OptionDeclaration> out;
  for (const RunParameter& p : run_parameters())
    if (p.declaration) out.push_back(*p.declaration);
  return out;
}

namespace {
// The options' defaults for rigid or compliant contacts (the sub-steps and the cap differ).
cd::Settings defaults_for_contacts(bool rigid) {
  return rigid ? rigid_option_defaults() : option_defaults();
}

// The value of p's option in the field's unit, if given or defaulted.
std::optional<OptionValue> option_value(const RunParameter& p, const OptionValues& values,
                                        const PileScale& s) {
  const auto v = values.find(p.option);
  if (v == values.end()) return std::nullopt;
  switch (p.scale) {
    case OptionScale::diameter: return std::get<double>(v->second) * s.diameter;
    case OptionScale::weight_per_diameter:
      return std::get<double>(v->second) * s.mass * s.gravity / s.diameter;
    case OptionScale::none: break;
  }
  return v->second;
}
}  // namespace

void set_declared_options(TiltOptions& o, const OptionValues& values) {
  for (const RunParameter& p : run_parameters())
    if (p.declaration && p.group == ParameterGroup::tilt)
      p.set_option(o, option_value(p, values, {}));
}

cd::Settings settings_from_options(const OptionValues& values, const PileScale& scale) {
  TiltOptions o;
  for (const RunParameter& p : run_parameters())
    if (p.declaration && p.group == ParameterGroup::settings)
      p.set_option(o, option_value(p, values, scale));
  // Rigid contacts' steps are not split, and their cap is 50 times the compliant one's:
  // without a compliance halving h does not improve a step's conditioning, and a split
  // step's tolerance, relative to g h / 2^level, asks 2^level times more of its solve, so
  // the rescue made the rigid steps harder (docs/method.md, "Sub-steps").
  const cd::Settings by_stiffness = defaults_for_contacts(o.settings.contact_stiffness == 0.0);
  if (!values.count("max-substeps")) o.settings.max_substeps = by_stiffness.max_substeps;
  if (!values.count("max-sweeps")) o.settings.max_sweeps = by_stiffness.max_sweeps;
  const int n = o.settings.max_substeps;
  if ((n & (n - 1)) != 0)
    throw UsageError(field("max_substeps") + ": expected a power of two in [1, " +
                     std::to_string(cd::max_substeps_limit) + "], got '" + std::to_string(n) + "'");
  return o.settings;
}

cd::Settings option_defaults() {
  cd::Settings d;
  d.solver = cd::SolverKind::pcg;
  d.tolerance = 1e-6;
  d.max_substeps = 64;
  d.substep_after = 1000;
  return d;
}

cd::Settings rigid_option_defaults() {
  cd::Settings d = option_defaults();
  d.contact_stiffness = 0.0;
  d.max_substeps = 1;
  d.max_sweeps = 100000;
  return d;
}

namespace {
// Whether `v` is in `a`, and the message that names `name` and the range if not.
bool accepted(const Accepted& a, double v) {
  return (!a.finite || std::isfinite(v)) && (a.low_open ? v > a.low : v >= a.low) &&
         (!a.below || v < *a.below);
}
std::string refusal(const Accepted& a, const std::string& name) {
  if (a.below)
    return name + " must be in " + (a.low_open ? "(" : "[") + io::format_number(a.low) + ", " +
           io::format_number(*a.below) + ")";
  if (std::isfinite(a.low))
    return name + " must be " + (a.low_open ? "> " : ">= ") + io::format_number(a.low);
  return name + " must be finite";
}
double number(const io::Value& v) {
  if (auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return std::get<double>(v);
}
}  // namespace

void validate(const TiltOptions& o) {
  auto bad = [](const std::string& what) { throw UsageError(what); };
  for (const RunParameter& p : run_parameters())
    if (p.accepted && !accepted(*p.accepted, number(p.get(o))))
      bad(refusal(*p.accepted, field(p.field)));
  // The start is from_deg, or with a branch the tilt of the frame branched from.
  if (o.to_deg && !(*o.to_deg >= o.from_deg))
    bad(field("to_deg") + " " + io::format_number(*o.to_deg) + " is below the starting tilt " +
        io::format_number(o.from_deg) + " deg (" + field("from_deg") + ", or the frame of " +
        field("branch_at") + ")");
  if (!(o.max_deg >= o.from_deg)) bad("the maximum angle must be >= " + field("from_deg"));
  // Set by two options (steps or degrees), so named by neither.
  if (o.frame_every < 1) bad("the frame interval must be >= 1 step");
  cd::validate(o.settings);
}

std::int64_t hold_steps(const TiltOptions& o) {
  return std::max<std::int64_t>(1, steps_for(o.avalanche_hold_deg, o.rate_deg));
}

io::Values tilt_parameters(const TiltOptions& o) {
  io::Values v = settings_parameters(o.settings);
  for (const RunParameter& p : run_parameters())
    if (p.group == ParameterGroup::tilt && !p.key.empty()) v[p.key] = p.get(o);
  return v;
}

const std::vector<std::pair<std::string, std::string>>& tilt_option_parameters() {
  static const std::vector<std::pair<std::string, std::string>> table = [] {
    std::vector<std::pair<std::string, std::string>> t;
    for (const RunParameter& p : run_parameters()) {
      if (p.key.empty() || p.option.empty()) continue;
      t.emplace_back(p.option, p.key);
      if (!p.also_option.empty()) t.emplace_back(p.also_option, p.key);
    }
    return t;
  }();
  return table;
}

TiltOptions tilt_options_from_parameters(const io::Values& v, const std::string& file) {
  TiltOptions o;
  o.settings = settings_from_parameters(v, file);
  for (const RunParameter& p : run_parameters())
    if (p.group == ParameterGroup::tilt && !p.key.empty()) p.set(o, v, p.key, file);
  return o;
}

namespace {
std::string message_text(const RunParameter& p, const io::Value& v) {
  if (p.shown_as && v == p.shown_as->first) return p.shown_as->second;  // tilt_to_deg -1: "none"
  return value_text(v);
}
}  // namespace

InheritedOptions inherit_options(const io::Values& run, const TiltOptions& asked,
                                 const std::set<std::string>& given,
                                 std::optional<double> start_deg, const std::string& file) {
  const TiltOptions from_run = tilt_options_from_parameters(with_pre_seam_settings(run), file);
  const io::Values before = tilt_parameters(from_run), want = tilt_parameters(asked);
  io::Values merged = before;
  std::map<std::string, std::string> option_of;  // parameter -> the option that set it
  std::map<std::string, std::string> reason_of;  // parameter -> why it changed, if derived
  for (const RunParameter& p : run_parameters()) {
    if (p.inherit != Inherit::from_run) continue;
    for (const std::string& option : {p.option, p.also_option})
      if (!option.empty() && given.count(option)) {
        merged[p.key] = want.at(p.key);
        option_of[p.key] = option;
      }
  }
  // The sub-steps and the cap default by the contacts (settings_from_options): a branch
  // that makes the run's compliant contacts rigid, or its rigid ones compliant, takes the
  // new contacts' defaults for those of the two not given. (A resume, no start_deg, keeps
  // the run's options: another stiffness is refused there, by that option's name.)
  const bool was_rigid = from_run.settings.contact_stiffness == 0.0;
  const bool rigid = std::get<double>(merged.at(parameter_key("contact_stiffness"))) == 0.0;
  if (start_deg && rigid != was_rigid) {
    const cd::Settings d = defaults_for_contacts(rigid);
    const std::string why =
        rigid ? "the default with rigid contacts" : "the default with compliant contacts";
    for (const auto& [option, field, value] :
         {std::tuple{"max-substeps", "max_substeps", d.max_substeps},
          std::tuple{"max-sweeps", "max_sweeps", d.max_sweeps}})
      if (!given.count(option)) {
        merged[parameter_key(field)] = std::int64_t{value};
        reason_of[parameter_key(field)] = why;
      }
  }
  // The run's frame interval is an interval of tilt: at another rate it stays that many
  // degrees, not that many steps.
  const std::string &rate_key = parameter_key("rate_deg"),
                    &frames_key = parameter_key("frame_every"),
                    &from_key = parameter_key("from_deg");
  const double rate = std::get<double>(merged.at(rate_key));
  if (!option_of.count(frames_key) && rate != from_run.rate_deg) {
    merged[frames_key] = std::max<std::int64_t>(
        1, std::llround(static_cast<double>(from_run.frame_every) * from_run.rate_deg / rate));
    reason_of[frames_key] = "the same interval in degrees at this --rate";
  }
  if (start_deg) merged[from_key] = *start_deg;
  InheritedOptions out;
  out.options = tilt_options_from_parameters(merged, file);
  for (const RunParameter& p : run_parameters())  // not parameters: the command line's
    if (p.inherit == Inherit::as_asked)
      p.set(out.options, {{p.field, p.get(asked)}}, p.field, file);
  for (const RunParameter& p : run_parameters()) {
    if (p.key.empty() || p.option.empty() || (start_deg && p.key == from_key)) continue;
    if (merged.at(p.key) == before.at(p.key)) continue;
    const auto by = option_of.find(p.key);
    const auto why = reason_of.find(p.key);
    out.changes.push_back({by == option_of.end() ? "" : by->second, p.key,
                           message_text(p, before.at(p.key)), message_text(p, merged.at(p.key)),
                           why == reason_of.end() ? "" : why->second});
  }
  return out;
}

}  // namespace cdpile::sim
