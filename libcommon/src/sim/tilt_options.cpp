// The tilt protocol's options, as run parameters and back, and a branch's or a resume's
// (tilt_options.hpp; docs/method.md, "Tilt").
#include "cdpile/sim/tilt_options.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/sim/avalanche.hpp"
#include "cdpile/sim/common.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace cdpile::sim {

void validate(const TiltOptions& o) {
  auto bad = [](const std::string& what) { throw UsageError(what); };
  if (!(o.rate_deg > 0.0) || !std::isfinite(o.rate_deg)) bad(field("rate_deg") + " must be > 0");
  if (!std::isfinite(o.from_deg)) bad(field("from_deg") + " must be finite");
  // The start is from_deg, or with a branch the tilt of the frame branched from.
  if (o.to_deg && !(*o.to_deg >= o.from_deg))
    bad(field("to_deg") + " " + io::format_number(*o.to_deg) + " is below the starting tilt " +
        io::format_number(o.from_deg) + " deg (" + field("from_deg") + ", or the frame of " +
        field("branch_at") + ")");
  if (!(o.max_deg >= o.from_deg)) bad("the maximum angle must be >= " + field("from_deg"));
  if (!(o.margin_deg >= 0.0)) bad(field("margin_deg") + " must be >= 0");
  if (!(o.avalanche_energy > 0.0)) bad(field("avalanche_energy") + " must be > 0");
  if (!(o.avalanche_hold_deg >= 0.0)) bad(field("avalanche_hold_deg") + " must be >= 0");
  if (o.frame_every < 1) bad("the frame interval must be >= 1 step");
  if (o.checkpoint_every < 1) bad(field("checkpoint_every") + " must be >= 1");
  if (!(o.eps >= 0.0 && o.eps < 1.0)) bad(field("eps") + " must be in [0, 1)");
  cd::validate(o.settings);
}

std::int64_t hold_steps(const TiltOptions& o) {
  return std::max<std::int64_t>(1, steps_for(o.avalanche_hold_deg, o.rate_deg));
}

io::Values tilt_parameters(const TiltOptions& o) {
  io::Values v = settings_parameters(o.settings);
  v.insert({{"tilt_rate_deg_per_step", o.rate_deg},
            {"tilt_from_deg", o.from_deg},
            {"tilt_to_deg", o.to_deg ? *o.to_deg : -1.0},
            {"tilt_max_deg", o.max_deg},
            {"avalanche_margin_deg", o.margin_deg},
            {"avalanche_energy", o.avalanche_energy},
            {"avalanche_hold_deg", o.avalanche_hold_deg},
            {"frame_every_steps", o.frame_every},
            {"critical_eps", o.eps}});
  return v;
}

const std::vector<std::pair<std::string, std::string>>& tilt_option_parameters() {
  static const std::vector<std::pair<std::string, std::string>> table = {
      {"rate", "tilt_rate_deg_per_step"},
      {"from", "tilt_from_deg"},
      {"to", "tilt_to_deg"},
      {"max-angle", "tilt_max_deg"},
      {"margin", "avalanche_margin_deg"},
      {"avalanche-ek", "avalanche_energy"},
      {"avalanche-hold", "avalanche_hold_deg"},
      {"eps", "critical_eps"},
      {"frame-every", "frame_every_steps"},
      {"frame-every-deg", "frame_every_steps"},
      {"mu", "mu_grain"},
      {"mu-wall", "mu_wall"},
      {"time-step", "time_step_s"},
      {"theta-method", "theta"},
      {"tolerance", "tolerance"},
      {"max-sweeps", "max_sweeps"},
      {"criterion", "criterion"},
      {"check-every", "check_every"},
      {"solver", "solver"},
      {"stiffness", "contact_stiffness_N_m2"},
      {"scramble", "scramble_seed"},
      {"max-substeps", "max_substeps"},
      {"substep-after", "substep_after"},
      {"sweep-order", "sweep_order"},
      {"alert", "alert_distance_m"}};
  return table;
}

TiltOptions tilt_options_from_parameters(const io::Values& v, const std::string& file) {
  TiltOptions o;
  o.settings = settings_from_parameters(v, file);
  o.rate_deg = io::as_real(v, "tilt_rate_deg_per_step", file);
  o.from_deg = io::as_real(v, "tilt_from_deg", file);
  const double to = io::as_real(v, "tilt_to_deg", file);
  if (to != -1.0) o.to_deg = to;  // -1: none (tilt_parameters)
  o.max_deg = io::as_real(v, "tilt_max_deg", file);
  o.margin_deg = io::as_real(v, "avalanche_margin_deg", file);
  o.avalanche_energy = io::as_real(v, "avalanche_energy", file);
  o.avalanche_hold_deg = io::as_real(v, "avalanche_hold_deg", file);
  o.frame_every = io::as_int(v, "frame_every_steps", file);
  o.eps = io::as_real(v, "critical_eps", file);
  return o;
}

namespace {
std::string message_text(const std::string& key, const io::Value& v) {
  if (key == "tilt_to_deg" && v == io::Value(-1.0)) return "none";  // tilt_parameters' "no --to"
  if (auto* d = std::get_if<double>(&v)) return io::format_number(*d);
  if (auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  return std::get<std::string>(v);
}
}  // namespace

InheritedOptions inherit_options(const io::Values& run, const TiltOptions& asked,
                                 const std::set<std::string>& given,
                                 std::optional<double> start_deg, const std::string& file) {
  const TiltOptions from_run = tilt_options_from_parameters(with_pre_seam_settings(run), file);
  const io::Values before = tilt_parameters(from_run), want = tilt_parameters(asked);
  io::Values merged = before;
  std::map<std::string, std::string> option_of;  // parameter -> the option that set it
  for (const auto& [option, key] : tilt_option_parameters())
    if (given.count(option)) {
      merged[key] = want.at(key);
      option_of[key] = option;
    }
  // The run's frame interval is an interval of tilt: at another rate it stays that many
  // degrees, not that many steps.
  const double rate = std::get<double>(merged.at("tilt_rate_deg_per_step"));
  if (!option_of.count("frame_every_steps") && rate != from_run.rate_deg)
    merged["frame_every_steps"] = std::max<std::int64_t>(
        1, std::llround(static_cast<double>(from_run.frame_every) * from_run.rate_deg / rate));
  if (start_deg) merged["tilt_from_deg"] = *start_deg;
  InheritedOptions out;
  out.options = tilt_options_from_parameters(merged, file);
  out.options.checkpoint_every = asked.checkpoint_every;
  out.options.settings.threads = asked.settings.threads;  // how fast, not what: not a parameter
  for (const auto& [option, key] : tilt_option_parameters()) {
    if (option == "frame-every-deg" || (start_deg && key == "tilt_from_deg"))
      continue;  // one entry per parameter
    if (merged.at(key) == before.at(key)) continue;
    const auto by = option_of.find(key);
    out.changes.push_back({by == option_of.end() ? "" : by->second, key,
                           message_text(key, before.at(key)), message_text(key, merged.at(key))});
  }
  return out;
}

}  // namespace cdpile::sim
