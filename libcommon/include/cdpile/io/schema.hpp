/// The cdpile file schema (docs/schema.md): one HDF5 layout for piles, runs and the
/// analysis products, following H5MD 1.1 for the grains.
///
///   /                         attrs: schema = "cdpile", schema_version, kind
///   /h5md                     attrs: version = [1, 1]; author/, creator/ (name, version)
///   /particles/grains/box     attrs: dimension = 2, boundary = [none, none],
///                             edges [2] (width, height, m), walls (floor, left, right)
///   /particles/grains/{radius,mass,inertia,species}      [N] fixed per grain
///   /particles/grains/{position,velocity}/{step,time,value}   value [F][N][2]
///   /particles/grains/{orientation,angular_velocity}/{step,time,value}  value [F][N]
///   /contacts/{step,time,tilt_angle,offset,count}        [F] per frame
///   /contacts/{i,j,fn,ft,gap,status} [K], {point,normal} [K][2]: all frames, flat
///   /observables/<name>/{step,time,value}   one row per time step (step/time linked)
///   /parameters               attrs: every physical and numerical parameter, the
///                             unit in the name's suffix (time_step_s, mu_grain, ...)
///   /results                  attrs: results of the run (e.g. avalanche_angle_deg)
///   /provenance/<k>           attrs: tool, version, command_line, inputs, date; cpu_s
///                             where recorded; via in a file made from several inputs
///                             (merge_histories)
#pragma once

#include "cdpile/io/files.hpp"
#include "cdpile/io/h5.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace cdpile::io {

inline constexpr std::int64_t schema_version = 1;

/// A parameter or result: an integer, a real or a text. Names carry their unit as a
/// suffix (`time_step_s`, `tilt_rate_deg_per_step`); a bare name is dimensionless.
using Value = std::variant<std::int64_t, double, std::string>;
using Values = std::map<std::string, Value>;

double as_real(const Values& v, const std::string& key, const std::string& file);
std::int64_t as_int(const Values& v, const std::string& key, const std::string& file);

/// Who made a file, from what: one entry per tool that wrote into it, appended.
struct Provenance {
  std::string tool, version, command_line, inputs, date;
  /// In a file made from several inputs, the input this entry came through ("run2.h5";
  /// "c.h5 > run2.h5" through two such files); empty for the file's own tool and for the
  /// entries of a single input's chain.
  std::string via = {};
  /// CPU seconds (user + system, all threads) the tool spent making its part of the file,
  /// summed over the processes of a resumed tilt; negative where not recorded (files
  /// written before 2026-12-02).
  double cpu_s = -1.0;
};

/// The history of a file made from `inputs` (name and history of each, in order): with one
/// input, its history as it is; with several, each input's history in turn, every entry
/// marked with the input it came through (`via`), so that no input's chain is lost and each
/// can be told apart. The caller appends its own entry.
std::vector<Provenance> merge_histories(
    const std::vector<std::pair<std::string, std::vector<Provenance>>>& inputs);
/// CPU seconds (user + system, all threads) this process has used so far.
double process_cpu_s();
/// Provenance of the running tool (date now, version of this build, its CPU so far).
Provenance provenance_now(const std::string& tool, const std::string& command_line,
                          const std::string& inputs);

/// The person recorded in /h5md/author of the files this process writes (H5MD 1.1: the
/// author's real name, optionally an email).
struct Author {
  std::string name, email;
};
/// Sets the author from "NAME" or "NAME <EMAIL>" (the --author option of every tool).
void set_author(const std::string& text);
/// The author: set_author's, else the environment variable CDPILE_AUTHOR (same form),
/// else the user's full name from the password database (its GECOS field), else the login
/// name, else "unknown".
Author author();
/// Parses "NAME" or "NAME <EMAIL>"; surrounding blanks are dropped.
Author parse_author(const std::string& text);

/// The H5MD units module (version 1.0, system "SI"): declared in piles and runs, whose
/// H5MD elements carry `unit` attributes in its notation (m, s, kg m-1, degree, ...).
void declare_units_module(const h5::File& f);
/// A `unit` attribute as the units module wants it (variable-length ASCII); nothing for a
/// dimensionless quantity (empty unit).
void set_unit(const h5::File& f, const std::string& path, const std::string& unit);

/// Per-step scalar time series: named columns over steps. Standard names (units):
/// tilt_angle (deg), kinetic_energy (J/m, translational, sum over grains),
/// rotational_energy (J/m), contacts (active, f_n > 0), contacts_grain (active
/// grain-grain), sliding (status slide), sweeps (NSGS sweeps), residual (solver
/// residual, dimensionless), converged (1/0), max_overlap (m).
struct Series {
  std::vector<std::int64_t> step;
  std::vector<double> time;  ///< [s]
  std::map<std::string, std::vector<double>> real;
  std::map<std::string, std::vector<std::int64_t>> integer;
  std::map<std::string, std::string> unit;  ///< unit per column name ("" = none)

  std::size_t size() const { return step.size(); }
  void clear();
};

/// Kind of a file: "pile" (one static frame), "run" (a tilt simulation); analysis
/// products name themselves ("localnu", ...).
struct RunHeader {
  std::string kind = "run";
  Box box;
  Values parameters;
  Values results;
  std::vector<Provenance> provenance;
};

/// Writes a pile or a run. The grains' fixed properties are written once; frames and
/// observables are appended (chunked, extendible datasets).
class RunWriter {
 public:
  /// Starts a new file in `f` with the grains' fixed properties from `grains`.
  RunWriter(h5::File& f, const RunHeader& header, const Grains& grains);
  /// Reopens an existing run for appending, dropping frames and observables after
  /// `last_step` (resume from a checkpoint).
  static RunWriter reopen(h5::File& f, std::int64_t last_step);

  void append_frame(const Frame& frame);
  /// Several frames with one append per dataset: reopening a compressed, chunked dataset
  /// for every frame re-reads its last chunk, which made many small frames slow to write.
  void append_frames(const std::vector<Frame>& frames);
  void append_series(const Series& rows);
  void set_result(const std::string& name, const Value& v);
  void add_provenance(const Provenance& p);
  /// Records the CPU of the tool that wrote the file last (its provenance's last entry).
  void set_last_cpu(double cpu_s);
  void flush();

  std::size_t frames() const { return frames_; }
  std::int64_t contacts_written() const { return contacts_; }

 private:
  explicit RunWriter(h5::File& f) : f_(&f) {}
  h5::File* f_;
  std::size_t frames_ = 0, grains_ = 0;
  std::int64_t contacts_ = 0;
};

/// Reads and validates a pile or run. Every problem (missing group, wrong schema
/// version, wrong shape, NaN or infinite value, negative radius, inconsistent
/// offsets) is an Error naming the file and the path inside it; so are magnitudes no
/// pile can have (a radius over half the box width; in frame(), a grain outside the box
/// by more than length_scale() or faster than speed_bound()) and a contact listed twice
/// in a frame, and every value outside the range docs/schema.md, "Ranges", states (box
/// edges, masses, inertias, steps, times, tilts, contact gaps, points and normals, the
/// standard observables): "WHERE: VALUE is outside RANGE".
class RunReader {
 public:
  explicit RunReader(const h5::File& f);
  const RunHeader& header() const { return header_; }
  std::size_t grain_count() const { return n_; }
  std::size_t frame_count() const { return frame_steps_.size(); }
  const std::vector<std::int64_t>& frame_steps() const { return frame_steps_; }
  /// Frame k: the grains (fixed properties and state) and contacts.
  Frame frame(std::size_t k) const;
  /// Only the contacts of frame k (cheaper: no grain state).
  Contacts contacts(std::size_t k) const;
  double frame_tilt_angle(std::size_t k) const { return frame_tilt_[k]; }
  double frame_time(std::size_t k) const { return frame_time_[k]; }
  /// The grains' fixed properties (radius, mass, inertia, species), state zeroed.
  const Grains& grain_properties() const { return grains_; }
  /// All per-step observables. Error if the file is a run without them (check_observables).
  Series series() const;
  /// Error naming /observables if the file is a run (kind "run") without observables; a
  /// pile may lack them.
  void check_observables() const;
  const std::string& name() const { return f_->name(); }
  /// The file read (to-xdmf maps its datasets into virtual ones).
  const h5::File& file() const { return *f_; }
  /// L = max(box width, box height) [m]: frame() refuses a grain centre farther than L
  /// outside the box.
  double length_scale() const;
  /// The fastest a grain may move, rim included: 1000 sqrt(g L) [m/s], g the file's
  /// gravity_m_s2 (9.81 if absent or zero).
  double speed_bound() const;
  /// The largest contact force a pile can have [N/m]: the impulse that stops all its grains
  /// moving at speed_bound() within one time step (the file's time_step_s, 1e-4 s if absent,
  /// not below 1e-9 s). contacts() refuses a force beyond it: the engine's warm start of
  /// such a force throws grains beyond every bound (a force of 1e300 crashed tilt-cd).
  double force_bound() const;
  /// How far from the box a contact's point may lie and how large its gap may be [m]:
  /// 10 L + h speed_bound() (two centres inside the box enlarged by L are less than 4.3 L
  /// apart, a radius is at most L / 2, and the predicted configuration of a step moves a
  /// centre by at most h speed_bound()); docs/schema.md, "Ranges".
  double contact_reach() const;
  /// Error naming `path` (its grain positions) and `velocity_path` unless every grain of
  /// `g` lies within the box enlarged by length_scale() and moves slower than
  /// speed_bound(), rim included: the magnitudes a pile can have, for a frame and for the
  /// checkpoint of a partial run. `what` starts the message ("frame 3", "checkpoint").
  void check_grain_state(const Grains& g, const std::string& path, const std::string& velocity_path,
                         const std::string& what) const;

 private:
  const h5::File* f_;
  RunHeader header_;
  Grains grains_;
  std::size_t n_ = 0;
  std::vector<std::int64_t> frame_steps_, offset_, count_;
  std::vector<double> frame_time_, frame_tilt_;
};

/// Writes and reads the common attributes of any cdpile file (root attributes,
/// /h5md, /parameters, /results, /provenance). Used by RunWriter and by the analysis
/// products.
void write_header(const h5::File& f, const RunHeader& h);
RunHeader read_header(const h5::File& f, const std::string& expected_kind = "");
void write_values(const h5::File& f, const std::string& group, const Values& v);
Values read_values(const h5::File& f, const std::string& group);
void append_provenance(const h5::File& f, const Provenance& p);
/// Sets `cpu_s` on the last /provenance entry: a tool whose file is written before its
/// work ends (a tilt's header) records its CPU there when it ends.
void set_last_cpu(const h5::File& f, double cpu_s);

}  // namespace cdpile::io
