/// The Newton step of the active face (docs/method.md, "The newton solver"): the exact
/// solution of the step's problem with the statuses held, a sliding contact's friction
/// following its normal impulse.
///
/// With the statuses of the contacts fixed, the law is linear: an open contact carries
/// nothing; a sticking one has both components free, u'_n = 0 and u'_t = 0; a sliding one
/// has R_t = s mu R_n (s the sign of its R_t) and u'_n = 0. The face's unknowns x (the
/// changes of the free components) then solve A x = -u', with A = C + H M^-1 G^T: H maps
/// the grains' velocities to the measured components (n, and t when sticking), G the
/// impulses' directions (n, t, or n + s mu t for a sliding contact) and C the
/// compliances 1/(k h^2). A is not symmetric when a contact slides. By Woodbury's identity
///     A^-1 = C^-1 - C^-1 H J^-1 G^T C^-1,   J = M + G^T C^-1 H,
/// J having three unknowns per free grain (x, y, rotation) and the sparsity of the
/// contact network: one sparse LU (KLU, SuiteSparse) of J gives the exact step, and
/// preconditions GMRES on the faces that follow it in the time step.
#pragma once

#include "cdpile/cd/contact_system.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace cdpile::cd {

/// A contact of the face: its row in the system, and whether it sticks (both components
/// free) or slides (the normal one free, R_t = s mu R_n).
struct FaceRow {
  std::uint32_t row;
  bool t;  ///< sticking: the tangential component is free too
};

/// A value per face contact: its normal and tangential components.
struct FaceValue {
  double n = 0.0, t = 0.0;
};

/// The factor of J that a time step's Newton steps share. Between two Newton steps of a
/// step, J changes by the rows whose status the projection changed (a few of thousands)
/// and by nothing else, so the factor of the step's first J, through Woodbury's identity
/// with the face's own H and G, is a preconditioner under which GMRES solves a later face
/// in a few iterations (at most r + 1 for r changed components). The factor is made anew
/// when the iterations spent beyond one per solve exceed a refactorisation's cost, or a
/// solve does not converge in krylov_budget; and at the first Newton step of every time
/// step (ContactSystem::step), so that a step's solution does not depend on the steps
/// before it. The ordering of J (its pattern's) is kept while the face keeps its contacts.
class FaceFactor {
 public:
  /// GMRES iterations a solve takes with a kept factor before the factor is made anew.
  static constexpr int krylov_budget = 10;
  /// A refactorisation costs about as much as this many solves with the factor (17 ms
  /// against 1.9 at 4000 grains, docs/performance.md): once the iterations beyond one
  /// per solve since the factor was made exceed it, the next solve makes a new factor.
  static constexpr int refactor_cost = 8;

  FaceFactor();
  ~FaceFactor();
  FaceFactor(FaceFactor&&) noexcept;
  FaceFactor& operator=(FaceFactor&&) noexcept;

  /// What the factor did so far: numeric factorisations (new or refactorisations),
  /// solves (newton_face_step calls) and GMRES iterations (each one solve with J).
  struct Counts {
    long factorisations = 0, solves = 0, iterations = 0;
  };
  const Counts& counts() const;

 private:
  friend bool newton_face_step(ContactSystem&, const std::vector<FaceRow>&,
                               const std::vector<FaceValue>&, FaceFactor&, double);
  struct Kept;
  std::unique_ptr<Kept> kept_;
};

/// Moves the face's impulses by the solution x of A x = residual (the minus law's
/// velocities u' of the face, per FaceRow) and the bodies' velocities with them
/// (v += M^-1 G^T x), x such that ||residual - A x||_2 <= target: GMRES preconditioned
/// by the step's factor of J, made from this face's J when the step has none (then the
/// first iteration is the exact solve). Needs compliant contacts (C > 0). Returns false,
/// moving nothing, when J could not be factorised.
bool newton_face_step(ContactSystem& s, const std::vector<FaceRow>& face,
                      const std::vector<FaceValue>& residual, FaceFactor& factor,
                      double target);

}  // namespace cdpile::cd
