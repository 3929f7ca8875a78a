#include "cdpile/reading/inputs.hpp"

#include "cdpile/analysis/run_summary.hpp"
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/contact_table.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/parameter_keys.hpp"

#include <cmath>
#include <limits>

namespace cdpile::reading {

// The files this layer reads are io's (schema, products, contact tables, checkpoints).
using namespace cdpile::io;

namespace {
std::optional<double> real_parameter(const Values& v, const char* key, const std::string& file) {
  if (v.find(key) == v.end()) return std::nullopt;
  return as_real(v, key, file);
}

// The index of the frame to map among `count` frames with ids `id(k)` and angles
// `theta(k)`, or empty. `last_loading` is the fallback.
template <class Id, class Theta>
std::optional<std::size_t> map_index(std::size_t count, const LocalNuReading& o, Id id, Theta theta,
                                     std::optional<std::size_t> last_loading,
                                     const std::string& file) {
  if (o.map_frame) {
    for (std::size_t k = 0; k < count; ++k)
      if (id(k) == *o.map_frame) return k;
    throw Error(
        file, "",
        "no frame " + std::to_string(*o.map_frame) + " to map (" + field("map_frame") + ")");
  }
  if (o.map_theta) {
    std::optional<std::size_t> best;
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < count; ++k)
      if (auto t = theta(k); t && std::abs(*t - *o.map_theta) < d) {
        d = std::abs(*t - *o.map_theta);
        best = k;
      }
    if (!best)
      throw Error(file, "", "no frame has a tilt angle to compare with " + field("map_theta"));
    return best;
  }
  if (last_loading) return last_loading;
  return count ? std::optional<std::size_t>(count - 1) : std::nullopt;
}

// A contact table has no parameters and no grains, so mu and D are required options: a
// missing one is a usage error, reported before the table is parsed.
void require_table_options(const LocalNuReading& o, const std::string& file) {
  const std::string missing = !o.mu.grain && !o.diameter
                                  ? field("mu") + " and " + field("diameter") + " are"
                              : !o.mu.grain ? field("mu") + " is"
                              : !o.diameter ? field("diameter") + " is"
                                            : "";
  if (!missing.empty()) throw UsageError(missing + " required for a contact table (" + file + ")");
}
}  // namespace

analysis::RecordedRule recorded_rule(const RunHeader& h, const std::string& file) {
  return {real_parameter(h.parameters, keys::critical_eps, file),
          real_parameter(h.parameters, keys::mu_grain, file),
          real_parameter(h.parameters, keys::mu_wall, file)};
}

analysis::Friction run_friction(const RunHeader& h, const analysis::FrictionChoice& given,
                                const std::string& file) {
  const analysis::RecordedRule recorded = recorded_rule(h, file);
  return analysis::choose_friction(given, &recorded, file);
}

namespace {
// The contacts of frame k that count, classified; a bad force names the frame.
analysis::ContactSet classify(const Frame& fr, std::size_t k, const analysis::Friction& mu,
                              const analysis::CriticalRule& rule, const std::string& file) {
  try {
    return analysis::select_contacts(fr.contacts, fr.grains.species, mu, rule);
  } catch (const Error& e) {
    throw Error(file, "/contacts", "frame " + std::to_string(k) + ": " + e.what());
  }
}
}  // namespace

analysis::ContactSet frame_contact_set(const RunReader& rr, std::size_t k,
                                       const analysis::Friction& mu,
                                       const analysis::CriticalRule& rule,
                                       const std::string& file) {
  // The whole frame is read, not only its contacts: reading checks its grain state too
  // (docs/schema.md promises finite values everywhere), for a few N x 2 doubles a frame.
  return classify(rr.frame(k), k, mu, rule, file);
}

analysis::RunRecord read_run_steps(const RunReader& rr, const std::string& file,
                                   const analysis::CriticalRule& rule) {
  const RunHeader& h = rr.header();
  const Grains& g = rr.grain_properties();
  analysis::RunRecord r;
  r.name = file;
  r.free_grains = analysis::free_grain_count(g);
  r.diameter = analysis::mean_diameter(g);
  r.mean_mass = analysis::mean_mass(g);
  r.gravity = real_parameter(h.parameters, keys::gravity_m_s2, file).value_or(0.0);
  r.recorded_avalanche = real_parameter(h.results, "avalanche_angle_deg", file);
  r.recorded_rule = recorded_rule(h, file);
  r.steps = steps_from_series(rr.series(), rule.include_walls, file);
  return r;
}

analysis::RunRecord read_run_record(const RunReader& rr, const std::string& file,
                                    const analysis::Friction& mu,
                                    const analysis::CriticalRule& rule,
                                    analysis::RattlerRule rattlers, double slip_speed,
                                    double rest_speed, bool per_contact) {
  analysis::RunRecord r = read_run_steps(rr, file, rule);
  r.mu = mu;
  for (std::size_t k = 0; k < rr.frame_count(); ++k) {
    const Frame fr = rr.frame(k);
    const analysis::ContactSet set = classify(fr, k, mu, rule, file);
    analysis::FrameRecord f;
    try {
      f = analysis::frame_record(fr.contacts, fr.grains, set, r, rule.eps, rattlers, slip_speed,
                                 rest_speed, per_contact);
    } catch (const Error& e) {
      throw Error(file, "/contacts", "frame " + std::to_string(k) + ": " + e.what());
    }
    f.frame = static_cast<std::int64_t>(k);
    f.step = fr.step;
    f.theta = fr.tilt_angle * 180.0 / M_PI;
    r.frames.push_back(std::move(f));
  }
  return r;
}

bool is_summary(const Input& in) {
  if (in.is_hdf5()) return read_header(in.hdf5()).kind == analysis::summary_kind;
  return tsv_product_kind(in.text()) == analysis::summary_kind;
}

ProductFile read_summary(const Input& in) {
  // a summary in TSV would hold its numbers as text and its integers as reals: summarise
  // writes HDF5 only, so a TSV one was made otherwise
  if (!in.is_hdf5())
    throw Error(in.name(), "", "a summary in TSV: summaries are HDF5 (summarise -o FILE.h5)");
  return read_product(in, analysis::summary_kind);
}

analysis::Friction summary_run_friction(const analysis::Product& s,
                                        const analysis::FrictionChoice& given) {
  const analysis::RecordedRule recorded{s.result("recorded_eps"), s.result("recorded_mu_grain"),
                                        s.result("recorded_mu_wall")};
  return analysis::choose_friction(given, &recorded, s.source);
}

analysis::RunRecord read_summary_record(const analysis::Product& s, const analysis::Friction& mu,
                                        const analysis::CriticalRule& rule,
                                        analysis::RattlerRule rattlers, double slip_speed,
                                        double rest_speed) {
  analysis::require_reading(s,
                            analysis::critical_reading(rule, mu, rattlers, slip_speed, rest_speed));
  return analysis::summary_run_record(s);
}

CriticalInput read_critical_input(const Input& in, const CriticalReading& o,
                                  std::optional<analysis::Product>& first_summary) {
  const analysis::CriticalOptions& opt = o.options;
  const bool steps = opt.source == analysis::SeriesSource::steps;
  CriticalInput out;
  if (is_summary(in)) {
    if (o.per_contact)
      throw UsageError(in.name() + ": a summary keeps no contacts: " + field("contacts") +
                       " needs the run files");
    ProductFile s = read_summary(in);
    if (!first_summary)
      first_summary = s.product;
    else
      analysis::require_same_engine(*first_summary, s.product, in.name());
    const analysis::Friction mu = summary_run_friction(s.product, o.mu);
    out.run =
        read_summary_record(s.product, mu, opt.rule, opt.rattlers, opt.slip_speed, opt.rest.speed);
    if (steps) analysis::require_step_rule(in.name(), out.run.recorded_rule, opt.rule, mu);
    out.history = std::move(s.provenance);
    out.summary = true;
    return out;
  }
  const RunReader rr(in.hdf5());
  out.note = partial_run_note(rr);
  out.history = rr.header().provenance;
  const analysis::Friction mu = run_friction(rr.header(), o.mu, in.name());
  // --series steps with another rule than the run's: refused before its frames are read
  if (steps)
    analysis::require_step_rule(in.name(), recorded_rule(rr.header(), in.name()), opt.rule, mu);
  out.run = read_run_record(rr, in.name(), mu, opt.rule, opt.rattlers, opt.slip_speed,
                            opt.rest.speed, o.per_contact);
  return out;
}

namespace {
// localnu's input `run` from its summary `s`: the frames, sums and pdf counts as they were
// made, and, for the input to map, the stored map of the angle asked for.
LocalNuInputInfo add_localnu_summary(analysis::LocalNuStudy& study, const analysis::Product& s,
                                     std::int64_t run, const LocalNuReading& o) {
  const analysis::Friction mu = summary_run_friction(s, o.mu);
  analysis::require_reading(s, analysis::localnu_reading(study.options(), o.rule, mu, o.avalanche,
                                                         o.theta_c, o.diameter));
  if (study.options().per_contact)
    throw UsageError(s.source + ": a summary keeps no contacts: " + field("per_contact") +
                     " needs the run file");
  LocalNuInputInfo info;
  info.length_unit = "m";
  info.summary.emplace();
  info.summary->kind = s.kind;
  info.summary->parameters = s.parameters;
  info.summary->source = s.source;
  study.add_summary(run, s);
  const analysis::Table& frames = s.table("localnu_frames");
  info.frames = frames.rows();
  for (std::size_t k = 0; k < info.frames; ++k)
    info.loading_frames += frames.column("loading").num[k] == 1.0;
  info.theta_c = s.result("loading_theta_c_deg");
  if (auto it = s.results.find("loading_theta_c_from");
      it != s.results.end() && std::holds_alternative<std::string>(it->second))
    info.theta_c_from = std::get<std::string>(it->second);
  if (run != o.map_run) return info;
  if (o.map_frame) {
    // the default map, then those of the angles asked for when it was made
    std::vector<std::optional<double>> held = {std::nullopt};
    for (std::size_t m = 1; auto t = s.result("map" + std::to_string(m) + "_asked_deg"); ++m)
      held.push_back(t);
    for (const std::optional<double>& t : held) {
      auto found = analysis::summary_map(s, t);
      if (!found || analysis::detail::number(found->second, "map_frame") !=
                        std::optional<double>(static_cast<double>(*o.map_frame)))
        continue;
      info.mapped_frame = *o.map_frame;
      study.set_map(run, std::move(found->first), std::move(found->second));
      return info;
    }
    throw Error(s.source, "",
                "the summary holds no map of frame " + std::to_string(*o.map_frame) + " (" +
                    field("map_frame") + "): map it from the run file");
  }
  auto found = analysis::summary_map(s, o.map_theta);
  if (!found) {
    const auto it = s.parameters.find("reading_map_theta");
    const std::string held =
        it != s.parameters.end() && std::holds_alternative<std::string>(it->second)
            ? std::get<std::string>(it->second)
            : std::string();
    throw Error(s.source, "",
                o.map_theta
                    ? "the summary holds maps at " +
                          (held.empty() ? std::string("no angle") : held + " deg") + ", not at " +
                          format_number(*o.map_theta) + " (" + field("map_theta") +
                          "): map it from the run file, or summarise the run with it"
                    : std::string("the summary holds no default map (its run has no frame)"));
  }
  if (auto f = analysis::detail::number(found->second, "map_frame"))
    info.mapped_frame = static_cast<std::int64_t>(*f);
  study.set_map(run, std::move(found->first), std::move(found->second));
  return info;
}
}  // namespace

LocalNuInputInfo add_localnu_input(analysis::LocalNuStudy& study, const Input& in, std::int64_t run,
                                   const LocalNuReading& o) {
  if (is_summary(in)) return add_localnu_summary(study, read_summary(in).product, run, o);
  LocalNuInputInfo info;
  const std::string& file = in.name();
  if (o.diameter && !(*o.diameter > 0.0 && std::isfinite(*o.diameter)))
    throw Error(file, "", "the mean diameter must be > 0");
  const bool map_here = run == o.map_run;
  auto is_loading = [&](std::optional<double> theta) {
    return !info.theta_c || !theta || *theta <= *info.theta_c;
  };

  if (!in.is_hdf5()) {
    // A plain contact table: no grains, so D and mu come from the command line. What is
    // plainly not one is named as such first: an empty file, or a cdpile TSV product
    // (its header has a '# kind: ...' line).
    if (in.text().find_first_not_of(" \t\r\n") == std::string::npos)
      throw Error(file, "", "empty: neither a run (HDF5) nor a contact table");
    if (const std::string kind = tsv_product_kind(in.text()); !kind.empty())
      throw Error(file, "",
                  "is a '" + kind + "' product, expected a run (HDF5) or a contact table");
    require_table_options(o, file);
    ContactTable t = read_contact_table(in.text(), file, {o.duplicates}, o.diameter);
    info.table = true;
    info.length_unit = t.length_unit;
    info.merged = t.merged;
    // Without a status column the solver's status is unknown (the table's `sliding` is NA).
    if (!t.has_status)
      for (auto& f : t.frames) f.contacts.status.clear();
    const analysis::Friction mu = analysis::choose_friction(o.mu, nullptr, file);
    if (o.theta_c) {
      info.theta_c = o.theta_c;
      info.theta_c_from = "option";
    } else
      info.theta_c_from = "none";
    std::optional<std::size_t> last_loading;
    for (std::size_t k = 0; k < t.frames.size(); ++k)
      if (is_loading(t.frames[k].theta)) last_loading = k;
    std::optional<std::size_t> to_map;
    if (map_here)
      to_map = map_index(
          t.frames.size(), o, [&](std::size_t k) { return t.frames[k].frame; },
          [&](std::size_t k) { return t.frames[k].theta; }, last_loading, file);
    for (std::size_t k = 0; k < t.frames.size(); ++k) {
      const ContactTableFrame& f = t.frames[k];
      analysis::ContactSet set;
      try {
        set = analysis::select_contacts(f.contacts, {}, mu, o.rule);
      } catch (const Error& e) {
        throw Error(file, "line " + std::to_string(f.first_line),
                    std::string("frame ") + std::to_string(f.frame) + ": " + e.what());
      }
      const bool loading = is_loading(f.theta);
      study.add_frame(run, file, f.frame, f.frame, f.theta, *o.diameter, set, loading, to_map == k);
      if (to_map == k) info.mapped_frame = f.frame;
      ++info.frames;
      info.loading_frames += loading;
    }
    return info;
  }

  const RunReader rr(in.hdf5());
  info.length_unit = "m";
  rr.check_observables();  // read only for theta_c, but a run without them is damaged
  const analysis::Friction mu = run_friction(rr.header(), o.mu, file);
  const double diameter = o.diameter.value_or(analysis::mean_diameter(rr.grain_properties()));
  if (o.theta_c) {
    info.theta_c = o.theta_c;
    info.theta_c_from = "option";
  } else {
    // The same avalanche angle as `critical`, so that both tools cut the loading phase
    // at the same theta.
    const analysis::RunRecord rec = read_run_steps(rr, file, o.rule);
    if (auto t = analysis::avalanche_angle(rec, o.avalanche)) {
      info.theta_c = t;
      info.theta_c_from = "rule";
    } else if (rec.recorded_avalanche) {
      info.theta_c = rec.recorded_avalanche;
      info.theta_c_from = "recorded";
    } else {
      info.theta_c_from = "none";
    }
  }
  const std::size_t n = rr.frame_count();
  auto theta_of = [&](std::size_t k) -> std::optional<double> {
    return rr.frame_tilt_angle(k) * 180.0 / M_PI;
  };
  std::optional<std::size_t> last_loading;
  for (std::size_t k = 0; k < n; ++k)
    if (is_loading(theta_of(k))) last_loading = k;
  std::optional<std::size_t> to_map;
  if (map_here)
    to_map = map_index(
        n, o, [](std::size_t k) { return static_cast<std::int64_t>(k); }, theta_of, last_loading,
        file);
  for (std::size_t k = 0; k < n; ++k) {
    const analysis::ContactSet set = frame_contact_set(rr, k, mu, o.rule, file);
    const bool loading = is_loading(theta_of(k));
    study.add_frame(run, file, static_cast<std::int64_t>(k), rr.frame_steps()[k], theta_of(k),
                    diameter, set, loading, to_map == k);
    if (to_map == k) info.mapped_frame = static_cast<std::int64_t>(k);
    ++info.frames;
    info.loading_frames += loading;
  }
  return info;
}

analysis::Product summarise_run(const Input& in, const SummaryReading& opt) {
  const std::string& file = in.name();
  if (is_summary(in)) throw Error(file, "", "is a summary already, expected a run");
  const RunReader rr(in.hdf5());
  const analysis::Friction mu = run_friction(rr.header(), opt.mu, file);
  const analysis::RunRecord run =
      read_run_record(rr, file, mu, opt.rule, opt.rattlers, opt.slip_speed, opt.rest_speed);
  LocalNuReading reading;
  reading.mu = opt.mu;
  reading.rule = opt.rule;
  reading.avalanche = opt.avalanche;
  // localnu's product of this run alone, as input 0 (its default map: the last loading frame)
  auto localnu = [&](std::optional<double> map_theta, LocalNuInputInfo* info) {
    analysis::LocalNuStudy study(opt.localnu);
    reading.map_theta = map_theta;
    *info = add_localnu_input(study, in, 0, reading);
    return study.product();
  };
  LocalNuInputInfo info;
  const analysis::Product part = localnu(std::nullopt, &info);
  // A map needs its frame only: the one localnu maps for --map-theta t, alone in a study
  // (the map and its map_* results are those of the whole run's pass).
  const std::size_t n = rr.frame_count();
  auto theta_of = [&](std::size_t k) -> std::optional<double> {
    return rr.frame_tilt_angle(k) * 180.0 / M_PI;
  };
  const double diameter = analysis::mean_diameter(rr.grain_properties());
  std::vector<analysis::Product> maps;
  for (double t : opt.map_thetas) {
    reading.map_theta = t;
    const std::optional<std::size_t> k = map_index(
        n, reading, [](std::size_t f) { return static_cast<std::int64_t>(f); }, theta_of,
        std::nullopt, file);
    analysis::LocalNuStudy study(opt.localnu);
    if (k)
      study.add_frame(0, file, static_cast<std::int64_t>(*k), rr.frame_steps()[*k], theta_of(*k),
                      diameter, frame_contact_set(rr, *k, mu, opt.rule, file), true, true);
    maps.push_back(study.product());
  }
  analysis::Product s = analysis::make_summary(
      run, analysis::critical_reading(opt.rule, mu, opt.rattlers, opt.slip_speed, opt.rest_speed),
      part,
      analysis::localnu_reading(opt.localnu, opt.rule, mu, opt.avalanche, std::nullopt,
                                std::nullopt),
      opt.map_thetas, maps, rr.header().parameters);
  if (info.theta_c) s.results["loading_theta_c_deg"] = *info.theta_c;
  s.results["loading_theta_c_from"] = info.theta_c_from;
  s.source = file;
  return s;
}

}  // namespace cdpile::reading
