// The Newton step of the active face through Woodbury's identity: GMRES preconditioned by
// a kept sparse LU of the grains' J (face_newton.hpp; docs/method.md, "The newton solver").
#include "cdpile/cd/face_newton.hpp"

#include "cdpile/check.hpp"

#include <Eigen/Core>
#include <klu.h>

#include <algorithm>

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

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

/// The pattern of J over a face: a 3 x 3 block (x, y, rotation) for each body that moves
/// and for each pair of moving bodies that a face contact joins, in compressed columns.
/// It holds whatever the statuses of the face's contacts, so one ordering and one pivot
/// sequence serve every J of the same contacts: a new factor of a later J is a numeric
/// refactorisation (klu_refactor) while the face keeps its contacts. (The pattern of all
/// the step's candidate contacts would hold longer, but its extra pairs cost fill in every
/// solve: 1.5 times the CPU of the face's pattern in a quiet window of the paper pile.)
class GrainPattern {
 public:
  GrainPattern() = default;
  GrainPattern(const std::vector<Component>& comps, std::int32_t unknowns) {
    const std::size_t blocks = static_cast<std::size_t>(unknowns / 3);
    std::vector<std::vector<std::int32_t>> near(blocks);
    for (std::size_t b = 0; b < blocks; ++b) near[b].push_back(static_cast<std::int32_t>(b));
    for (const Component& c : comps) {
      const std::int32_t di = c.dof_i, dj = c.dof_j;
      if (di < 0 || dj < 0 || c.tangential) continue;  // a contact's pairs: from its normal
      near[static_cast<std::size_t>(di / 3)].push_back(dj / 3);
      near[static_cast<std::size_t>(dj / 3)].push_back(di / 3);
    }
    near_start_.push_back(0);
    for (auto& n : near) {
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
      near_.insert(near_.end(), n.begin(), n.end());
      near_start_.push_back(static_cast<std::int32_t>(near_.size()));
    }
    column_start_.push_back(0);
    for (std::size_t q = 0; q < blocks; ++q)
      for (int y = 0; y < 3; ++y) {
        for (std::int32_t k = near_start_[q]; k < near_start_[q + 1]; ++k)
          for (std::int32_t x = 0; x < 3; ++x) row_index_.push_back(3 * near_[static_cast<std::size_t>(k)] + x);
        column_start_.push_back(static_cast<std::int32_t>(row_index_.size()));
      }
  }
  bool operator==(const GrainPattern& o) const { return near_ == o.near_ && near_start_ == o.near_start_; }
  std::int32_t size() const { return static_cast<std::int32_t>(column_start_.size()) - 1; }
  std::size_t entries() const { return row_index_.size(); }
  std::int32_t* column_start() { return column_start_.data(); }
  std::int32_t* row_index() { return row_index_.data(); }
  /// The entry of J at (first unknown of block p + x, first unknown of block q + y).
  std::size_t at(std::int32_t p, std::int32_t q, int x, int y) const {
    const auto first = near_.begin() + near_start_[static_cast<std::size_t>(q)];
    const auto last = near_.begin() + near_start_[static_cast<std::size_t>(q) + 1];
    const auto rank = std::lower_bound(first, last, p) - first;
    CDPILE_DEBUG_CHECK(first + rank != last && first[rank] == p, "a block outside J's pattern");
    return static_cast<std::size_t>(column_start_[static_cast<std::size_t>(3 * q + y)] + 3 * rank + x);
  }

 private:
  std::vector<std::int32_t> near_start_, near_;  // per block, the blocks it meets, sorted
  std::vector<std::int32_t> column_start_, row_index_;
};

/// J = M + G^T C^-1 H over the bodies' unknowns, in `pattern`.
std::vector<double> grain_matrix(const std::vector<Body>& bodies,
                                 const std::vector<std::int32_t>& dof, const GrainPattern& pattern,
                                 const std::vector<Component>& comps) {
  std::vector<double> j(pattern.entries(), 0.0);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (dof[b] < 0) continue;
    const std::int32_t p = dof[b] / 3;
    j[pattern.at(p, p, 0, 0)] = j[pattern.at(p, p, 1, 1)] = 1.0 / bodies[b].inv_m;
    j[pattern.at(p, p, 2, 2)] = 1.0 / bodies[b].inv_i;
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
            j[pattern.at(base[p] / 3, base[q] / 3, x, y)] += g[p][x] * h[q][y] / c.compliance;
      }
  }
  return j;
}

/// A sparse LU of J by KLU (SuiteSparse): the ordering made once per pattern (a function
/// of the pattern alone), then a numeric factorisation with its own pivots, or a
/// refactorisation with the pivots of the last one.
class GrainFactor {
 public:
  GrainFactor() { klu_defaults(&common_); }
  ~GrainFactor() { release(); }
  GrainFactor(const GrainFactor&) = delete;
  GrainFactor& operator=(const GrainFactor&) = delete;

  bool valid() const { return numeric_ != nullptr; }
  /// Factorises j (in `pattern`), with the last ordering when the pattern is the last
  /// one's and, when `same_pivots`, the last pivots; false when J is singular to KLU.
  bool factorise(GrainPattern pattern, std::vector<double> j, bool same_pivots) {
    if (pattern == pattern_ && symbolic_) {
      if (same_pivots && numeric_ &&
          klu_refactor(pattern_.column_start(), pattern_.row_index(), j.data(), symbolic_,
                       numeric_, &common_))
        return true;
      if (numeric_) klu_free_numeric(&numeric_, &common_);
    } else {
      release();
      pattern_ = std::move(pattern);
      symbolic_ = klu_analyze(pattern_.size(), pattern_.column_start(), pattern_.row_index(), &common_);
      if (!symbolic_) return false;
    }
    numeric_ = klu_factor(pattern_.column_start(), pattern_.row_index(), j.data(), symbolic_, &common_);
    return valid();
  }
  std::int32_t size() const { return pattern_.size(); }
  /// b := J^-1 b.
  void solve(Eigen::VectorXd& b) { klu_solve(symbolic_, numeric_, size(), 1, b.data(), &common_); }

 private:
  void release() {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
  }
  klu_common common_;
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
  GrainPattern pattern_;
};

/// The face's operator A = C + H M^-1 G^T and its preconditioner over the face's
/// components, applied without forming A.
class FaceOperator {
 public:
  FaceOperator(const std::vector<Body>& bodies, std::vector<Component> comps,
               const std::vector<std::int32_t>& dof, std::int32_t unknowns)
      : comps_(std::move(comps)), inverse_mass_(unknowns), grains_(unknowns) {
    for (std::size_t b = 0; b < bodies.size(); ++b)
      if (dof[b] >= 0) {
        inverse_mass_[dof[b]] = inverse_mass_[dof[b] + 1] = bodies[b].inv_m;
        inverse_mass_[dof[b] + 2] = bodies[b].inv_i;
      }
  }
  std::size_t size() const { return comps_.size(); }
  const std::vector<Component>& components() const { return comps_; }

  /// out = A v = C v + H M^-1 G^T v.
  void apply(Eigen::Ref<const Eigen::VectorXd> v, Eigen::Ref<Eigen::VectorXd> out) {
    g_transpose(v, false, grains_);
    grains_.array() *= inverse_mass_.array();
    for (std::size_t q = 0; q < comps_.size(); ++q)
      out[q] = comps_[q].compliance * v[q] + h_dot(comps_[q], grains_);
  }

  /// z = A'^-1 r by Woodbury's identity, A'^-1 = C^-1 - C^-1 H J'^-1 G^T C^-1, with
  /// this face's H, G, C and the kept factor of J': the exact A^-1 when J' is this
  /// face's J.
  void precondition(GrainFactor& lu, Eigen::Ref<const Eigen::VectorXd> r, Eigen::Ref<Eigen::VectorXd> z) {
    g_transpose(r, true, grains_);
    lu.solve(grains_);
    for (std::size_t q = 0; q < comps_.size(); ++q)
      z[q] = (r[q] - h_dot(comps_[q], grains_)) / comps_[q].compliance;
  }

 private:
  /// out = G^T y over the unknowns; G^T C^-1 y when `scaled`.
  void g_transpose(Eigen::Ref<const Eigen::VectorXd> y, bool scaled, Eigen::VectorXd& out) const {
    out.setZero();
    for (std::size_t q = 0; q < comps_.size(); ++q) {
      const Component& c = comps_[q];
      const double yq = scaled ? y[q] / c.compliance : y[q];
      for (int a = 0; a < 3; ++a) {
        if (c.dof_i >= 0) out[c.dof_i + a] += yq * c.g_i[a];
        if (c.dof_j >= 0) out[c.dof_j + a] += yq * c.g_j[a];
      }
    }
  }
  static double h_dot(const Component& c, const Eigen::VectorXd& w) {
    double hw = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (c.dof_i >= 0) hw += c.h_i[a] * w[c.dof_i + a];
      if (c.dof_j >= 0) hw += c.h_j[a] * w[c.dof_j + a];
    }
    return hw;
  }

  std::vector<Component> comps_;
  Eigen::VectorXd inverse_mass_;
  Eigen::VectorXd grains_;  // scratch over the unknowns
};

struct KrylovResult {
  int iterations = 0;
  bool converged = false;
};

/// The memory of GMRES's bases, kept from one solve to the next (a face's size changes
/// from one solve to the next; its memory rarely needs to grow).
struct KrylovSpace {
  std::vector<double> memory;
  /// The bases v (n x budget + 1) and z (n x budget).
  std::pair<Eigen::Map<Eigen::MatrixXd>, Eigen::Map<Eigen::MatrixXd>> bases(Eigen::Index n, int budget) {
    const auto size = static_cast<std::size_t>(n) * static_cast<std::size_t>(2 * budget + 1);
    if (memory.size() < size) memory.resize(size);
    return {Eigen::Map<Eigen::MatrixXd>(memory.data(), n, budget + 1),
            Eigen::Map<Eigen::MatrixXd>(memory.data() + n * (budget + 1), n, budget)};
  }
};

/// GMRES for A x = b from x = 0, right-preconditioned (A P y = b, x = P y), at most
/// `budget` iterations without restart, until ||b - A x||_2 <= tol (Saad, Iterative
/// Methods for Sparse Linear Systems, 2nd ed., Algorithm 9.5; the least-squares problem
/// by Givens rotations). With P = A^-1 it converges in one iteration; with P the inverse
/// of a matrix that differs from A by rank r, in at most r + 1.
template <class Apply, class Precondition>
KrylovResult gmres(const Apply& apply, const Precondition& precondition, const Eigen::VectorXd& b,
                   Eigen::VectorXd& x, double tol, int budget, KrylovSpace& space) {
  const Eigen::Index n = b.size();
  x = Eigen::VectorXd::Zero(n);
  const double beta = b.norm();
  if (beta <= tol) return {0, true};
  auto [v, z] = space.bases(n, budget);
  Eigen::VectorXd w(n);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(budget + 1, budget);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(budget + 1), cs(budget), sn(budget);
  v.col(0) = b / beta;
  g[0] = beta;
  int k = 0;
  while (k < budget) {
    const int j = k++;
    precondition(v.col(j), z.col(j));
    apply(z.col(j), w);
    for (int i = 0; i <= j; ++i) {  // modified Gram-Schmidt
      h(i, j) = w.dot(v.col(i));
      w -= h(i, j) * v.col(i);
    }
    h(j + 1, j) = w.norm();
    const bool breakdown = !(h(j + 1, j) > 0.0);  // the exact solution is in the space
    if (!breakdown) v.col(j + 1) = w / h(j + 1, j);
    for (int i = 0; i < j; ++i) {
      const double t = cs[i] * h(i, j) + sn[i] * h(i + 1, j);
      h(i + 1, j) = -sn[i] * h(i, j) + cs[i] * h(i + 1, j);
      h(i, j) = t;
    }
    const double r = std::hypot(h(j, j), h(j + 1, j));
    cs[j] = h(j, j) / r;
    sn[j] = h(j + 1, j) / r;
    h(j, j) = r;
    h(j + 1, j) = 0.0;
    g[j + 1] = -sn[j] * g[j];
    g[j] = cs[j] * g[j];
    if (breakdown || std::abs(g[j + 1]) <= tol) break;
  }
  const Eigen::VectorXd y = h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
  x = z.leftCols(k) * y;
  return {k, std::abs(g[k]) <= tol};
}

}  // namespace

struct FaceFactor::Kept {
  GrainFactor lu;
  std::int64_t step = -1;        ///< the time step whose faces the numeric factor serves
  std::size_t bodies = 0;        ///< the bodies it was made with
  long extra_iterations = 0;     ///< GMRES iterations beyond one per solve since it was made
  Counts counts;
  KrylovSpace space;
};

FaceFactor::FaceFactor() : kept_(std::make_unique<Kept>()) {}
FaceFactor::~FaceFactor() = default;
FaceFactor::FaceFactor(FaceFactor&&) noexcept = default;
FaceFactor& FaceFactor::operator=(FaceFactor&&) noexcept = default;
const FaceFactor::Counts& FaceFactor::counts() const { return kept_->counts; }

bool newton_face_step(ContactSystem& s, const std::vector<FaceRow>& face,
                      const std::vector<FaceValue>& residual, FaceFactor& factor,
                      double target) {
  CDPILE_DEBUG_CHECK(s.compliance_n > 0.0 && s.compliance_t > 0.0,
               "the face's Newton step needs compliant contacts");
  CDPILE_DEBUG_CHECK(residual.size() == face.size(), "one residual per face contact");
  std::int32_t unknowns = 0;
  const std::vector<std::int32_t> dof = unknowns_of_bodies(s.bodies, unknowns);
  FaceOperator a(s.bodies, face_components(s, face, dof), dof, unknowns);
  if (unknowns == 0 || a.size() == 0) return false;
  FaceFactor::Kept& kept = *factor.kept_;
  // A new factor of this face's J: within the step, with the step's pivots.
  auto factorise = [&] {
    const bool same_step = kept.lu.valid() && kept.step == s.step && kept.bodies == s.bodies.size();
    GrainPattern pattern(a.components(), unknowns);
    std::vector<double> j = grain_matrix(s.bodies, dof, pattern, a.components());
    kept.step = s.step;
    kept.bodies = s.bodies.size();
    kept.extra_iterations = 0;
    ++kept.counts.factorisations;
    return kept.lu.factorise(std::move(pattern), std::move(j), same_step);
  };
  const bool fresh = !kept.lu.valid() || kept.step != s.step || kept.bodies != s.bodies.size() ||
                     kept.lu.size() != unknowns ||
                     kept.extra_iterations > FaceFactor::refactor_cost;
  if (fresh && !factorise()) return false;

  Eigen::VectorXd b(static_cast<Eigen::Index>(a.size())), x;
  for (std::size_t q = 0; q < a.size(); ++q) {
    const Component& c = a.components()[q];
    b[q] = c.tangential ? residual[c.face].t : residual[c.face].n;
  }
  auto apply = [&](Eigen::Ref<const Eigen::VectorXd> v, Eigen::Ref<Eigen::VectorXd> out) {
    a.apply(v, out);
  };
  auto precondition = [&](Eigen::Ref<const Eigen::VectorXd> r, Eigen::Ref<Eigen::VectorXd> z) {
    a.precondition(kept.lu, r, z);
  };
  KrylovResult k = gmres(apply, precondition, b, x, target, FaceFactor::krylov_budget, kept.space);
  ++kept.counts.solves;
  kept.counts.iterations += k.iterations;
  if (!k.converged && !fresh) {  // the factor is too far from this face's J
    if (!factorise()) return false;
    k = gmres(apply, precondition, b, x, target, FaceFactor::krylov_budget, kept.space);
    kept.counts.iterations += k.iterations;
  }
  kept.extra_iterations += std::max(0, k.iterations - 1);
  if (!x.allFinite()) return false;
  for (std::size_t q = 0; q < a.size(); ++q) {
    const Component& c = a.components()[q];
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
