// The Newton step of the active face through Woodbury's identity and a sparse LU of the
// grains' J (face_newton.hpp; docs/method.md, "The newton solver").
#include "cdpile/cd/face_newton.hpp"

#include "cdpile/check.hpp"

#include <Eigen/KLUSupport>
#include <Eigen/SparseCore>

#include <cstddef>

namespace cdpile::cd {

namespace {

/// One measured component of a face contact: the row h of H (the velocity it measures)
/// and the row g of G (the direction its impulse acts in), three coefficients on each
/// of the two grains' unknowns (x, y, rotation); `dof` -1 for a body that does not move.
struct Component {
  std::int32_t dof_i, dof_j;
  double h_i[3], h_j[3], g_i[3], g_j[3];
  double compliance;  ///< c = 1/(k h^2) of the component [1/kg per m]
  std::size_t face;   ///< its contact's index in the face
  bool tangential;
  double friction;    ///< s mu of a sliding contact's normal component, else 0
};

/// The first unknown of each body that moves, -1 for the others; `count` the unknowns.
std::vector<std::int32_t> unknowns_of_bodies(const std::vector<Body>& bodies, std::int32_t& count) {
  std::vector<std::int32_t> dof(bodies.size(), -1);
  count = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (moves(bodies[b])) {
      dof[b] = count;
      count += 3;
    }
  return dof;
}

/// The face's components. With t = (-n_y, n_x), the normal velocity of a contact is
/// n . (v_i - v_j) and the tangential one t . (v_i - v_j) - r_i w_i - r_j w_j (the
/// relative velocity of contact_system.hpp); an impulse acts along the same rows.
std::vector<Component> face_components(const ContactSystem& s, const std::vector<FaceRow>& face,
                                       const std::vector<std::int32_t>& dof) {
  std::vector<Component> out;
  out.reserve(2 * face.size());
  for (std::size_t k = 0; k < face.size(); ++k) {
    const ContactRow& r = s.rows[face[k].row];
    const std::int32_t di = dof[static_cast<std::size_t>(r.bi)];
    const std::int32_t dj = dof[static_cast<std::size_t>(r.bj)];
    const double tx = -r.ny, ty = r.nx;
    // A sliding contact's impulse is R_n (n + s mu t): its friction follows R_n.
    const double sm = face[k].t ? 0.0 : (r.rt >= 0.0 ? r.mu : -r.mu);
    out.push_back({di, dj, {r.nx, r.ny, 0.0}, {-r.nx, -r.ny, 0.0},
                   {r.nx + sm * tx, r.ny + sm * ty, -sm * r.ri},
                   {-(r.nx + sm * tx), -(r.ny + sm * ty), -sm * r.rj},
                   s.compliance_n, k, false, sm});
    if (face[k].t)
      out.push_back({di, dj, {tx, ty, -r.ri}, {-tx, -ty, -r.rj}, {tx, ty, -r.ri},
                     {-tx, -ty, -r.rj}, s.compliance_t, k, true, 0.0});
  }
  return out;
}

/// J = M + G^T C^-1 H over the bodies' unknowns.
Eigen::SparseMatrix<double> grain_matrix(const std::vector<Body>& bodies,
                                         const std::vector<std::int32_t>& dof,
                                         std::int32_t unknowns,
                                         const std::vector<Component>& comps) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * bodies.size() + 36 * comps.size());
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (dof[b] < 0) continue;
    const double m = 1.0 / bodies[b].inv_m, i = 1.0 / bodies[b].inv_i;
    entries.emplace_back(dof[b], dof[b], m);
    entries.emplace_back(dof[b] + 1, dof[b] + 1, m);
    entries.emplace_back(dof[b] + 2, dof[b] + 2, i);
  }
  for (const Component& c : comps) {
    const std::int32_t base[2] = {c.dof_i, c.dof_j};
    const double* g[2] = {c.g_i, c.g_j};
    const double* h[2] = {c.h_i, c.h_j};
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q) {
        if (base[p] < 0 || base[q] < 0) continue;
        for (int x = 0; x < 3; ++x)
          for (int y = 0; y < 3; ++y)
            if (g[p][x] != 0.0 && h[q][y] != 0.0)
              entries.emplace_back(base[p] + x, base[q] + y, g[p][x] * h[q][y] / c.compliance);
      }
  }
  Eigen::SparseMatrix<double> j(unknowns, unknowns);
  j.setFromTriplets(entries.begin(), entries.end());
  j.makeCompressed();
  return j;
}

}  // namespace

bool newton_face_step(ContactSystem& s, const std::vector<FaceRow>& face,
                      const std::vector<FaceValue>& residual) {
  CDPILE_DEBUG_CHECK(s.compliance_n > 0.0 && s.compliance_t > 0.0,
               "the face's Newton step needs compliant contacts");
  CDPILE_DEBUG_CHECK(residual.size() == face.size(), "one residual per face contact");
  std::int32_t unknowns = 0;
  const std::vector<std::int32_t> dof = unknowns_of_bodies(s.bodies, unknowns);
  const std::vector<Component> comps = face_components(s, face, dof);
  if (unknowns == 0 || comps.empty()) return false;
  Eigen::KLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(grain_matrix(s.bodies, dof, unknowns, comps));
  if (lu.info() != Eigen::Success) return false;

  // x = A^-1 res = y - C^-1 H J^-1 G^T y with y = C^-1 res.
  std::vector<double> x(comps.size());
  Eigen::VectorXd gty = Eigen::VectorXd::Zero(unknowns);
  for (std::size_t q = 0; q < comps.size(); ++q) {
    const Component& c = comps[q];
    const FaceValue& res = residual[c.face];
    x[q] = (c.tangential ? res.t : res.n) / c.compliance;
    for (int a = 0; a < 3; ++a) {
      if (c.dof_i >= 0) gty[c.dof_i + a] += x[q] * c.g_i[a];
      if (c.dof_j >= 0) gty[c.dof_j + a] += x[q] * c.g_j[a];
    }
  }
  const Eigen::VectorXd w = lu.solve(gty);
  if (lu.info() != Eigen::Success || !w.allFinite()) return false;
  for (std::size_t q = 0; q < comps.size(); ++q) {
    const Component& c = comps[q];
    double hw = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (c.dof_i >= 0) hw += c.h_i[a] * w[c.dof_i + a];
      if (c.dof_j >= 0) hw += c.h_j[a] * w[c.dof_j + a];
    }
    x[q] -= hw / c.compliance;
  }
  for (std::size_t q = 0; q < comps.size(); ++q) {
    const Component& c = comps[q];
    ContactRow& r = s.rows[face[c.face].row];
    const double dn = c.tangential ? 0.0 : x[q];
    const double dt = c.tangential ? x[q] : c.friction * x[q];
    s.apply_impulse(r, dn, dt);
    r.rn += dn;
    r.rt += dt;
  }
  return true;
}

}  // namespace cdpile::cd
