/// Non-smooth Gauss-Seidel over a ContactSystem (docs/method.md, "The scheme", step 6):
/// contact after contact, the exact 2D local solve (local_solver.hpp) with the others
/// frozen, the bodies' velocities updated at once (the ELG layout of LMGC90: each
/// contact's local velocity is read from its two bodies in O(1)).
#pragma once

#include "cdpile/cd/solver.hpp"

namespace cdpile::cd {

/// The sums one sweep leaves for the convergence measures (SolveReport).
struct SweepSums {
  double largest = 0.0;     ///< max_a |W_aa dR_a|
  double square_sum = 0.0;  ///< sum over active contacts of the same, squared
  double scale_sum = 0.0;   ///< sum over active contacts of W_nn R_n
  int active = 0;           ///< contacts with R_n > 0 after the sweep
};

/// One sweep over the rows, forward or backward.
SweepSums nsgs_sweep(ContactSystem& s, bool backward);

class NsgsSolver final : public ContactSolver {
 public:
  explicit NsgsSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::nsgs; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  bool converged(const SolveReport& r, const ContactSystem& s, double gravity_velocity) const;
  SolverSettings settings_;
};

}  // namespace cdpile::cd
