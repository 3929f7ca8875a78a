// The tilt protocol's loop, a fresh run and a resumed one (tilt.hpp; docs/method.md,
// "Tilt" and "Checkpoints").
#include "cdpile/sim/tilt.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/sim/common.hpp"
#include "cdpile/sim/overlap.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace cdpile::sim {
namespace h5 = io::h5;

namespace {

// The checkpoint's impulses are a step's solution, written by a run with these settings:
// each pair names a grain and a grain or a wall, R_n >= 0, |R_t| <= mu R_n (to the
// rounding of a sub-step's rescaling), and no impulse changes a grain's velocity by more
// than the speed any grain may have. A damaged partial fails here, in one line, rather
// than in the engine.
void check_checkpoint_impulses(const Restored& rs, const cd::Settings& s, double vmax,
                               const std::string& file) {
  auto number_text = [](double x) { return io::format_number(x, 6); };
  const auto n = static_cast<std::int64_t>(rs.grains.size());
  const std::string path = std::string(io::kCheckpointGroup) + "/impulse_rt";
  for (std::size_t k = 0; k < rs.engine.impulses.size(); ++k) {
    const cd::StoredImpulse& p = rs.engine.impulses[k];
    const std::string pair = "impulse " + std::to_string(k) + " of pair (" + std::to_string(p.i) +
                             ", " + std::to_string(p.j) + ")";
    if (p.i < 0 || p.i >= n || p.j < wall_right || p.j >= n || p.j == p.i)
      throw Error(file, std::string(io::kCheckpointGroup) + "/impulse_i",
                  pair + ": not a grain and a grain or a wall of the " + std::to_string(n) +
                      " grains");
    const double mu = p.j < 0 ? s.mu_wall : s.mu_grain;
    const double m = rs.grains.mass[static_cast<std::size_t>(p.i)];
    if (!(p.rn >= 0.0) || !(std::fabs(p.rt) <= mu * p.rn * (1.0 + 1e-9)))
      throw Error(file, path,
                  pair + ": (R_n, R_t) = (" + number_text(p.rn) + ", " + number_text(p.rt) +
                      ") N s/m is outside the Coulomb cone of mu = " + number_text(mu));
    if (!(p.rn <= m * vmax))
      throw Error(file, std::string(io::kCheckpointGroup) + "/impulse_rn",
                  pair + ": R_n = " + number_text(p.rn) + " N s/m would move grain " +
                      std::to_string(p.i) + " faster than 1000 sqrt(g L) = " +
                      number_text(vmax) + " m/s");
  }
}


constexpr double kDeg = M_PI / 180.0;

double angle_deg(const TiltOptions& o, std::int64_t step) {
  return o.from_deg + static_cast<double>(step) * o.rate_deg;
}

TiltOutcome drive(cd::Engine& engine, Recorder& rec, const TiltOptions& o, LoopState st,
                  Pending& pending, const OverlapGrowth& growth, const TiltHooks& hooks) {
  const Agitation agitation(engine.grains(), o.settings.gravity);
  const std::vector<Species> species = engine.grains().species;
  const std::int64_t margin = steps_for(o.margin_deg, o.rate_deg);
  const std::int64_t cap = o.to_deg ? steps_for(*o.to_deg - o.from_deg, o.rate_deg)
                                    : steps_for(o.max_deg - o.from_deg, o.rate_deg);
  auto last_step = [&] {
    if (!o.to_deg && st.detector.detected)
      return std::min(cap, st.detector.confirmed_step + margin);
    return cap;
  };
  TiltOutcome out;
  // The run's CPU: the earlier processes' (from the checkpoint) and this one's, kept in
  // every checkpoint and recorded in the run's provenance at its end.
  const double cpu_before = st.cpu_s;
  auto note_cpu = [&] { st.cpu_s = cpu_before + io::process_cpu_s(); };
  std::int64_t step = engine.state().step;
  out.first_step = step;
  auto stop = [&] { return hooks.stop && hooks.stop(); };
  auto deferring = [&](bool on) {
    if (hooks.deferring) hooks.deferring(on);
  };
  // The end of an interrupted run: what is done up to the last completed step is saved,
  // a checkpoint in OUTPUT.partial or the run so far on standard output.
  auto interrupted = [&] {
    if (!rec.checkpoints()) deferring(false);  // a blocked standard output must not hold the tool
    note_cpu();
    rec.interrupt(pending, engine, st);
    out.steps = step;
    out.final_angle_deg = angle_deg(o, step);
    out.avalanche = st.detector.detected;
    out.avalanche_deg = st.detector.angle_deg;
    out.interrupted = true;
    out.stop_reason = "interrupted";
    out.unconverged_steps = st.unconverged;
    return out;
  };
  engine.set_cancel(stop);
  deferring(true);
  while (step < last_step()) {
    const double deg = angle_deg(o, step + 1);
    cd::StepReport r;
    try {
      r = engine.step(deg * kDeg);
    } catch (const cd::StepCancelled&) {  // the engine is still at the last completed step
      return interrupted();
    }
    step = r.step;
    Contacts c = engine.contacts();
    append_observables(pending.rows, r,
                       count_critical(c, species, o.settings.mu_grain, o.settings.mu_wall, o.eps));
    if (!r.converged) ++st.unconverged;
    st.max_overlap = std::max(st.max_overlap, r.max_overlap);
    st.max_overlap_grown = std::max(st.max_overlap_grown, growth.grown(c));
    const double a = agitation(r.kinetic_energy);
    st.detector.update(step, deg, a);
    const std::int64_t last = last_step();
    if (step % o.frame_every == 0 || step == last) {
      Frame fr;
      fr.step = r.step;
      fr.time = r.time;
      fr.tilt_angle = deg * kDeg;
      fr.grains = engine.grains();
      fr.contacts = std::move(c);
      pending.frames.push_back(std::move(fr));
    }
    if (hooks.progress) {
      TiltProgress p;
      p.step = step;
      p.angle_deg = deg;
      p.agitation = a;
      p.avalanche = st.detector.detected;
      p.avalanche_deg = st.detector.angle_deg;
      p.last_step = (o.to_deg || st.detector.detected) ? last : -1;
      p.cap_step = cap;
      hooks.progress(p);
    }
    if (step >= last) break;
    if (stop()) return interrupted();
    if (step % o.checkpoint_every == 0) {
      note_cpu();
      rec.commit(pending, engine, st);
    }
  }
  // The last step made durable: from here on a kill loses nothing but the final copy
  // (resumed, the run only writes its output), so a signal may end the tool at once.
  if (rec.checkpoints()) {
    note_cpu();
    rec.commit(pending, engine, st);
    deferring(false);
    if (stop()) return interrupted();
  }
  out.steps = step;
  out.final_angle_deg = angle_deg(o, step);
  out.avalanche = st.detector.detected;
  out.avalanche_deg = st.detector.angle_deg;
  out.unconverged_steps = st.unconverged;
  out.stop_reason = o.to_deg ? "to"
                    : (st.detector.detected && step == st.detector.confirmed_step + margin)
                        ? "avalanche"
                        : "max_angle";
  io::Values results{
      {"steps", step},
      {"final_angle_deg", out.final_angle_deg},
      {"avalanche_detected", std::int64_t{st.detector.detected ? 1 : 0}},
      {"unconverged_steps", st.unconverged},
      {"max_overlap_m", st.max_overlap},
      {"max_overlap_grown_m", st.max_overlap_grown},
      {"stop_reason", out.stop_reason},
  };
  // Flagged in the file as well as on stderr: a number of warnings and their text.
  out.warnings = settings_warnings(o.settings, agitation.diameter());
  for (auto& w : run_warnings(step, st.unconverged, st.max_overlap_grown, agitation.diameter(),
                              o.settings.contact_stiffness, o.settings.max_substeps))
    out.warnings.push_back(std::move(w));
  results["warnings"] = static_cast<std::int64_t>(out.warnings.size());
  if (!out.warnings.empty()) {
    std::string text;
    for (const auto& w : out.warnings) text += (text.empty() ? "" : "; ") + w;
    results["warning_messages"] = text;
  }
  if (st.detector.detected) {
    results["avalanche_angle_deg"] = st.detector.angle_deg;
    results["avalanche_step"] = st.detector.start_step;
    results["avalanche_confirmed_step"] = st.detector.confirmed_step;
  }
  deferring(false);
  note_cpu();
  rec.finish(pending, engine, st, results);
  return out;
}

LoopState fresh_state(const TiltOptions& o) {
  LoopState s;
  s.detector.threshold = o.avalanche_energy;
  s.detector.hold = hold_steps(o);
  return s;
}

bool same_value(const io::Value& a, const io::Value& b) { return a == b; }

std::string value_text(const io::Value& v) {
  if (auto* d = std::get_if<double>(&v)) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", *d);
    return buf;
  }
  if (auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  return std::get<std::string>(v);
}

}  // namespace

void check_output(const std::string& output, bool force) {
  io::Output check(output, force, true);  // an existing output, a missing folder, a terminal
  if (output != "-" && !force && has_partial(output))
    throw Error(partial_path(output), "",
                "an interrupted run exists; use " + field("resume") + " to continue it or " +
                    field("force") + " to start over");
}

TiltOutcome run_tilt(const PileInput& pile, const TiltOptions& o, const std::string& output,
                     bool force, const io::Provenance& prov, const TiltHooks& hooks) {
  validate(o);
  const bool to_stdout = output == "-";
  check_output(output, force);
  if (!to_stdout) {
    std::error_code ec;
    std::filesystem::remove(partial_path(output), ec);  // --force: start over
  }
  io::RunHeader h;
  h.kind = "run";
  h.box = pile.box;
  h.parameters = pile.parameters;  // the pile's own, then the tilt's over them
  for (const auto& [k, v] : tilt_parameters(o)) h.parameters[k] = v;
  if (pile.branch) {  // where in the input run this one branched off
    h.parameters["branch_step"] = pile.branch->step;
    h.parameters["branch_tilt_deg"] = pile.branch->tilt_deg;
  }
  h.provenance = pile.provenance;
  h.provenance.push_back(prov);

  cd::Engine engine(pile.box, pile.grains, o.settings);
  // Warm start from the pile's last contact forces: the first tilt step starts from the
  // equilibrium the pile was left in.
  engine.set_state(warm_start_state(pile.contacts, o.settings.time_step));

  Pending pending;
  Frame f0;
  f0.step = 0;
  f0.time = 0.0;
  f0.tilt_angle = o.from_deg * kDeg;
  f0.grains = pile.grains;
  f0.contacts = pile.contacts;
  pending.frames.push_back(std::move(f0));
  LoopState st = fresh_state(o);
  const OverlapGrowth growth(pile.contacts);
  if (to_stdout) {
    StreamRecorder rec(h, pile.grains);
    return drive(engine, rec, o, st, pending, growth, hooks);
  }
  FileRecorder rec(output, force);
  rec.start(h, pile.grains, pending, engine, st);
  try {
    return drive(engine, rec, o, st, pending, growth, hooks);
  } catch (...) {
    // A run that fails in its first step (a pile the engine cannot handle) never
    // started: its partial holds only the pile, and is removed. A run that did steps
    // keeps its partial for --resume, as after a kill.
    if (engine.state().step == 0) {
      std::error_code ec;
      std::filesystem::remove(partial_path(output), ec);
    }
    throw;
  }
}

TiltOutcome resume_tilt(const TiltOptions& o, const std::string& output, bool force,
                        const TiltHooks& hooks) {
  validate(o);
  if (output == "-")
    throw UsageError(field("resume") + " needs an output file (" + field("output") +
                     " FILE), not standard output");
  const std::string partial = partial_path(output);
  if (!has_partial(output)) throw Error(partial, "", "no partial run to resume");
  remove_stale_temporaries(output);
  Restored rs;
  Box box;
  Contacts start;  // the run's first frame: the pile's overlaps, which are not the run's
  {
    h5::File f = h5::open_read(partial, partial);
    io::RunReader r(f);
    if (r.header().kind != "run") throw Error(partial, "/", "is not a partial tilt run");
    const io::Values stored = with_pre_seam_settings(r.header().parameters);
    for (const auto& [k, v] : tilt_parameters(o)) {
      auto it = stored.find(k);
      if (it == stored.end()) throw Error(partial, "/parameters", "missing parameter '" + k + "'");
      if (!same_value(it->second, v))
        throw Error(partial, "/parameters",
                    k + " is " + value_text(v) + " here but " + value_text(it->second) +
                        " in the interrupted run; resume with the same options");
    }
    rs = read_checkpoint(f, r.grain_properties());
    r.check_grain_state(rs.grains, std::string(io::kCheckpointGroup) + "/position",
                        std::string(io::kCheckpointGroup) + "/velocity", "checkpoint");
    check_checkpoint_impulses(rs, o.settings, r.speed_bound(), partial);
    box = r.header().box;
    if (r.frame_count() > 0) start = r.contacts(0);
  }
  cd::Engine engine(box, rs.grains, o.settings);
  engine.set_state(rs.engine);
  LoopState st = rs.loop;
  st.detector.threshold = o.avalanche_energy;
  st.detector.hold = hold_steps(o);
  Pending pending;
  FileRecorder rec(output, force);
  rec.mark_committed(rs.engine.step);
  return drive(engine, rec, o, st, pending, OverlapGrowth(start), hooks);
}

}  // namespace cdpile::sim
