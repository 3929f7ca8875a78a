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
/// contact network: one sparse LU (KLU, SuiteSparse) of J gives the exact step.
#pragma once

#include "cdpile/cd/contact_system.hpp"

#include <cstdint>
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

/// Moves the face's impulses by the exact solution x of A x = residual (the minus law's
/// velocities u' of the face, per FaceRow) and the bodies' velocities with them
/// (v += M^-1 G^T x). Needs compliant contacts (C > 0). Returns false, moving nothing,
/// when J could not be factorised.
bool newton_face_step(ContactSystem& s, const std::vector<FaceRow>& face,
                      const std::vector<FaceValue>& residual);

}  // namespace cdpile::cd
