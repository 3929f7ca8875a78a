// Where a tilt run's recorded data goes: OUTPUT.partial and its checkpoints, or standard
// output (recorder.hpp; docs/method.md, "Checkpoints").
#include "cdpile/sim/recorder.hpp"

#include "cdpile/error.hpp"
#include "cdpile/io/checkpoint.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <utility>

namespace cdpile::sim {
namespace h5 = io::h5;

// ---------------------------------------------------------------------------------------
// The partial and its checkpoint

std::string partial_path(const std::string& output) {
  // OUTPUT.partial, unless that name is longer than the file system allows (NAME_MAX,
  // 255 bytes) for a legal OUTPUT of 248 bytes or more: then OUTPUT's name cut to leave
  // room for a hash of the whole name (FNV-1a, 64 bits), so that --resume finds the same
  // partial again and two long names sharing a beginning get different partials.
  const std::filesystem::path p(output);
  const std::filesystem::path dir =
      p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
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

bool has_partial(const std::string& output) {
  std::error_code ec;
  return std::filesystem::exists(partial_path(output), ec);
}

bool finished_run(const std::string& output) {
  std::error_code ec;
  if (!std::filesystem::exists(output, ec)) return false;
  std::filesystem::remove(partial_path(output), ec);
  return true;
}

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

void write_checkpoint(const h5::File& f, const cd::Engine& e, const LoopState& s) {
  io::Checkpoint c;
  c.grains = e.grains();
  const cd::EngineState st = e.state();
  for (const auto& imp : st.impulses) c.impulses.push_back({imp.i, imp.j, imp.rn, imp.rt});
  c.step = st.step;
  c.time = st.time;
  const AvalancheDetector& d = s.detector;
  c.counters = {{"detector_since", d.since},
                {"detector_since_deg", d.since_deg},
                {"detector_detected", std::int64_t{d.detected ? 1 : 0}},
                {"detector_angle_deg", d.angle_deg},
                {"detector_start_step", d.start_step},
                {"detector_confirmed_step", d.confirmed_step},
                {"unconverged_steps", s.unconverged},
                {"max_overlap", s.max_overlap},
                {"max_overlap_grown", s.max_overlap_grown},
                {"cpu_s", s.cpu_s},
                {"substep_level", std::int64_t{st.substep_level}}};
  c.description =
      "state to resume this partial run bit for bit: grain state, warm-start impulses [N s/m] "
      "of the last step by pair (i, j), clock and avalanche detector; see docs/method.md";
  io::write_checkpoint(f, c);
}

Restored read_checkpoint(const h5::File& f, const Grains& properties) {
  const io::Checkpoint c = io::read_checkpoint(f, properties);
  const std::string& file = f.name();
  Restored r;
  r.grains = c.grains;
  for (const auto& imp : c.impulses) r.engine.impulses.push_back({imp.i, imp.j, imp.rn, imp.rt});
  r.engine.step = c.step;
  r.engine.time = c.time;
  // Partials written before sub-steps existed have no level: they ran without sub-steps.
  r.engine.substep_level =
      c.has_counter("substep_level") ? static_cast<int>(c.counter_int("substep_level", file)) : 0;
  AvalancheDetector& d = r.loop.detector;
  d.since = c.counter_int("detector_since", file);
  d.since_deg = c.counter_real("detector_since_deg", file);
  d.detected = c.counter_int("detector_detected", file) != 0;
  d.angle_deg = c.counter_real("detector_angle_deg", file);
  d.start_step = c.counter_int("detector_start_step", file);
  d.confirmed_step = c.counter_int("detector_confirmed_step", file);
  r.loop.unconverged = c.counter_int("unconverged_steps", file);
  r.loop.max_overlap = c.counter_real("max_overlap", file);
  // Partials written before the growth was kept have only the largest overlap: an upper
  // bound of the growth, so a resumed run warns at least as often as it would have.
  r.loop.max_overlap_grown = c.has_counter("max_overlap_grown")
                                 ? c.counter_real("max_overlap_grown", file)
                                 : r.loop.max_overlap;
  // Partials written before the CPU was kept: the resumed run records its own CPU only.
  r.loop.cpu_s = c.has_counter("cpu_s") ? c.counter_real("cpu_s", file) : 0.0;
  return r;
}

// ---------------------------------------------------------------------------------------
// Recorders

namespace {

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

}  // namespace

FileRecorder::FileRecorder(std::string output, bool force)
    : output_(std::move(output)), partial_(partial_path(output_)), force_(force) {}

void FileRecorder::start(const io::RunHeader& h, const Grains& g, Pending& p, const cd::Engine& e,
                         const LoopState& s) {
  remove_stale_temporaries(output_);
  const std::string tmp = io::make_temporary_beside(partial_);
  h5::File f = h5::create(tmp, partial_);
  io::RunWriter w(f, h, g);
  seal(f, w, tmp, p, e, s);
}

void FileRecorder::seal(h5::File& f, io::RunWriter& w, const std::string& tmp, Pending& p,
                        const cd::Engine& e, const LoopState& s) {
  append_pending(w, p);
  write_checkpoint(f, e, s);
  f.close();
  io::rename_onto(tmp, partial_);
  io::unregister_temporary(tmp);
  p.clear();
  committed_step_ = e.state().step;
}

void FileRecorder::commit(Pending& p, const cd::Engine& e, const LoopState& s) {
  // Nothing new since the last checkpoint: the partial is already it (copying a large
  // partial to rewrite the same checkpoint would only delay an interrupted run's end).
  if (p.frames.empty() && p.rows.size() == 0 && e.state().step == committed_step_) return;
  const std::string tmp = io::make_temporary_beside(partial_);
  std::error_code ec;
  std::filesystem::copy_file(partial_, tmp, std::filesystem::copy_options::overwrite_existing, ec);
  if (ec) throw Error(partial_, "", "cannot copy for a checkpoint: " + ec.message());
  h5::File f = h5::open_write(tmp, partial_);
  io::RunWriter w = io::RunWriter::reopen(f, std::numeric_limits<std::int64_t>::max());
  keep_recorded_columns(f, p.rows);
  seal(f, w, tmp, p, e, s);
}

void FileRecorder::finish(Pending& p, const cd::Engine& e, const LoopState& s,
                          const io::Values& results) {
  commit(p, e, s);  // a kill from here on resumes at the last step and redoes only this
  h5::File src = h5::open_read(partial_, partial_);
  io::RunHeader h = io::read_header(src);
  h.results = results;
  io::Output out(output_, force_);
  h5::File& dst = out.create_hdf5();
  io::write_header(dst, h);
  io::set_last_cpu(dst, s.cpu_s);  // the tilt's entry, last in a run's history
  // The units module as the partial declared it (a partial written before it was
  // declared keeps its old unit texts, so it is not declared for them either).
  if (h5::exists(src, "/h5md/modules/units")) io::declare_units_module(dst);
  // A copy keeps chunking, filters and the hard links inside each copied group (the
  // shared step and time of the observables); /checkpoint is left behind.
  for (const char* g : {"/particles", "/contacts", "/observables"})
    if (h5::exists(src, g)) h5::copy(src, g, dst);
  src.close();
  out.commit();
  std::filesystem::remove(partial_);
}

StreamRecorder::StreamRecorder(const io::RunHeader& h, const Grains& g) : out_("-", true) {
  writer_ = std::make_unique<io::RunWriter>(out_.create_hdf5(), h, g);
}

void StreamRecorder::commit(Pending& p, const cd::Engine&, const LoopState&) {
  append_pending(*writer_, p);
  p.clear();
}

void StreamRecorder::finish(Pending& p, const cd::Engine& e, const LoopState& s,
                            const io::Values& results) {
  commit(p, e, s);
  for (const auto& [k, v] : results) writer_->set_result(k, v);
  writer_->set_last_cpu(s.cpu_s);
  out_.commit();
}

void StreamRecorder::interrupt(Pending& p, const cd::Engine& e, const LoopState& s) {
  finish(p, e, s, {{"interrupted", std::int64_t{1}}, {"steps", e.state().step}});
}

}  // namespace cdpile::sim
