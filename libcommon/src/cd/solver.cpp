// The solver seam: names, settings checks, the solver factory and the solver-independent
// residual of the contact law (solver.hpp, contact_system.hpp).
#include "cdpile/cd/solver.hpp"

#include "cdpile/cd/active_set.hpp"
#include "cdpile/cd/admm.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/local_solver.hpp"
#include "cdpile/cd/nsgs.hpp"
#include "cdpile/cd/pcg.hpp"
#include "cdpile/cd/schedule.hpp"
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace cdpile::cd {

const char* solver_name(SolverKind k) {
  switch (k) {
    case SolverKind::nsgs: return "nsgs";
    case SolverKind::nncg: return "nncg";
    case SolverKind::pcg: return "pcg";
    case SolverKind::newton: return "newton";
    case SolverKind::admm: return "admm";
  }
  return "?";
}

SolverKind solver_from_name(const std::string& name) {
  for (const SolverKind k :
       {SolverKind::nsgs, SolverKind::nncg, SolverKind::pcg, SolverKind::newton, SolverKind::admm})
    if (name == solver_name(k)) return k;
  throw UsageError("unknown contact solver '" + name + "' (nsgs, nncg, pcg, newton or admm)");
}

const char* criterion_name(Criterion c) {
  switch (c) {
    case Criterion::maxm: return "maxm";
    case Criterion::quad: return "quad";
    case Criterion::qm16: return "qm16";
    case Criterion::law: return "law";
    case Criterion::err: return "err";
  }
  return "?";
}

Criterion criterion_from_name(const std::string& name) {
  for (const Criterion c :
       {Criterion::maxm, Criterion::quad, Criterion::qm16, Criterion::law, Criterion::err})
    if (name == criterion_name(c)) return c;
  throw UsageError("unknown convergence criterion '" + name + "' (maxm, quad, qm16, law or err)");
}

void SolveReport::add_sweep(double new_residual) {
  residual = new_residual;
  history_[count_ % (kHistory + 1)] = new_residual;
  ++count_;
}

double SolveReport::contraction(int over) const {
  if (over < 1 || over > kHistory || count_ <= over) return -1.0;
  const double before = history_[(count_ - 1 - over) % (kHistory + 1)];
  if (before == 0.0) return 0.0;  // converged exactly then, and since
  return std::pow(residual / before, 1.0 / over);
}

int err_window(const SolverSettings& s) {
  return s.solver == SolverKind::pcg || s.solver == SolverKind::newton
             ? std::min(2 * (s.sweeps_between_rounds + 1), SolveReport::kHistory)
             : 2;
}

void validate(const SolverSettings& s) {
  auto bad = [](const std::string& what) { throw UsageError("engine settings: " + what); };
  if (!(s.tolerance > 0.0)) bad("tolerance must be > 0");
  if (s.max_sweeps < 1) bad("the sweep cap must be >= 1");
  if (s.check_every < 1) bad("the sweeps between convergence checks must be >= 1");
  if (s.krylov_after < 1 || s.sweeps_between_rounds < 1)
    bad("the sweeps before and between gradient rounds must be >= 1");
  if (s.newton_after < 0) bad("the sweeps before the Newton steps must be >= 0");
  if (s.finish_after < 0) bad("the sweeps before the active-set finish must be >= 0");
  if (s.strips < 0 || s.strips > max_strips)
    bad("strips must be in [0, " + std::to_string(max_strips) + "], got " +
        std::to_string(s.strips));
  if (s.threads < 1 || s.threads > max_threads)
    bad("threads must be in [1, " + std::to_string(max_threads) + "], got " +
        std::to_string(s.threads));
  // Not bad(): the message names the two fields a user sets.
  if (s.threads > 1 && s.sweep_order == SweepOrder::pair)
    throw UsageError(field("threads") + " " + std::to_string(s.threads) +
                     ": more than one thread needs " + field("sweep_order") +
                     " strips (pair order is sequential; docs/method.md, \"Threads\")");
}

namespace {

/// A solver whose steps not converged after finish_after sweeps are finished by the
/// active-set Newton (docs/method.md, "Finishing a step by its active set"): the solver
/// to finish_after, the Newton from its impulses (kept only if it meets the law's
/// residual, half the tolerance, as ADMM's), then the solver again from the impulses
/// kept, so that its sweeps check the criterion as in every step. A Newton that fails is
/// tried again from the solver's impulses at 2, 4, 8 ... times finish_after, nearer the
/// solution each time, until the cap.
class FinishedSolver final : public ContactSolver {
 public:
  explicit FinishedSolver(const SolverSettings& s) : settings_(s) {}
  SolverKind kind() const override { return settings_.solver; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override {
    ActiveSetOptions o;
    o.tolerance = 0.5 * settings_.tolerance;
    o.velocity_floor = gravity_velocity;
    o.cancel = system.cancel;
    int done = 0;
    bool finished = false;
    std::optional<DelassusProblem> problem;
    for (long next = settings_.finish_after;; next *= 2) {
      SolverSettings part = settings_;
      part.finish_after = 0;
      part.max_sweeps = static_cast<int>(std::min<long>(next, settings_.max_sweeps)) - done;
      SolveReport report = make_solver(part)->solve(system, gravity_velocity);
      done += report.sweeps;
      if (report.converged || done >= settings_.max_sweeps) {
        report.sweeps = done;
        report.finished = finished;
        return report;
      }
      // The problem does not depend on the impulses (q is the bodies' velocities less W R):
      // assembled once for every retry of the step.
      if (!problem) problem = delassus_problem(system);
      Eigen::VectorXd r = row_impulses(system);
      if (solve_active_set(*problem, r, o).converged) {
        set_row_impulses(system, r);
        finished = true;
      }
    }
  }

 private:
  SolverSettings settings_;
};

}  // namespace

std::shared_ptr<const ContactSolver> make_solver(const SolverSettings& s) {
  validate(s);
  if (s.finish_after > 0 && s.finish_after < s.max_sweeps)
    return std::make_shared<const FinishedSolver>(s);
  switch (s.solver) {
    case SolverKind::nsgs: return std::make_shared<const NsgsSolver>(s);
    case SolverKind::nncg: return std::make_shared<const NncgSolver>(s);
    case SolverKind::pcg: return std::make_shared<const PcgSolver>(s);
    case SolverKind::newton: return std::make_shared<const NewtonSolver>(s);
    case SolverKind::admm: return std::make_shared<const AdmmSolver>(s);
  }
  throw UsageError("unknown contact solver");
}

LawResidual law_residual(const ContactSystem& s, double velocity_scale) {
  // Each contact's violation on the team's threads (-1: open and staying open, no
  // violation; a negative normal impulse is one), then summed in row order: the same bits
  // on any team.
  std::vector<double> violation(s.rows.size());
  for_each_range(s.rows.size(), s.team, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const ContactRow& r = s.rows[k];
      double b_n, b_t;
      s.free_local_velocity(r, b_n, b_t);
      const LocalImpulse l = local_solve_diagonal(r.w_nn, r.w_tt, r.mu, b_n, b_t);
      violation[k] = r.rn == 0.0 && !(l.rn > 0.0)
                         ? -1.0
                         : std::max(std::abs(r.w_nn * (l.rn - r.rn)), std::abs(r.w_tt * (l.rt - r.rt)));
    }
  });
  LawResidual out;
  double square_sum = 0.0;
  int counted = 0;
  for (const double e : violation) {
    if (e < 0.0) continue;
    out.max = std::max(out.max, e);
    square_sum += e * e;
    ++counted;
  }
  const double unit = velocity_scale > 0.0 ? velocity_scale : 1.0;
  out.max /= unit;
  out.rms = counted > 0 ? std::sqrt(square_sum / counted) / unit : 0.0;
  return out;
}

}  // namespace cdpile::cd
