// The tilt protocol, its run recording and its checkpoints (tilt.hpp; docs/method.md).
#include "cdpile/sim/tilt.hpp"

#include "cdpile/error.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/sim/common.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace cdpile::sim {
namespace h5 = io::h5;

namespace {

constexpr const char* kCheckpoint = "/checkpoint";
constexpr double kDeg = M_PI / 180.0;

/// Steps to turn by `deg` at `rate` degrees per step, rounded up (a tiny tolerance keeps
/// 2 / 0.001 at 2000 despite rounding).
std::int64_t steps_for(double deg, double rate) {
  return static_cast<std::int64_t>(std::ceil(deg / rate - 1e-9));
}

/// The avalanche rule (docs/method.md, "Avalanche"): the first step from which the
/// agitation a = Ek per grain / (m g D) stays >= threshold for `hold` steps in a row.
struct Detector {
  double threshold = 0.0;
  std::int64_t hold = 1;
  std::int64_t since = -1;     ///< first step of the current run above the threshold
  double since_deg = 0.0;
  bool detected = false;
  double angle_deg = 0.0;      ///< tilt at `since` when confirmed
  std::int64_t start_step = -1, confirmed_step = -1;

  void update(std::int64_t step, double angle, double a) {
    if (detected) return;
    if (!(a >= threshold)) {
      since = -1;
      return;
    }
    if (since < 0) {
      since = step;
      since_deg = angle;
    }
    if (step - since + 1 >= hold) {
      detected = true;
      angle_deg = since_deg;
      start_step = since;
      confirmed_step = step;
    }
  }
};

/// Everything besides the recorded data that the loop needs to continue.
struct LoopState {
  Detector detector;
  std::int64_t unconverged = 0;
  double max_overlap = 0.0;
};

// ---------------------------------------------------------------------------------------
// Checkpoint group

void write_checkpoint(const h5::File& f, const cd::Engine& e, const LoopState& s) {
  if (h5::exists(f, kCheckpoint) && H5Ldelete(f.id(), kCheckpoint, H5P_DEFAULT) < 0)
    throw Error(f.name(), kCheckpoint, "cannot replace the checkpoint");
  h5::create_group(f, kCheckpoint);
  const std::string c = kCheckpoint;
  const Grains& g = e.grains();
  const auto n = static_cast<hsize_t>(g.size());
  h5::write(f, c + "/position", g.position.empty() ? nullptr : g.position[0].data(), {n, 2});
  h5::write(f, c + "/velocity", g.velocity.empty() ? nullptr : g.velocity[0].data(), {n, 2});
  h5::write(f, c + "/orientation", g.orientation);
  h5::write(f, c + "/angular_velocity", g.angular_velocity);
  const cd::EngineState st = e.state();
  std::vector<std::int32_t> ii, jj;
  std::vector<double> rn, rt;
  for (const auto& imp : st.impulses) {
    ii.push_back(imp.i);
    jj.push_back(imp.j);
    rn.push_back(imp.rn);
    rt.push_back(imp.rt);
  }
  h5::write(f, c + "/impulse_i", ii);
  h5::write(f, c + "/impulse_j", jj);
  h5::write(f, c + "/impulse_rn", rn);
  h5::write(f, c + "/impulse_rt", rt);
  h5::set_attr(f, c, "step", st.step);
  h5::set_attr(f, c, "time", st.time);
  const Detector& d = s.detector;
  h5::set_attr(f, c, "detector_since", d.since);
  h5::set_attr(f, c, "detector_since_deg", d.since_deg);
  h5::set_attr(f, c, "detector_detected", std::int64_t{d.detected ? 1 : 0});
  h5::set_attr(f, c, "detector_angle_deg", d.angle_deg);
  h5::set_attr(f, c, "detector_start_step", d.start_step);
  h5::set_attr(f, c, "detector_confirmed_step", d.confirmed_step);
  h5::set_attr(f, c, "unconverged_steps", s.unconverged);
  h5::set_attr(f, c, "max_overlap", s.max_overlap);
  h5::set_attr(f, c, "description", std::string(
      "state to resume this partial run bit for bit: grain state, warm-start impulses [N s/m] "
      "of the last step by pair (i, j), clock and avalanche detector; see docs/method.md"));
}

struct Restored {
  Grains grains;
  cd::EngineState engine;
  LoopState loop;
};

Restored read_checkpoint(const h5::File& f, const Grains& properties) {
  if (!h5::exists(f, kCheckpoint)) throw Error(f.name(), kCheckpoint, "missing: not a partial run");
  const std::string c = kCheckpoint;
  const auto n = static_cast<hsize_t>(properties.size());
  Restored r;
  r.grains = properties;
  auto pos = h5::read<double>(f, c + "/position", {n, 2});
  auto vel = h5::read<double>(f, c + "/velocity", {n, 2});
  r.grains.orientation = h5::read<double>(f, c + "/orientation", {n});
  r.grains.angular_velocity = h5::read<double>(f, c + "/angular_velocity", {n});
  if (pos.size() != 2 * n || vel.size() != 2 * n || r.grains.orientation.size() != n ||
      r.grains.angular_velocity.size() != n)
    throw Error(f.name(), kCheckpoint, "grain state does not match the " + std::to_string(n) + " grains");
  for (std::size_t k = 0; k < n; ++k) {
    r.grains.position[k] = Vec2(pos[2 * k], pos[2 * k + 1]);
    r.grains.velocity[k] = Vec2(vel[2 * k], vel[2 * k + 1]);
  }
  auto ii = h5::read<std::int32_t>(f, c + "/impulse_i", {0});
  auto jj = h5::read<std::int32_t>(f, c + "/impulse_j", {ii.size()});
  auto rn = h5::read<double>(f, c + "/impulse_rn", {ii.size()});
  auto rt = h5::read<double>(f, c + "/impulse_rt", {ii.size()});
  for (std::size_t k = 0; k < ii.size(); ++k) r.engine.impulses.push_back({ii[k], jj[k], rn[k], rt[k]});
  r.engine.step = h5::attr_int(f, c, "step");
  r.engine.time = h5::attr_double(f, c, "time");
  Detector& d = r.loop.detector;
  d.since = h5::attr_int(f, c, "detector_since");
  d.since_deg = h5::attr_double(f, c, "detector_since_deg");
  d.detected = h5::attr_int(f, c, "detector_detected") != 0;
  d.angle_deg = h5::attr_double(f, c, "detector_angle_deg");
  d.start_step = h5::attr_int(f, c, "detector_start_step");
  d.confirmed_step = h5::attr_int(f, c, "detector_confirmed_step");
  r.loop.unconverged = h5::attr_int(f, c, "unconverged_steps");
  r.loop.max_overlap = h5::attr_double(f, c, "max_overlap");
  return r;
}

// ---------------------------------------------------------------------------------------
// Where the recorded data goes

/// Data done since the last commit.
struct Pending {
  io::Series rows = observables_series();
  std::vector<Frame> frames;
  void clear() {
    rows.clear();
    frames.clear();
  }
};

class Recorder {
 public:
  virtual ~Recorder() = default;
  /// A checkpoint: everything pending becomes durable, with the state to resume.
  virtual void commit(Pending& p, const cd::Engine& e, const LoopState& s) = 0;
  /// The run is complete: write the final output with these results.
  virtual void finish(Pending& p, const cd::Engine& e, const LoopState& s, const io::Values& results) = 0;
  /// Ctrl-C: leave a valid file up to the last completed step.
  virtual void interrupt(Pending& p, const cd::Engine& e, const LoopState& s) = 0;
  /// Whether commit() makes the run durable (a checkpoint file) rather than only
  /// gathering it in memory for a final write.
  virtual bool checkpoints() const = 0;
};

/// A partial written by an earlier version may lack an observable added since (residual_rms):
/// a series cannot gain a column, so the resumed run goes on without it rather than
/// refusing to resume. Columns the partial has are all kept.
void keep_recorded_columns(const h5::File& f, io::Series& s) {
  const std::string obs = "/observables";
  if (!h5::exists(f, obs) || h5::members(f, obs).empty()) return;
  std::erase_if(s.real, [&](const auto& c) { return !h5::exists(f, obs + "/" + c.first); });
  std::erase_if(s.integer, [&](const auto& c) { return !h5::exists(f, obs + "/" + c.first); });
}

void append_pending(io::RunWriter& w, const Pending& p) {
  w.append_frames(p.frames);
  if (p.rows.size() > 0) w.append_series(p.rows);
}

/// Removes temporaries left by a process killed while writing a checkpoint
/// (.OUTPUT.partial.tmp-*) or the final file (.OUTPUT.tmp-*).
void remove_stale_temporaries(const std::string& output) {
  namespace fs = std::filesystem;
  const fs::path p(output);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  const std::string a = fs::path(io::temporary_prefix(output)).filename().string();
  const std::string b = fs::path(io::temporary_prefix(partial_path(output))).filename().string();
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(a, 0) == 0 || name.rfind(b, 0) == 0) fs::remove(entry.path(), ec);
  }
}

/// A run to a file, through OUTPUT.partial (tilt.hpp).
class FileRecorder : public Recorder {
 public:
  FileRecorder(std::string output, bool force) : output_(std::move(output)), partial_(partial_path(output_)), force_(force) {}

  /// Starts the partial: header, grains, frame 0 and the checkpoint of step 0.
  void start(const io::RunHeader& h, const Grains& g, Pending& p, const cd::Engine& e, const LoopState& s) {
    remove_stale_temporaries(output_);
    const std::string tmp = io::make_temporary_beside(partial_);
    {
      h5::File f = h5::create(tmp, partial_);
      io::RunWriter w(f, h, g);
      append_pending(w, p);
      write_checkpoint(f, e, s);
      f.close();
    }
    io::rename_onto(tmp, partial_);
    io::unregister_temporary(tmp);
    p.clear();
    committed_step_ = e.state().step;
  }

  /// The partial already holds everything up to `step` (a resumed run's checkpoint).
  void mark_committed(std::int64_t step) { committed_step_ = step; }
  bool checkpoints() const override { return true; }

  void commit(Pending& p, const cd::Engine& e, const LoopState& s) override {
    // Nothing new since the last checkpoint: the partial is already it (copying a large
    // partial to rewrite the same checkpoint would only delay an interrupted run's end).
    if (p.frames.empty() && p.rows.size() == 0 && e.state().step == committed_step_) return;
    const std::string tmp = io::make_temporary_beside(partial_);
    std::error_code ec;
    std::filesystem::copy_file(partial_, tmp, std::filesystem::copy_options::overwrite_existing, ec);
    if (ec) throw Error(partial_, "", "cannot copy for a checkpoint: " + ec.message());
    {
      h5::File f = h5::open_write(tmp, partial_);
      io::RunWriter w = io::RunWriter::reopen(f, std::numeric_limits<std::int64_t>::max());
      keep_recorded_columns(f, p.rows);
      append_pending(w, p);
      write_checkpoint(f, e, s);
      f.close();
    }
    io::rename_onto(tmp, partial_);
    io::unregister_temporary(tmp);
    p.clear();
    committed_step_ = e.state().step;
  }

  void finish(Pending& p, const cd::Engine& e, const LoopState& s, const io::Values& results) override {
    commit(p, e, s);  // a kill from here on resumes at the last step and redoes only this
    h5::File src = h5::open_read(partial_, partial_);
    io::RunHeader h = io::read_header(src);
    h.results = results;
    io::Output out(output_, force_);
    h5::File& dst = out.create_hdf5();
    io::write_header(dst, h);
    // The units module as the partial declared it (a partial written before it was
    // declared keeps its old unit texts, so it is not declared for them either).
    if (h5::exists(src, "/h5md/modules/units")) io::declare_units_module(dst);
    // H5Ocopy keeps chunking, filters and the hard links inside each copied group (the
    // shared step and time of the observables); /checkpoint is left behind.
    for (const char* g : {"/particles", "/contacts", "/observables"}) {
      if (!h5::exists(src, g)) continue;
      if (H5Ocopy(src.id(), g, dst.id(), g, H5P_DEFAULT, H5P_DEFAULT) < 0)
        throw Error(output_, g, "cannot copy from the partial run");
    }
    src.close();
    out.commit();
    std::filesystem::remove(partial_);
  }

  void interrupt(Pending& p, const cd::Engine& e, const LoopState& s) override { commit(p, e, s); }

 private:
  std::string output_, partial_;
  bool force_;
  std::int64_t committed_step_ = -1;
};

/// A run to standard output: an in-memory file written out at the end.
class StreamRecorder : public Recorder {
 public:
  StreamRecorder(const io::RunHeader& h, const Grains& g) : out_("-", true) {
    writer_ = std::make_unique<io::RunWriter>(out_.create_hdf5(), h, g);
  }
  void commit(Pending& p, const cd::Engine&, const LoopState&) override {
    append_pending(*writer_, p);
    p.clear();
  }
  void finish(Pending& p, const cd::Engine& e, const LoopState& s, const io::Values& results) override {
    commit(p, e, s);
    for (const auto& [k, v] : results) writer_->set_result(k, v);
    out_.commit();
  }
  void interrupt(Pending& p, const cd::Engine& e, const LoopState& s) override {
    finish(p, e, s, {{"interrupted", std::int64_t{1}}, {"steps", e.state().step}});
  }
  bool checkpoints() const override { return false; }

 private:
  io::Output out_;
  std::unique_ptr<io::RunWriter> writer_;
};

// ---------------------------------------------------------------------------------------
// The loop

double angle_deg(const TiltOptions& o, std::int64_t step) {
  return o.from_deg + static_cast<double>(step) * o.rate_deg;
}

TiltOutcome drive(cd::Engine& engine, Recorder& rec, const TiltOptions& o, LoopState st, Pending& pending,
                  const TiltHooks& hooks) {
  const Agitation agitation(engine.grains(), o.settings.gravity);
  const std::vector<Species> species = engine.grains().species;
  const std::int64_t margin = steps_for(o.margin_deg, o.rate_deg);
  const std::int64_t cap = o.to_deg ? steps_for(*o.to_deg - o.from_deg, o.rate_deg)
                                    : steps_for(o.max_deg - o.from_deg, o.rate_deg);
  auto last_step = [&] {
    if (!o.to_deg && st.detector.detected) return std::min(cap, st.detector.confirmed_step + margin);
    return cap;
  };
  TiltOutcome out;
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
    append_observables(pending.rows, r, count_critical(c, species, o.settings.mu_grain, o.settings.mu_wall, o.eps));
    if (!r.converged) ++st.unconverged;
    st.max_overlap = std::max(st.max_overlap, r.max_overlap);
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
    if (step % o.checkpoint_every == 0) rec.commit(pending, engine, st);
  }
  // The last step made durable: from here on a kill loses nothing but the final copy
  // (resumed, the run only writes its output), so a signal may end the tool at once.
  if (rec.checkpoints()) {
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
                   : (st.detector.detected && step == st.detector.confirmed_step + margin) ? "avalanche"
                                                                                           : "max_angle";
  io::Values results{
      {"steps", step},
      {"final_angle_deg", out.final_angle_deg},
      {"avalanche_detected", std::int64_t{st.detector.detected ? 1 : 0}},
      {"unconverged_steps", st.unconverged},
      {"max_overlap_m", st.max_overlap},
      {"stop_reason", out.stop_reason},
  };
  // Flagged in the file as well as on stderr: a number of warnings and their text.
  out.warnings = settings_warnings(o.settings, agitation.diameter());
  for (auto& w : run_warnings(step, st.unconverged, st.max_overlap, agitation.diameter(),
                              o.settings.contact_stiffness))
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
  rec.finish(pending, engine, st, results);
  return out;
}

}  // namespace

std::vector<std::string> run_warnings(std::int64_t steps, std::int64_t unconverged, double max_overlap_m,
                                      double diameter_m, double contact_stiffness) {
  std::vector<std::string> w;
  char line[300];
  // 1 %: a few isolated cap hits during impacts are expected and harmless; beyond that the
  // forces of a visible part of the run are those of a truncated Gauss-Seidel, whose
  // critical contacts differ from the converged ones (docs/performance.md).
  if (steps > 0 && unconverged * 100 > steps) {
    std::snprintf(line, sizeof line,
                  "%lld of %lld steps (%.1f %%) hit the sweep cap; their forces are not converged "
                  "(raise --max-sweeps; docs/performance.md)",
                  static_cast<long long>(unconverged), static_cast<long long>(steps),
                  100.0 * static_cast<double>(unconverged) / static_cast<double>(steps));
    w.emplace_back(line);
  }
  // 1e-3 D: the documented bound of the overlaps (docs/method.md); larger ones mean grains
  // travel too far in one step for the velocity-level contact law to hold them apart.
  // With a contact stiffness k the overlap f / k is the contact's compliance, chosen with k
  // (docs/method.md, "Force selection"): the warning then says so instead of blaming h.
  if (diameter_m > 0.0 && max_overlap_m > 1e-3 * diameter_m) {
    if (contact_stiffness > 0.0)
      std::snprintf(line, sizeof line,
                    "the largest overlap, %.2g D, exceeds 1e-3 D: the compliance of the contact "
                    "stiffness (overlap = force / k; a stiffer k makes it smaller)",
                    max_overlap_m / diameter_m);
    else
      std::snprintf(line, sizeof line,
                    "the largest overlap, %.2g D, exceeds 1e-3 D; the time step is too large for these "
                    "speeds (lower --time-step)",
                    max_overlap_m / diameter_m);
    w.emplace_back(line);
  }
  return w;
}

std::vector<std::string> settings_warnings(const cd::Settings& s, double diameter_m) {
  std::vector<std::string> w;
  char line[300];
  // The map's grid has h sqrt(g/D) = 0.0099 (no overlap at any tolerance of 1e-3 or
  // tighter) and 0.04 (overlaps at 1e-3 and looser, at nearly every tolerance from 0.16):
  // 0.02 is the geometric middle of the last sound point and the first failing one.
  const double h_hat = diameter_m > 0.0 ? s.time_step * std::sqrt(s.gravity / diameter_m) : 0.0;
  if (h_hat > 0.02) {
    std::snprintf(line, sizeof line,
                  "h sqrt(g/D) = %.3g is above 0.02; runs of the stability map overlapped beyond 1e-3 D "
                  "from 0.04 on (lower --time-step; docs/performance.md)",
                  h_hat);
    w.emplace_back(line);
  }
  // At 1e-2 and 1e-1 every run of the map at h >= 1e-4 s overlapped, or avalanched more
  // than 2 degrees from the reference (the artificial stiffness of a truncated solver).
  // The map measured the sweep criteria; 'law' is in units of g h, another scale.
  if (s.tolerance >= 1e-2 && s.criterion != cd::Criterion::law) {
    std::snprintf(line, sizeof line,
                  "the tolerance %.3g is 1e-2 or looser; runs of the stability map overlapped or moved "
                  "the avalanche there (lower --tolerance; docs/performance.md)",
                  s.tolerance);
    w.emplace_back(line);
  }
  return w;
}

namespace {

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

// ---------------------------------------------------------------------------------------

void validate(const TiltOptions& o) {
  auto bad = [](const std::string& what) { throw UsageError(what); };
  if (!(o.rate_deg > 0.0) || !std::isfinite(o.rate_deg)) bad("--rate must be > 0");
  if (!std::isfinite(o.from_deg)) bad("--from must be finite");
  // The start is --from, or with --branch-at the tilt of the frame branched from.
  if (o.to_deg && !(*o.to_deg >= o.from_deg))
    bad("--to " + io::format_number(*o.to_deg) + " is below the starting tilt " + io::format_number(o.from_deg) +
        " deg (--from, or the frame of --branch-at)");
  if (!(o.max_deg >= o.from_deg)) bad("the maximum angle must be >= --from");
  if (!(o.margin_deg >= 0.0)) bad("--margin must be >= 0");
  if (!(o.avalanche_energy > 0.0)) bad("--avalanche-ek must be > 0");
  if (!(o.avalanche_hold_deg >= 0.0)) bad("--avalanche-hold must be >= 0");
  if (o.frame_every < 1) bad("the frame interval must be >= 1 step");
  if (o.checkpoint_every < 1) bad("--checkpoint-every must be >= 1");
  if (!(o.eps >= 0.0 && o.eps < 1.0)) bad("--eps must be in [0, 1)");
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

InheritedOptions inherit_options(const io::Values& run, const TiltOptions& asked, const std::set<std::string>& given,
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
  for (const auto& [option, key] : tilt_option_parameters()) {
    if (option == "frame-every-deg" || (start_deg && key == "tilt_from_deg")) continue;  // one entry per parameter
    if (merged.at(key) == before.at(key)) continue;
    const auto by = option_of.find(key);
    out.changes.push_back({by == option_of.end() ? "" : by->second, key, message_text(key, before.at(key)),
                           message_text(key, merged.at(key))});
  }
  return out;
}

namespace {

/// The physical parameters a tilt takes from its pile unless options override them: a
/// bad one is the file's error (exit 1, the file named), not a usage error.
void check_pile_parameters(const io::Values& v, const std::string& file) {
  auto check = [&](const char* key, bool positive) {
    if (!v.count(key)) return;
    const double x = io::as_real(v, key, file);
    if (positive ? !(x > 0) : !(x >= 0)) {
      char what[160];
      std::snprintf(what, sizeof what, "%s must be %s 0, got %g", key, positive ? ">" : ">=", x);
      throw Error(file, "/parameters", what);
    }
  };
  check("mu_grain", false);
  check("mu_wall", false);
  check("gravity_m_s2", false);
  check("diameter_mean_m", true);
}

/// Frame k of a pile or run as the start of a tilt.
PileInput start_from_frame(const io::h5::File& f, const io::RunReader& r, std::size_t k) {
  check_pile_parameters(r.header().parameters, f.name());
  PileInput p;
  p.name = f.name();
  p.box = r.header().box;
  const Frame fr = r.frame(k);
  p.grains = fr.grains;
  p.contacts = fr.contacts;
  p.parameters = r.header().parameters;
  p.provenance = r.header().provenance;
  return p;
}

void check_grains(const io::h5::File& f, const io::RunReader& r, const std::string& what) {
  if (r.frame_count() == 0) throw Error(f.name(), "/particles/grains/position", "the " + what + " has no frame");
  if (r.grain_count() == 0) throw Error(f.name(), "/particles/grains", "the " + what + " has no grain");
}

}  // namespace

PileInput read_pile(const io::h5::File& f) {
  io::RunReader r(f);
  if (r.header().kind != "pile")
    throw Error(f.name(), "/", "is a '" + r.header().kind + "' file, expected a pile (made by deposit)");
  check_grains(f, r, "pile");
  return start_from_frame(f, r, r.frame_count() - 1);
}

cd::EngineState warm_start_state(const Contacts& contacts, double time_step) {
  cd::EngineState es;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (contacts.fn[k] == 0.0 && contacts.ft[k] == 0.0) continue;
    es.impulses.push_back({contacts.i[k], contacts.j[k], contacts.fn[k] * time_step, contacts.ft[k] * time_step});
  }
  std::sort(es.impulses.begin(), es.impulses.end(), [](const cd::StoredImpulse& a, const cd::StoredImpulse& b) {
    return cd::pair_key(a.i, a.j) < cd::pair_key(b.i, b.j);
  });
  return es;
}

PileInput read_branch(const io::h5::File& f, double at_deg) {
  io::RunReader r(f);
  if (r.header().kind != "run")
    throw Error(f.name(), "/", "is a '" + r.header().kind + "' file; a branch starts from a run (made by tilt-cd)");
  check_grains(f, r, "run");
  // The last frame at or below the requested tilt (frames are in step order, and the
  // tilt grows with the step). Angles are compared in degrees to 1e-9 so that a frame
  // written at "5 degrees" is found by --branch-at 5.
  std::optional<std::size_t> pick;
  for (std::size_t k = 0; k < r.frame_count(); ++k)
    if (r.frame_tilt_angle(k) / kDeg <= at_deg + 1e-9) pick = k;
  if (!pick) {
    char what[160];
    std::snprintf(what, sizeof what, "has no frame at or below %g deg (the first is at %g deg)", at_deg,
                  r.frame_tilt_angle(0) / kDeg);
    throw Error(f.name(), "/particles/grains/position", what);
  }
  PileInput p = start_from_frame(f, r, *pick);
  p.branch = PileInput::Branch{r.frame_steps()[*pick], r.frame_tilt_angle(*pick) / kDeg};
  return p;
}

std::string partial_path(const std::string& output) {
  // OUTPUT.partial, unless that name is longer than the file system allows (NAME_MAX,
  // 255 bytes) for a legal OUTPUT of 248 bytes or more: then OUTPUT's name cut to leave
  // room for a hash of the whole name (FNV-1a, 64 bits), so that --resume finds the same
  // partial again and two long names sharing a beginning get different partials.
  const std::filesystem::path p(output);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  const long name_max = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  const std::size_t limit = static_cast<std::size_t>(name_max > 0 ? name_max : 255);
  std::string name = p.filename().string();
  if (name.size() + 8 <= limit) return output + ".partial";
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : name) h = (h ^ c) * 1099511628211ull;
  char tail[32];
  std::snprintf(tail, sizeof tail, "-%016llx.partial", static_cast<unsigned long long>(h));
  name.resize(limit - std::strlen(tail));
  return (dir / (name + tail)).string();
}

PileInput read_partial(const std::string& output) {
  const std::string partial = partial_path(output);
  h5::File f = h5::open_read(partial, partial);
  io::RunReader r(f);
  PileInput p;
  p.name = partial;
  p.box = r.header().box;
  p.parameters = r.header().parameters;
  p.provenance = r.header().provenance;
  p.grains = read_checkpoint(f, r.grain_properties()).grains;
  return p;
}

void check_output(const std::string& output, bool force) {
  io::Output check(output, force, true);  // an existing output, a missing folder, a terminal
  std::error_code ec;
  if (output != "-" && !force && std::filesystem::exists(partial_path(output), ec))
    throw Error(partial_path(output), "", "an interrupted run exists; use --resume to continue it or --force to start over");
}

TiltOutcome run_tilt(const PileInput& pile, const TiltOptions& o, const std::string& output, bool force,
                     const io::Provenance& prov, const TiltHooks& hooks) {
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
  if (to_stdout) {
    StreamRecorder rec(h, pile.grains);
    return drive(engine, rec, o, st, pending, hooks);
  }
  FileRecorder rec(output, force);
  rec.start(h, pile.grains, pending, engine, st);
  try {
    return drive(engine, rec, o, st, pending, hooks);
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

TiltOutcome resume_tilt(const TiltOptions& o, const std::string& output, bool force, const TiltHooks& hooks) {
  validate(o);
  if (output == "-") throw UsageError("--resume needs an output file (-o FILE), not standard output");
  const std::string partial = partial_path(output);
  std::error_code ec;
  if (!std::filesystem::exists(partial, ec)) throw Error(partial, "", "no partial run to resume");
  remove_stale_temporaries(output);
  Restored rs;
  Box box;
  {
    h5::File f = h5::open_read(partial, partial);
    io::RunReader r(f);
    if (r.header().kind != "run") throw Error(partial, "/", "is not a partial tilt run");
    const io::Values stored = with_pre_seam_settings(r.header().parameters);
    for (const auto& [k, v] : tilt_parameters(o)) {
      auto it = stored.find(k);
      if (it == stored.end()) throw Error(partial, "/parameters", "missing parameter '" + k + "'");
      if (!same_value(it->second, v))
        throw Error(partial, "/parameters", k + " is " + value_text(v) + " here but " + value_text(it->second) +
                                                " in the interrupted run; resume with the same options");
    }
    rs = read_checkpoint(f, r.grain_properties());
    box = r.header().box;
  }
  cd::Engine engine(box, rs.grains, o.settings);
  engine.set_state(rs.engine);
  LoopState st = rs.loop;
  st.detector.threshold = o.avalanche_energy;
  st.detector.hold = hold_steps(o);
  Pending pending;
  FileRecorder rec(output, force);
  rec.mark_committed(rs.engine.step);
  return drive(engine, rec, o, st, pending, hooks);
}

}  // namespace cdpile::sim
