#include "cdpile/io/analysis_input.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/contact_table.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/parameter_keys.hpp"

#include <cmath>
#include <limits>

namespace cdpile::io {

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

LocalNuInputInfo add_localnu_input(analysis::LocalNuStudy& study, const Input& in, std::int64_t run,
                                   const LocalNuReading& o) {
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
    ContactTable t = read_contact_table(in.text(), file, {o.duplicates});
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

}  // namespace cdpile::io
