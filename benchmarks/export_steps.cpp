// Writes the frictional contact problems of real tilt steps in Siconos' fc2d text format,
// so that other solvers (benchmarks/newton_on_steps.py runs Siconos' own) can take on
// exactly the problems NSGS met: the steps that end at the sweep cap, where a paper run
// spends most of its time (docs/performance.md, "Newton on the capped steps").
//
// The run is branched as `tilt-cd --branch-at DEG` does (its last frame at or below DEG,
// warm-started from the frame's forces) and tilted on with the run's own solver settings
// and rate. After each step whose NSGS hit the sweep cap (every step with --all), it
// writes into OUTDIR, which must not exist:
//   step-K.dat   the step's problem (cd::Engine::delassus_problem, io::write_siconos_fc2d)
//   step-K.r     the impulses the engine ended the step with, 2m values on one line
//   step-K.r0    the impulses it started from (the previous step's, matched by the pair
//                as the engine's warm start matches them; 0 for a new pair), same layout
//   step-K.ut0   from the second step on: the previous step's tangential speed |u_t| at
//                its end (u = W R + q of its problem and impulses) [m/s], matched by the
//                pair the same way, one value per contact: the De Saxce shift a lagged law
//                would freeze (docs/performance.md, "A shift lagged by a step")
// and prints one line per step on stdout (TSV): the step K after the branch, tilt [deg],
// contact candidates m, active contacts, sweeps, the engine's residual (its maxm
// measure, docs/method.md) and the natural-map residual of its impulses (Siconos'
// measure, cd::natural_map_residual), and the file written (or '-').
//
// With --stiffness K the branch runs at the contact stiffness K [m g / D] (0: rigid) instead
// of the run's, as `tilt-cd --branch-at DEG --stiffness K` would: the same steps at another k;
// with --solver NAME, by that solver (cd::solver_from_name) instead of the run's. The last
// column is the CPU time of the step [ms], so that solvers compare on the same steps
// (docs/performance.md, "A factorised solver"); --max-substeps, --max-sweeps and
// --substep-after replace those settings (--max-substeps 1: every step's problem at the full
// h). With --none no file
// is written.
//
// Usage: export_steps RUN DEG STEPS OUTDIR [--all | --none] [--stiffness K] [--solver NAME]
//                     [--max-substeps N] [--max-sweeps N] [--substep-after S]
#include "cdpile/analysis/critical.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/error.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/siconos.hpp"
#include "cdpile/sim/common.hpp"
#include "cdpile/sim/tilt.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <utility>
#include <vector>
#include <numbers>
#include <optional>
#include <string>

namespace cd = cdpile::cd;
namespace io = cdpile::io;
namespace sim = cdpile::sim;

namespace {

int usage() {
  std::cerr << "usage: export_steps RUN DEG STEPS OUTDIR [--all | --none] [--stiffness K] "
               "[--solver NAME] [--max-substeps N] [--max-sweeps N] [--substep-after S]\n";
  return 2;
}

void write_text(const std::string& path, const auto& fill) {
  io::Output out(path, false);
  fill(out.text());
  out.commit();
}

void write_row(std::ostream& o, const Eigen::VectorXd& values) {
  char v[32];
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    std::snprintf(v, sizeof v, "%.17g", values[i]);
    o << v << (i + 1 < values.size() ? " " : "\n");
  }
}

using Pair = std::pair<std::int32_t, std::int32_t>;

/// Each contact's tangential speed |u_t| at the end of a step, u = W R + q, by its pair.
std::map<Pair, double> tangential_speeds(const cd::DelassusProblem& p, const Eigen::VectorXd& r,
                                         const cdpile::Contacts& rows) {
  const Eigen::VectorXd u = p.W * r + p.q;
  std::map<Pair, double> by_pair;
  for (std::size_t a = 0; a < rows.size(); ++a)
    by_pair[{rows.i[a], rows.j[a]}] = std::abs(u[2 * static_cast<Eigen::Index>(a) + 1]);
  return by_pair;
}

/// The previous step's |u_t| in this step's row order, 0 where the pair is new.
Eigen::VectorXd matched_speeds(const std::map<Pair, double>& previous, const cdpile::Contacts& rows) {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t a = 0; a < rows.size(); ++a) {
    const auto it = previous.find({rows.i[a], rows.j[a]});
    if (it != previous.end()) s[static_cast<Eigen::Index>(a)] = it->second;
  }
  return s;
}

/// The warm start of the step in the problem's row order: the stored impulse of each row's
/// pair (i, j), 0 where the pair is new. (The engine matches by the pair too; a step split
/// in sub-steps starts its later parts elsewhere, so this is the start of the first.)
Eigen::VectorXd matched_start(const std::vector<cd::StoredImpulse>& start, const cdpile::Contacts& rows) {
  std::map<std::pair<std::int32_t, std::int32_t>, std::pair<double, double>> by_pair;
  for (const cd::StoredImpulse& s : start) by_pair[{s.i, s.j}] = {s.rn, s.rt};
  Eigen::VectorXd r = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(rows.size()));
  for (std::size_t a = 0; a < rows.size(); ++a) {
    const auto it = by_pair.find({rows.i[a], rows.j[a]});
    if (it == by_pair.end()) continue;
    r[2 * static_cast<Eigen::Index>(a)] = it->second.first;
    r[2 * static_cast<Eigen::Index>(a) + 1] = it->second.second;
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) return usage();
  const std::string run = argv[1], dir = argv[4];
  bool all = false, none = false;
  std::optional<double> stiffness;  // [m g / D]
  std::optional<std::string> solver;
  std::optional<int> max_substeps, max_sweeps, substep_after;
  for (int a = 5; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--all")
      all = true;
    else if (arg == "--none")
      none = true;
    else if (arg == "--stiffness" && a + 1 < argc)
      stiffness = std::stod(argv[++a]);
    else if (arg == "--solver" && a + 1 < argc)
      solver = argv[++a];
    else if (arg == "--max-substeps" && a + 1 < argc)
      max_substeps = std::stoi(argv[++a]);
    else if (arg == "--max-sweeps" && a + 1 < argc)
      max_sweeps = std::stoi(argv[++a]);
    else if (arg == "--substep-after" && a + 1 < argc)
      substep_after = std::stoi(argv[++a]);
    else
      return usage();
  }
  try {
    const double at_deg = std::stod(argv[2]);
    const long steps = std::stol(argv[3]);
    if (steps < 1) return usage();
    if (std::filesystem::exists(dir)) throw cdpile::Error(dir, "", "exists; give a new folder");

    sim::PileInput pile;
    {
      io::Input in(run);
      pile = sim::read_branch(in.hdf5(), at_deg);
    }
    cd::Settings settings = sim::settings_from_parameters(pile.parameters, run);
    if (stiffness) {  // m g / D in N/m^2, as tilt-cd converts its option (sim::pile_settings)
      const double diameter = pile.parameters.count("diameter_mean_m")
                                  ? io::as_real(pile.parameters, "diameter_mean_m", run)
                                  : cdpile::analysis::mean_diameter(pile.grains);
      settings.contact_stiffness =
          *stiffness * cdpile::analysis::mean_mass(pile.grains) * settings.gravity / diameter;
    }
    if (solver) settings.solver = cd::solver_from_name(*solver);
    if (max_substeps) settings.max_substeps = *max_substeps;
    if (max_sweeps) settings.max_sweeps = *max_sweeps;
    if (substep_after) settings.substep_after = *substep_after;
    const double rate_deg = io::as_real(pile.parameters, sim::parameter_key("rate_deg"), run);
    cd::Engine engine(pile.box, pile.grains, settings);
    engine.set_state(sim::warm_start_state(pile.contacts, settings.time_step));
    std::filesystem::create_directories(dir);

    std::printf("step\ttilt_deg\tcandidates\tcontacts\tsweeps\tresidual\tnatural_map\tfile\t"
                "substeps\tcpu_ms\n");
    std::map<Pair, double> previous_speeds;  // |u_t| at the end of the step before
    for (long k = 1; k <= steps; ++k) {
      const double deg = pile.branch->tilt_deg + static_cast<double>(k) * rate_deg;
      const std::vector<cd::StoredImpulse> start = engine.state().impulses;
      const std::clock_t cpu = std::clock();
      const cd::StepReport r = engine.step(deg * std::numbers::pi / 180.0);
      const double cpu_ms = 1e3 * static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
      const cd::DelassusProblem p = engine.delassus_problem();
      const Eigen::VectorXd impulses = engine.local_impulses();
      std::string file = "-";
      if (!none && (all || !r.converged)) {
        char name[32];
        std::snprintf(name, sizeof name, "step-%06ld", k);
        file = std::string(name) + ".dat";
        write_text(dir + "/" + file, [&](std::ostream& o) { io::write_siconos_fc2d(o, p); });
        write_text(dir + "/" + name + ".r", [&](std::ostream& o) { write_row(o, impulses); });
        write_text(dir + "/" + name + ".r0", [&](std::ostream& o) {
          write_row(o, matched_start(start, engine.contacts()));
        });
        if (k > 1)
          write_text(dir + "/" + name + ".ut0", [&](std::ostream& o) {
            write_row(o, matched_speeds(previous_speeds, engine.contacts()));
          });
      }
      previous_speeds = tangential_speeds(p, impulses, engine.contacts());
      std::printf("%ld\t%.3f\t%d\t%d\t%d\t%.3e\t%.3e\t%s\t%d\t%.1f\n", k, deg, r.candidates,
                  r.contacts, r.sweeps, r.residual, cd::natural_map_residual(p, impulses),
                  file.c_str(), r.substeps, cpu_ms);
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::cerr << "export_steps: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
