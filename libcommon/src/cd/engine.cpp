// The Contact Dynamics engine: one Moreau-Jean step as named stages (engine.hpp).
#include "cdpile/cd/engine.hpp"

#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/local_solver.hpp"
#include "cdpile/cd/schedule.hpp"
#include "cdpile/check.hpp"
#include "cdpile/error.hpp"

#include <Eigen/SparseCore>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace cdpile::cd {

namespace {

using Clock = std::chrono::steady_clock;

/// Adds the seconds since `start` to `acc` and restarts the stopwatch.
void lap(Clock::time_point& start, double& acc) {
  const auto now = Clock::now();
  acc += std::chrono::duration<double>(now - start).count();
  start = now;
}

bool is_fixed(const Grains& g, std::size_t i) { return g.species[i] == Species::floor; }

// The dashpot's eta = 2 zeta sqrt(k m / 2) (docs/method.md, "The contact dashpot"): zeta is
// the damping ratio of a contact between two grains of the free grains' mean mass m
// (reduced mass m / 2); all grains' when none is free.
double dashpot(const Grains& g, const TimeStepping& s) {
  double mass = 0.0, all = 0.0;
  std::size_t free = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    all += g.mass[i];
    if (is_fixed(g, i)) continue;
    mass += g.mass[i];
    ++free;
  }
  const double mean = free > 0 ? mass / static_cast<double>(free)
                               : all / static_cast<double>(std::max<std::size_t>(g.size(), 1));
  return 2.0 * s.contact_damping_ratio * std::sqrt(s.contact_stiffness * 0.5 * mean);
}

// With the dashpot, what the next step anchors at is the spring's part of the step's
// impulse R (docs/method.md, "The contact dashpot"): (1 - s) R0 + s R, s = k h / (k h + eta)
// the spring's share of the change, not the dashpot's -eta h u, which lasts one step. A
// sliding contact keeps its normal spring and a tangential part on the cone of it (the
// Cundall-Strack spring clamped by Coulomb); an open one (R = 0) keeps nothing. Both stay
// in the cone: convex combinations of admissible impulses, or a point on its edge.
// The weights s and 1 - s are both given (kept), so that a small dashpot's 1 - s does not
// round away. R0 may lie outside this step's cone (a pile settled with a larger mu): the
// tangential part is then clamped to it.
void spring_part(const ContactRow& r, double s, double kept, double& rn, double& rt) {
  if (!(r.rn > 0.0)) {
    rn = rt = 0.0;
    return;
  }
  rn = kept * r.rn0 + s * r.rn;
  rt = r.status == ContactStatus::slide ? r.rt * (rn / r.rn) : kept * r.rt0 + s * r.rt;
  rt = std::clamp(rt, -r.mu * rn, r.mu * rn);
  CDPILE_DEBUG_CHECK(rn > 0.0, "the spring's part of an impulse is not positive");
}

}  // namespace

void validate(const TimeStepping& s) {
  auto bad = [](const std::string& what) { throw UsageError("engine settings: " + what); };
  if (!(s.time_step > 0.0) || !std::isfinite(s.time_step)) bad("time step must be > 0");
  if (!(s.theta >= 0.5 && s.theta <= 1.0)) bad("theta must be in [0.5, 1]");
  if (!(s.gravity >= 0.0) || !std::isfinite(s.gravity)) bad("gravity must be >= 0");
  if (!(s.mu_grain >= 0.0) || !(s.mu_wall >= 0.0)) bad("friction coefficients must be >= 0");
  if (!(s.alert_distance >= 0.0)) bad("alert distance must be >= 0");
  if (!(s.contact_stiffness >= 0.0) || !std::isfinite(s.contact_stiffness))
    bad("contact stiffness must be >= 0 and finite (0: rigid contacts)");
  if (!(s.contact_damping_ratio >= 0.0) || !std::isfinite(s.contact_damping_ratio))
    bad("contact damping ratio must be >= 0 and finite (0: no dashpot)");
  if (s.contact_damping_ratio > 0.0 && s.contact_stiffness == 0.0)
    bad("a contact damping ratio needs a contact stiffness (a dashpot beside the spring)");
  if (s.max_substeps < 1 || s.max_substeps > max_substeps_limit ||
      (s.max_substeps & (s.max_substeps - 1)) != 0)
    bad("the largest number of sub-steps must be a power of two from 1 to " +
        std::to_string(max_substeps_limit));
  if (s.substep_after < 1) bad("the sweeps before a step is split must be >= 1");
}

void validate(const Settings& s) {
  validate(static_cast<const TimeStepping&>(s));
  validate(static_cast<const SolverSettings&>(s));
}

Engine::Engine(Box box, Grains grains, Settings settings)
    : box_(box), grains_(std::move(grains)), settings_(settings) {
  validate(settings_);
  const std::size_t n = grains_.size();
  if (grains_.mass.size() != n || grains_.inertia.size() != n || grains_.species.size() != n ||
      grains_.position.size() != n || grains_.velocity.size() != n ||
      grains_.orientation.size() != n || grains_.angular_velocity.size() != n)
    throw Error("engine: grain arrays have different sizes");
  if (!(box_.width > 0.0)) throw Error("engine: the box width must be > 0");
  inv_mass_.resize(n);
  inv_inertia_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(grains_.radius[i] > 0.0) || !(grains_.mass[i] > 0.0) || !(grains_.inertia[i] > 0.0))
      throw Error("engine: grain " + std::to_string(i) +
                  " has a non-positive radius, mass or inertia");
    const bool fixed = is_fixed(grains_, i);
    inv_mass_[i] = fixed ? 0.0 : 1.0 / grains_.mass[i];
    inv_inertia_[i] = fixed ? 0.0 : 1.0 / grains_.inertia[i];
    if (fixed) {  // glued grains never move
      grains_.velocity[i] = Vec2::Zero();
      grains_.angular_velocity[i] = 0.0;
    }
  }
  system_.bodies.resize(n + 1);
  system_.bodies[n] = {0.0, 0.0, 0.0, 0.0, 0.0};  // the walls: one static body
  if (settings_.contact_damping_ratio > 0.0) damping_ = dashpot(grains_, settings_);
  set_substep(settings_.time_step);
  stored_h_ = settings_.time_step;
  solver_ = make_solver(settings_);
  SolverSettings budget = settings_;
  budget.max_sweeps = std::min(settings_.max_sweeps, settings_.substep_after);
  budget_solver_ = make_solver(budget);
  if (settings_.threads > 1) {
    team_ = std::make_shared<Team>(settings_.threads);
    system_.team = team_.get();
  }
}

// The (sub)step size of the stages, and the compliance of the force-selection rule
// (docs/method.md, "Force selection"): an implicit spring of stiffness k on the step's
// displacement h u, R - R0 = -k h^2 u; with the dashpot eta beside it (docs/method.md,
// "The contact dashpot"), R - R0 = -(k h^2 + eta h) u, of which the spring's share is
// k h / (k h + eta).
void Engine::set_substep(double h) {
  h_ = h;
  const double k = settings_.contact_stiffness;
  if (k > 0.0) {
    system_.compliance_n = 1.0 / (k * h * h + damping_ * h);
    system_.compliance_t = system_.compliance_n;
    spring_share_ = k * h / (k * h + damping_);
    dashpot_share_ = damping_ / (k * h + damping_);
  }
}

void Engine::lock_rotation(std::size_t grain, bool locked) {
  if (grain >= grains_.size()) throw Error("engine: no grain " + std::to_string(grain));
  inv_inertia_[grain] = (locked || is_fixed(grains_, grain)) ? 0.0 : 1.0 / grains_.inertia[grain];
  if (locked) grains_.angular_velocity[grain] = 0.0;
}

const char* substep_start_name(SubstepStart s) {
  switch (s) {
    case SubstepStart::last: return "last";
    case SubstepStart::h: return "h";
  }
  return "?";
}

SubstepStart substep_start_from_name(const std::string& name) {
  for (const SubstepStart s : {SubstepStart::last, SubstepStart::h})
    if (name == substep_start_name(s)) return s;
  throw UsageError("unknown sub-step start '" + name + "' (last or h)");
}

StepReport Engine::step(double tilt_angle) {
  last_tilt_angle_ = tilt_angle;
  const Vec2 g = tilted_gravity(settings_.gravity, tilt_angle);
  StepReport report;
  report.substeps = 0;
  if (settings_.max_substeps > 1) {
    // A split step changes the grains after its first sub-step: what a cancelled step must
    // leave as it was is kept then (advance), not at every step.
    step_start_.kept = false;
    try {
      // Start at the level the last step ended at (a rearrangement lasts many steps, and
      // each failed attempt costs substep_after sweeps), one level coarser when every
      // sub-step of the last step converged in under a quarter of that; or at h.
      const int parts = settings_.substep_start == SubstepStart::h ? 1 : 1 << substep_level_;
      SubstepTally tally;
      tally.finest = parts;
      for (int k = 0; k < parts; ++k) advance(settings_.time_step / parts, parts, g, report, tally);
      int level = 0;
      while ((1 << level) < tally.finest) ++level;
      if (level > 0 && 4 * tally.hardest_sweeps < settings_.substep_after) --level;
      substep_level_ = level;
    } catch (const StepCancelled&) {
      if (step_start_.kept) {
        grains_ = step_start_.grains;
        stored_keys_ = step_start_.keys;
        stored_rn_ = step_start_.rn;
        stored_rt_ = step_start_.rt;
      }
      stored_h_ = settings_.time_step;
      throw;
    }
    // The stored impulses are the last sub-step's; the state keeps impulses over h.
    if (stored_h_ != settings_.time_step) {
      const double scale = settings_.time_step / stored_h_;
      for (double& v : stored_rn_) v *= scale;
      for (double& v : stored_rt_) v *= scale;
      stored_h_ = settings_.time_step;
    }
  } else {
    SubstepTally tally;
    advance(settings_.time_step, 1, g, report, tally);
  }

  ++step_;
  time_ = static_cast<double>(step_) * settings_.time_step;  // no drift from summing h
  report.step = step_;
  report.time = time_;
  report.tilt_angle = tilt_angle;
  measure(report);
  profile_.steps += 1;
  profile_.substeps += report.substeps;
  return report;
}

// Advances the grains by hs = h / parts, in stages 1-9 (engine.hpp). When sub-steps are
// allowed and the solve has not converged within settings.substep_after sweeps, the
// attempt is dropped (stages 1-6 change neither the grains nor the stored impulses) and
// the interval is done as two halves, each of which may split again, down to
// h / max_substeps, where the sweep cap of the settings applies (docs/method.md,
// "Sub-steps").
void Engine::advance(double hs, int parts, const Vec2& g, StepReport& report, SubstepTally& tally) {
  set_substep(hs);
  auto t = Clock::now();
  detect(g);
  lap(t, profile_.detect);
  compute_frames();
  lap(t, profile_.frames);
  compute_delassus();
  lap(t, profile_.delassus);
  debug_check_rows(system_);  // debug builds: what the warm start's merge relies on
  warm_start();
  lap(t, profile_.warm_start);
  const bool may_split = parts < settings_.max_substeps;
  const SolveReport s = solve(may_split ? *budget_solver_ : *solver_);
  lap(t, profile_.solve);
  report.sweeps += s.sweeps;
  profile_.sweeps += s.sweeps;
  profile_.contact_updates +=
      static_cast<std::int64_t>(s.sweeps) * static_cast<std::int64_t>(system_.rows.size());
  if (!s.converged && may_split) {
    tally.finest = std::max(tally.finest, 2 * parts);
    advance(0.5 * hs, 2 * parts, g, report, tally);
    advance(0.5 * hs, 2 * parts, g, report, tally);
    return;
  }
  tally.hardest_sweeps = std::max(tally.hardest_sweeps, s.sweeps);
  report.finishes += s.finished ? 1 : 0;
  const LawResidual law = law_residual(system_, settings_.gravity * hs);
  report.residual = std::max(report.residual, s.residual);
  report.residual_rms = std::max(report.residual_rms, s.residual_rms);
  report.converged = report.converged && s.converged;
  report.law_residual = std::max(report.law_residual, law.max);
  report.law_residual_rms = std::max(report.law_residual_rms, law.rms);
  report.substeps += 1;
  check_solution();
  // A sub-step that is not the whole step: the step's start is kept before its first one
  // changes the grains (step).
  if (parts > 1 && !step_start_.kept) {
    step_start_.grains = grains_;  // assignments reuse the storage of the last split step
    step_start_.keys = stored_keys_;
    step_start_.rn = stored_rn_;
    step_start_.rt = stored_rt_;
    step_start_.kept = true;
  }
  update_velocities();
  lap(t, profile_.update_velocities);
  update_positions();
  lap(t, profile_.update_positions);
  store_impulses();
  lap(t, profile_.store);
}

// Stage 1 and 2. Free velocities go into the bodies; candidates are found in the
// predicted configuration q_m = q + (1 - theta) h v (docs/method.md, "The scheme") with a cell
// grid. A pair is a candidate when its gap at q_m is below the alert distance plus what
// the two grains can travel in one step, h (|v| + g h) each, so that no contact can be
// missed whatever the speed (the margin is zero for grains at rest).
void Engine::refuse_non_finite_state() const {
  for (std::size_t i = 0; i < grains_.size(); ++i) {
    const Vec2 &x = grains_.position[i], &v = grains_.velocity[i];
    if (std::isfinite(x.x() + x.y()) && std::isfinite(v.norm()) &&
        std::isfinite(grains_.angular_velocity[i]))
      continue;
    char what[240];
    std::snprintf(what, sizeof what,
                  "the state is not finite at tilt %g deg: grain %zu at (%g, %g) m moving at "
                  "(%g, %g) m/s: the run stops",
                  last_tilt_angle_ * 180.0 / M_PI, i, x.x(), x.y(), v.x(), v.y());
    throw Error(what);
  }
  throw Error("the state is not finite (a grain's margin of motion)");
}

void Engine::detect(const Vec2& g) {
  const std::size_t n = grains_.size();
  const double h = h_;
  const double lead = (1.0 - settings_.theta) * h;
  predicted_.resize(n);
  margin_.resize(n);
  velocity_begin_.resize(n);
  omega_begin_.resize(n);
  double r_max = 0.0;
  const double g_norm = g.norm();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& v = grains_.velocity[i];
    velocity_begin_[i] = v;
    omega_begin_[i] = grains_.angular_velocity[i];
    const bool fixed = inv_mass_[i] == 0.0;
    // Free velocity v_free = v + h g (stage 1); a fixed grain has none.
    const Vec2 vf = fixed ? Vec2::Zero() : Vec2(v + h * g);
    system_.bodies[i] = {vf.x(), vf.y(), grains_.angular_velocity[i], inv_mass_[i],
                         inv_inertia_[i]};
    predicted_[i] = grains_.position[i] + lead * v;
    margin_[i] = fixed ? 0.0 : h * (v.norm() + g_norm * h);
    // Detection indexes its cell grid with these: a state that is not finite (from an
    // input's absurd force, a solver's, a parameter at its extreme) stops here, named, not
    // as a wild index (a NaN would pass the grid's min and max unseen).
    if (!std::isfinite(predicted_[i].x() + predicted_[i].y() + margin_[i])) refuse_non_finite_state();
    r_max = std::max(r_max, grains_.radius[i]);
  }
  if (settings_.sweep_order == SweepOrder::strips) assign_strips(r_max);
  // Stage 2: the candidates (cd/detection.hpp)
  detection_.detect({predicted_, grains_.radius, margin_, inv_mass_, box_.width,
                     settings_.alert_distance},
                    system_.rows, team_.get());
}

// Stage 3. Lever arms and the gap term of each contact. The tangent is
// t = (-n_y, n_x); the relative velocity of i with respect to j at the contact is
//   u_n = (v_i - v_j).n,   u_t = (v_i - v_j).t - w_i r_i - w_j r_j
// (the contact point is at -r_i n from i and +r_j n from j).
void Engine::compute_frames() {
  const double inv_h = 1.0 / h_;
  for_each_range(system_.rows.size(), system_.team, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      ContactRow& r = system_.rows[k];
      r.ri = grains_.radius[static_cast<std::size_t>(r.i)];
      r.rj = r.j < 0 ? 0.0 : grains_.radius[static_cast<std::size_t>(r.j)];
      r.mu = (r.j < 0) ? settings_.mu_wall : settings_.mu_grain;
      // LMGC90's IQS_CLB (docs/method.md, "The gap term"): u_n + max(0, gap/h) >= 0. A
      // contact becomes active only if the gap would close within the step; an existing
      // overlap is not pushed out, so no energy is injected (restitution 0).
      r.gap_velocity = std::max(0.0, r.gap * inv_h);
    }
  });
}

// Stage 4. The diagonal blocks of W = H M^-1 H^T, plus the compliances of the
// force-selection rule (zero for rigid contacts). For disks the normal passes through
// both centres, so W_nt = 0 (docs/method.md, "The scheme", step 3).
void Engine::compute_delassus() {
  const bool compliant = system_.compliant();
  for_each_range(system_.rows.size(), system_.team, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      ContactRow& r = system_.rows[k];
      const Body& a = system_.bodies[static_cast<std::size_t>(r.bi)];
      const Body& b = system_.bodies[static_cast<std::size_t>(r.bj)];
      r.w_nn = a.inv_m + b.inv_m;
      r.w_tt = a.inv_m + b.inv_m + r.ri * r.ri * a.inv_i + r.rj * r.rj * b.inv_i;
      if (compliant) {
        r.w_nn += system_.compliance_n;
        r.w_tt += system_.compliance_t;
      }
    }
  });
}

// The vertical strip of each moving grain's predicted centre (SweepOrder::strips,
// schedule.hpp): strips at least 4 r_max wide tile the box, so that a contact's grains lie
// in one strip or two neighbouring ones.
void Engine::assign_strips(double r_max) {
  const std::size_t n = grains_.size();
  const int strips = strip_count(box_.width, r_max, settings_.strips);
  const double width = box_.width / strips;
  system_.strip.assign(n + 1, -1);  // the walls' body: static
  for (std::size_t i = 0; i < n; ++i) {
    if (!moves(system_.bodies[i])) continue;
    const double at = std::floor(predicted_[i].x() / width);
    system_.strip[i] = static_cast<std::int32_t>(std::clamp(at, 0.0, static_cast<double>(strips - 1)));
  }
}

// Stage 5. Impulses of the previous step, matched by pair (both lists are sorted by
// pair_key), then applied to the free velocities: v = v_free + M^-1 H^T R. They are also
// the anchor R0 of the compliance.
void Engine::warm_start() {
#ifndef NDEBUG
  for (std::size_t k = 1; k < stored_keys_.size(); ++k)
    CDPILE_DEBUG_CHECK(stored_keys_[k - 1] < stored_keys_[k],
                       "stored impulse " + std::to_string(k) + " is out of pair order");
#endif
  // Impulses are forces times the step: stored over another (sub)step, they are rescaled
  // to this one (the same forces; docs/method.md, "Sub-steps").
  const double scale = h_ / stored_h_;
  std::size_t k = 0;
  for (ContactRow& r : system_.rows) {
    const std::uint64_t key = pair_key(r.i, r.j);
    while (k < stored_keys_.size() && stored_keys_[k] < key) ++k;
    if (k < stored_keys_.size() && stored_keys_[k] == key) {
      r.rn = stored_rn_[k] * scale;  // exact when scale is 1: x * 1.0 == x
      r.rt = stored_rt_[k] * scale;
    } else {
      r.rn = 0.0;
      r.rt = 0.0;
    }
    r.rn0 = r.rn;
    r.rt0 = r.rt;
    r.status = r.rn > 0.0 ? ContactStatus::stick : ContactStatus::open;
    if (r.rn == 0.0 && r.rt == 0.0) continue;
    system_.apply_impulse(r, r.rn, r.rt);
  }
}

// Stage 6. The settings' solver (NSGS by default) from the warm start; the caller measures
// the contact law's residual the same way whatever the solver and its stopping rule.
SolveReport Engine::solve(const ContactSolver& solver) {
  system_.step = step_ + 1;
  try {
    return solver.solve(system_, settings_.gravity * h_);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + " at step " + std::to_string(step_ + 1));
  }
}

// Invariants of every solver (debug builds; contact_system.hpp): the impulses are
// admissible, and the bodies hold v = v_free + M^-1 H^T R, the velocities the impulses
// make, checked by rebuilding them from the step's start.
void Engine::check_solution() const {
#ifndef NDEBUG
  debug_check_admissible(system_);
  const Vec2 g = tilted_gravity(settings_.gravity, last_tilt_angle_);
  std::vector<Body> free(system_.bodies.size(), Body{0.0, 0.0, 0.0, 0.0, 0.0});
  const double h = h_;
  for (std::size_t i = 0; i < grains_.size(); ++i) {
    const bool fixed = inv_mass_[i] == 0.0;
    const Vec2 vf = fixed ? Vec2::Zero() : Vec2(velocity_begin_[i] + h * g);
    free[i] = {vf.x(), vf.y(), omega_begin_[i], inv_mass_[i], inv_inertia_[i]};
  }
  debug_check_velocities(system_, free, settings_.gravity * h);
#endif
}

// Stage 7. The bodies hold v = v_free + M^-1 H^T R; copy it to the grains.
void Engine::update_velocities() {
  for (std::size_t i = 0; i < grains_.size(); ++i) {
    if (inv_mass_[i] == 0.0) continue;
    const Body& b = system_.bodies[i];
    grains_.velocity[i] = Vec2(b.vx, b.vy);
    grains_.angular_velocity[i] = inv_inertia_[i] == 0.0 ? 0.0 : b.w;
  }
}

// Stage 8. theta-method: q = q + h ((1 - theta) v_begin + theta v) = q_m + theta h v.
void Engine::update_positions() {
  const double h = h_, th = settings_.theta;
  for (std::size_t i = 0; i < grains_.size(); ++i) {
    if (inv_mass_[i] == 0.0) continue;
    grains_.position[i] = predicted_[i] + (th * h) * grains_.velocity[i];
    grains_.orientation[i] += h * ((1.0 - th) * omega_begin_[i] + th * grains_.angular_velocity[i]);
  }
}

// Stage 9. Keep the non-zero impulses (with the dashpot their spring's part: spring_part),
// sorted by pair, for the next warm start. On a team,
// each thread counts and then copies the kept impulses of its range of rows to their place:
// the same list as on one thread.
void Engine::store_impulses() {
  stored_h_ = h_;
  const std::vector<ContactRow>& rows = system_.rows;
  auto kept = [](const ContactRow& r) { return r.rn != 0.0 || r.rt != 0.0; };
  auto keep = [&](std::size_t first, std::size_t last, std::size_t at) {
    for (std::size_t k = first; k < last; ++k) {
      const ContactRow& r = rows[k];
      if (!kept(r)) continue;
      stored_keys_[at] = pair_key(r.i, r.j);
      if (damping_ > 0.0) {
        spring_part(r, spring_share_, dashpot_share_, stored_rn_[at], stored_rt_[at]);
      } else {
        stored_rn_[at] = r.rn;
        stored_rt_[at] = r.rt;
      }
      ++at;
    }
  };
  auto store = [&](std::size_t count) {
    stored_keys_.resize(count);
    stored_rn_.resize(count);
    stored_rt_.resize(count);
  };
  const std::size_t m = rows.size();
  if (!team_ || m < team_->smallest_shared()) {
    store(static_cast<std::size_t>(std::count_if(rows.begin(), rows.end(), kept)));
    keep(0, m, 0);
    return;
  }
  const auto threads = static_cast<std::size_t>(team_->size());
  std::vector<std::size_t> offset(threads + 1, 0);
  team_->run([&](int t) {
    const auto u = static_cast<std::size_t>(t);
    const std::size_t first = m * u / threads, last = m * (u + 1) / threads;
    offset[u + 1] = static_cast<std::size_t>(std::count_if(
        rows.begin() + static_cast<std::ptrdiff_t>(first),
        rows.begin() + static_cast<std::ptrdiff_t>(last), kept));
    team_->barrier();
    if (u == 0) {
      for (std::size_t k = 0; k < threads; ++k) offset[k + 1] += offset[k];
      store(offset[threads]);
    }
    team_->barrier();
    keep(first, last, offset[u]);
  });
}

void Engine::measure(StepReport& report) const {
  report.candidates = static_cast<int>(system_.rows.size());
  std::vector<char> touched(grains_.size(), 0);
  for (const ContactRow& r : system_.rows) {
    report.max_overlap = std::max(report.max_overlap, -r.gap);
    if (!(r.rn > 0.0)) continue;
    ++report.contacts;
    touched[static_cast<std::size_t>(r.i)] = 1;
    if (r.j >= 0) touched[static_cast<std::size_t>(r.j)] = 1;
    if (r.status == ContactStatus::slide) ++report.sliding;
    if (r.j >= 0 && inv_mass_[static_cast<std::size_t>(r.i)] != 0.0 &&
        inv_mass_[static_cast<std::size_t>(r.j)] != 0.0)
      ++report.contacts_grain;
  }
  for (std::size_t i = 0; i < grains_.size(); ++i) {
    if (inv_mass_[i] == 0.0) continue;
    if (!touched[i]) ++report.grains_without_contact;
    const double v2 = grains_.velocity[i].squaredNorm();
    const double w = grains_.angular_velocity[i];
    report.kinetic_energy += 0.5 * grains_.mass[i] * v2;
    report.rotational_energy += 0.5 * grains_.inertia[i] * w * w;
    report.max_speed = std::max(report.max_speed, std::sqrt(v2));
  }
}

Contacts Engine::contacts() const {
  Contacts c;
  c.resize(system_.rows.size());
  const double inv_h = 1.0 / h_;  // the last sub-step's (docs/method.md, "Sub-steps")
  for_each_range(system_.rows.size(), system_.team, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const ContactRow& r = system_.rows[k];
      const Vec2 n(r.nx, r.ny);
      const Vec2& xi = predicted_[static_cast<std::size_t>(r.i)];
      // Contact point: middle of the gap (or overlap) between the two surfaces, on the
      // line of centres; for a wall, the foot of the centre on the wall.
      c.i[k] = r.i;
      c.j[k] = r.j;
      c.point[k] = r.j < 0 ? Vec2(xi - (r.ri + r.gap) * n) : Vec2(xi - (r.ri + 0.5 * r.gap) * n);
      c.normal[k] = n;
      c.fn[k] = r.rn * inv_h;
      c.ft[k] = r.rt * inv_h;
      c.gap[k] = r.gap;
      c.status[k] = r.rn > 0.0 ? r.status : ContactStatus::open;
    }
  });
  return c;
}

// The step's problem in Delassus form, assembled from the contact system (delassus.hpp).
DelassusProblem Engine::delassus_problem() const { return cd::delassus_problem(system_); }

Eigen::VectorXd Engine::local_impulses() const {
  Eigen::VectorXd r(2 * static_cast<Eigen::Index>(system_.rows.size()));
  for (std::size_t a = 0; a < system_.rows.size(); ++a) {
    r[static_cast<Eigen::Index>(2 * a)] = system_.rows[a].rn;
    r[static_cast<Eigen::Index>(2 * a + 1)] = system_.rows[a].rt;
  }
  return r;
}

EngineState Engine::state() const {
  EngineState s;
  s.step = step_;
  s.time = time_;
  s.substep_level = substep_level_;
  s.impulses.reserve(stored_keys_.size());
  for (std::size_t k = 0; k < stored_keys_.size(); ++k) {
    StoredImpulse imp;
    imp.i = static_cast<std::int32_t>(stored_keys_[k] >> 32);
    imp.j = static_cast<std::int32_t>(static_cast<std::uint32_t>(stored_keys_[k]) ^ 0x80000000u);
    imp.rn = stored_rn_[k];
    imp.rt = stored_rt_[k];
    s.impulses.push_back(imp);
  }
  return s;
}

void Engine::set_state(const EngineState& s) {
  step_ = s.step;
  time_ = s.time;
  stored_h_ = settings_.time_step;
  if (s.substep_level < 0 || (1 << std::min(s.substep_level, 30)) > settings_.max_substeps)
    throw Error("engine: sub-step level " + std::to_string(s.substep_level) +
                " is beyond the settings' max_substeps");
  substep_level_ = s.substep_level;
  stored_keys_.clear();
  stored_rn_.clear();
  stored_rt_.clear();
  for (const StoredImpulse& imp : s.impulses) {
    stored_keys_.push_back(pair_key(imp.i, imp.j));
    stored_rn_.push_back(imp.rn);
    stored_rt_.push_back(imp.rt);
  }
  for (std::size_t k = 1; k < stored_keys_.size(); ++k)
    if (!(stored_keys_[k - 1] < stored_keys_[k]))
      throw Error("engine: stored impulses are not sorted by pair");
}

}  // namespace cdpile::cd
