// Newton on the grains' velocities (primal.hpp; docs/method.md, "The primal solver").
#include "cdpile/cd/primal.hpp"

#include "cdpile/cd/pcg.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cdpile::cd {

namespace {

using Vector = Eigen::VectorXd;
using Sparse = Eigen::SparseMatrix<double>;

/// Projection of p on the 2D cone |x_t| <= m x_n and its Jacobian (0, I or e e^T).
struct ConeProjection {
  double qn = 0.0, qt = 0.0;
  double jnn = 0.0, jnt = 0.0, jtt = 0.0;
  int face = 0;  ///< 0 open, 1 inside (sticking), 2 on a face (sliding)
};

ConeProjection project(double pn, double pt, double m) {
  ConeProjection c;
  if (std::abs(pt) <= m * pn) {  // inside
    c.qn = pn;
    c.qt = pt;
    c.jnn = c.jtt = 1.0;
    c.face = 1;
  } else if (m * std::abs(pt) <= -pn) {  // in the polar cone: projects on the apex
    c.face = 0;
  } else {  // on the face e = (1, sign(pt) m) / sqrt(1 + m^2)
    const double sg = pt > 0.0 ? 1.0 : -1.0;
    const double inv = 1.0 / (1.0 + m * m);
    const double en2 = inv, et2 = m * m * inv, ent = sg * m * inv;
    const double dot = pn + sg * m * pt;  // (p.e) sqrt(1 + m^2)
    c.qn = dot * inv;
    c.qt = sg * m * dot * inv;
    c.jnn = en2;
    c.jnt = ent;
    c.jtt = et2;
    c.face = 2;
  }
  return c;
}

/// The problem in the grains' velocities: the moving bodies' unknowns, their masses, the
/// free velocities, and per contact its compliance, anchor and shift.
struct Primal {
  std::vector<int> var;  ///< per body, its first unknown, or -1 (a body that does not move)
  int n = 0;
  Vector mass, v_free;
  /// 1 for an unknown that does not change: a moving body's locked rotation (inv_i = 0).
  Vector locked;
  std::vector<double> cn, ct, an, at, shift;

  /// u = H_a v of row r.
  void local_velocity(const ContactSystem& s, const ContactRow& r, const Vector& v, double& un,
                      double& ut) const {
    double vx = 0, vy = 0, wa = 0, wb = 0;
    if (const int i = var[static_cast<std::size_t>(r.bi)]; i >= 0) {
      vx += v[i];
      vy += v[i + 1];
      wa = v[i + 2];
    }
    if (const int j = var[static_cast<std::size_t>(r.bj)]; j >= 0) {
      vx -= v[j];
      vy -= v[j + 1];
      wb = v[j + 2];
    }
    (void)s;
    un = vx * r.nx + vy * r.ny;
    ut = -vx * r.ny + vy * r.nx - wa * r.ri - wb * r.rj;
  }
};

/// One contact at velocities v: its impulse R, its energy term and its Hessian block.
struct Local {
  double rn, rt, energy;
  double knn, knt, ktt;  ///< C^-1/2 J C^-1/2
  int face;
};

Local local(const Primal& p, std::size_t a, const ContactRow& r, double un, double ut) {
  const double cn = p.cn[a], ct = p.ct[a];
  const double zn = un + r.gap_velocity - cn * p.an[a] + p.shift[a];
  const double zt = ut - ct * p.at[a];
  const double sn = std::sqrt(cn), st = std::sqrt(ct);
  const ConeProjection c = project(-zn / sn, -zt / st, r.mu * std::sqrt(ct / cn));
  Local l;
  l.rn = c.qn / sn;
  l.rt = c.qt / st;
  l.energy = 0.5 * (c.qn * c.qn + c.qt * c.qt);
  l.knn = c.jnn / cn;
  l.knt = c.jnt / (sn * st);
  l.ktt = c.jtt / ct;
  l.face = c.face;
  return l;
}

/// The rows' H_a as 2 x 3 blocks per body: n = (nx, ny, 0) and t = (-ny, nx, -r) for body
/// i, minus the translation for body j with the same rotation sign (u_t's -w_j r_j).
void add_block(std::vector<Eigen::Triplet<double>>& t, const ContactRow& r, int i, int j,
               double knn, double knt, double ktt) {
  const double hi[2][3] = {{r.nx, r.ny, 0.0}, {-r.ny, r.nx, -r.ri}};
  const double hj[2][3] = {{-r.nx, -r.ny, 0.0}, {r.ny, -r.nx, -r.rj}};
  const double k[2][2] = {{knn, knt}, {knt, ktt}};
  auto couple = [&](int x, const double (*hx)[3], int y, const double (*hy)[3]) {
    if (x < 0 || y < 0) return;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) {
        double v = 0.0;
        for (int m = 0; m < 2; ++m)
          for (int l = 0; l < 2; ++l) v += hx[m][p] * k[m][l] * hy[l][q];
        t.emplace_back(x + p, y + q, v);
      }
  };
  couple(i, hi, i, hi);
  couple(i, hi, j, hj);
  couple(j, hj, i, hi);
  couple(j, hj, j, hj);
}

/// Adds H_a^T (dn, dt) to g.
void add_transpose(Vector& g, const ContactRow& r, int i, int j, double dn, double dt) {
  if (i >= 0) {
    g[i] += dn * r.nx - dt * r.ny;
    g[i + 1] += dn * r.ny + dt * r.nx;
    g[i + 2] += -dt * r.ri;
  }
  if (j >= 0) {
    g[j] -= dn * r.nx - dt * r.ny;
    g[j + 1] -= dn * r.ny + dt * r.nx;
    g[j + 2] += -dt * r.rj;
  }
}

struct Evaluation {
  double energy = 0.0;
  Vector gradient;
  std::vector<Local> locals;
};

Evaluation evaluate(const ContactSystem& s, const Primal& p, const Vector& v) {
  Evaluation e;
  const Vector dv = v - p.v_free;
  e.energy = 0.5 * dv.dot(p.mass.cwiseProduct(dv));
  e.gradient = p.mass.cwiseProduct(dv);
  e.locals.resize(s.rows.size());
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    const ContactRow& r = s.rows[a];
    double un, ut;
    p.local_velocity(s, r, v, un, ut);
    e.locals[a] = local(p, a, r, un, ut);
    e.energy += e.locals[a].energy;
    add_transpose(e.gradient, r, p.var[static_cast<std::size_t>(r.bi)],
                  p.var[static_cast<std::size_t>(r.bj)], -e.locals[a].rn, -e.locals[a].rt);
  }
  e.gradient = e.gradient.cwiseProduct(Vector::Ones(p.n) - p.locked);
  return e;
}

/// The exact step length along dv: the root of the convex piecewise quadratic's slope
/// f'(alpha) = dv . grad E(v + alpha dv), by Newton's method on it, kept in a bracket.
double line_search(const ContactSystem& s, const Primal& p, const Vector& v, const Vector& dv) {
  const std::size_t m = s.rows.size();
  std::vector<double> un(m), ut(m), dn(m), dt(m);
  for (std::size_t a = 0; a < m; ++a) {
    p.local_velocity(s, s.rows[a], v, un[a], ut[a]);
    p.local_velocity(s, s.rows[a], dv, dn[a], dt[a]);
  }
  const Vector mdv = p.mass.cwiseProduct(dv);
  const double quad = dv.dot(mdv), lin = (v - p.v_free).dot(mdv);
  auto slope = [&](double alpha, double& curvature) {
    double f1 = lin + alpha * quad;
    curvature = quad;
    for (std::size_t a = 0; a < m; ++a) {
      const Local l = local(p, a, s.rows[a], un[a] + alpha * dn[a], ut[a] + alpha * dt[a]);
      f1 -= l.rn * dn[a] + l.rt * dt[a];
      curvature += dn[a] * (l.knn * dn[a] + l.knt * dt[a]) + dt[a] * (l.knt * dn[a] + l.ktt * dt[a]);
    }
    return f1;
  };
  double lo = 0.0, hi = 1.0, c = 0.0;
  double f = slope(1.0, c);
  if (f <= 0.0) return 1.0;  // Newton's full step has not passed the minimum
  double alpha = 1.0;
  for (int k = 0; k < 30; ++k) {
    if (f > 0.0) hi = alpha; else lo = alpha;
    double next = alpha - f / c;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    alpha = next;
    f = slope(alpha, c);
    if (std::abs(f) <= 1e-12 * quad || hi - lo < 1e-12) break;
  }
  return alpha;
}

/// Rows' impulses and bodies' velocities from v's impulses R(v) (v = v_free + M^-1 H^T R).
void store(ContactSystem& s, const Evaluation& e) {
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    ContactRow& r = s.rows[a];
    const Local& l = e.locals[a];
    s.apply_impulse(r, l.rn - r.rn, l.rt - r.rt);
    r.rn = l.rn;
    r.rt = l.rt;
    r.status = l.face == 0 ? ContactStatus::open
               : l.face == 1 ? ContactStatus::stick
                             : ContactStatus::slide;
  }
}

/// De Saxce's shift mu |w_t| at each contact from v's impulses.
void move_shift(const ContactSystem& s, Primal& p, const Vector& v, const Evaluation& e) {
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    const ContactRow& r = s.rows[a];
    double un, ut;
    p.local_velocity(s, r, v, un, ut);
    const double wt = ut + p.ct[a] * (e.locals[a].rt - p.at[a]);
    p.shift[a] = r.mu * std::abs(wt);
  }
}

}  // namespace

PrimalReport solve_primal(ContactSystem& s, const PrimalOptions& o) {
  PrimalReport rep;
  if (s.rows.empty()) return rep;
  // The unknowns and the free velocities: v_free = v - M^-1 H^T R of the warm start.
  Primal p;
  p.var.assign(s.bodies.size(), -1);
  for (std::size_t b = 0; b < s.bodies.size(); ++b)
    if (moves(s.bodies[b])) {
      p.var[b] = p.n;
      p.n += 3;
    }
  p.mass.resize(p.n);
  p.locked = Vector::Zero(p.n);
  Vector v(p.n);
  for (std::size_t b = 0; b < s.bodies.size(); ++b)
    if (const int i = p.var[b]; i >= 0) {
      const Body& body = s.bodies[b];
      p.mass[i] = p.mass[i + 1] = 1.0 / body.inv_m;
      p.mass[i + 2] = body.inv_i > 0.0 ? 1.0 / body.inv_i : 1.0;
      p.locked[i + 2] = body.inv_i > 0.0 ? 0.0 : 1.0;
      v[i] = body.vx;
      v[i + 1] = body.vy;
      v[i + 2] = body.w;
    }
  Vector hr = Vector::Zero(p.n);
  for (const ContactRow& r : s.rows)
    add_transpose(hr, r, p.var[static_cast<std::size_t>(r.bi)], p.var[static_cast<std::size_t>(r.bj)],
                  r.rn, r.rt);
  hr = hr.cwiseProduct(Vector::Ones(p.n) - p.locked);
  p.v_free = v - hr.cwiseQuotient(p.mass);

  const std::size_t m = s.rows.size();
  const bool rigid = !s.compliant();
  double mean_w = 0.0;
  for (const ContactRow& r : s.rows) mean_w += r.w_nn;
  mean_w /= static_cast<double>(m);
  const double c_rigid = o.rigid_compliance * mean_w;
  p.cn.assign(m, rigid ? c_rigid : s.compliance_n);
  p.ct.assign(m, rigid ? c_rigid : s.compliance_t);
  p.an.resize(m);
  p.at.resize(m);
  for (std::size_t a = 0; a < m; ++a) {  // the anchor: R0 (compliant) or the start (rigid)
    p.an[a] = rigid ? s.rows[a].rn : s.rows[a].rn0;
    p.at[a] = rigid ? s.rows[a].rt : s.rows[a].rt0;
  }
  p.shift.assign(m, 0.0);
  Evaluation e = evaluate(s, p, v);
  move_shift(s, p, v, e);
  e = evaluate(s, p, v);

  Eigen::SimplicialLLT<Sparse> chol;
  bool analysed = false;
  std::vector<Eigen::Triplet<double>> trip;
  int inner = 0;
  while (rep.factorisations < o.max_factorisations) {
    if (o.cancel && o.cancel()) throw StepCancelled();
    // Newton's step on E at this shift: (M + sum H^T K H) dv = -grad E.
    trip.clear();
    trip.reserve(36 * m + static_cast<std::size_t>(p.n));
    for (int i = 0; i < p.n; ++i) trip.emplace_back(i, i, p.mass[i]);
    for (std::size_t a = 0; a < m; ++a) {
      const ContactRow& r = s.rows[a];
      const Local& l = e.locals[a];
      add_block(trip, r, p.var[static_cast<std::size_t>(r.bi)], p.var[static_cast<std::size_t>(r.bj)],
                l.knn, l.knt, l.ktt);
    }
    // A locked unknown keeps only its diagonal: its step is zero, its gradient being zero.
    for (auto& t : trip)
      if (t.row() != t.col() && (p.locked[t.row()] != 0.0 || p.locked[t.col()] != 0.0))
        t = Eigen::Triplet<double>(t.row(), t.col(), 0.0);
    Sparse A(p.n, p.n);
    A.setFromTriplets(trip.begin(), trip.end());
    if (!analysed) {
      chol.analyzePattern(A);
      analysed = true;
    }
    chol.factorize(A);
    ++rep.factorisations;
    if (chol.info() != Eigen::Success) break;
    const Vector dv = chol.solve(-e.gradient);
    const double alpha = line_search(s, p, v, dv);
    std::vector<int> before(m);
    for (std::size_t a = 0; a < m; ++a) before[a] = e.locals[a].face;
    v += alpha * dv;
    e = evaluate(s, p, v);
    bool same = alpha == 1.0;
    for (std::size_t a = 0; same && a < m; ++a) same = before[a] == e.locals[a].face;
    ++inner;
    // The law's residual of v's impulses, as the engine measures it.
    store(s, e);
    rep.residual = law_residual(s, o.velocity_floor).max;
    if (o.on_iteration) o.on_iteration(rep.factorisations, rep.shifts, rep.residual, alpha);
    if (rep.residual <= o.tolerance) {
      rep.converged = true;
      break;
    }
    if (same || inner >= o.inner_steps) {  // this E's minimum (or near it): move the shift
      if (rigid)
        for (std::size_t a = 0; a < m; ++a) {
          p.an[a] = e.locals[a].rn;
          p.at[a] = e.locals[a].rt;
        }
      move_shift(s, p, v, e);
      e = evaluate(s, p, v);
      ++rep.shifts;
      inner = 0;
    }
  }
  return rep;
}

SolveReport PrimalSolver::solve(ContactSystem& system, double gravity_velocity) const {
  if (system.rows.empty()) return SolveReport{};
  PrimalOptions o;
  o.tolerance = 0.5 * settings_.tolerance;
  o.velocity_floor = gravity_velocity;
  o.max_factorisations = std::max(1, std::min(primal_budget, settings_.max_sweeps - 1));
  o.cancel = system.cancel;
  const PrimalReport pr = solve_primal(system, o);
  // pcg from the primal impulses: its sweeps test the criterion on a sweep's impulses, as
  // every solver returns, and finish what the Newton steps left.
  SolverSettings rest = settings_;
  rest.solver = SolverKind::pcg;
  rest.max_sweeps = std::max(1, settings_.max_sweeps - pr.factorisations);
  SolveReport report = PcgSolver(rest).solve(system, gravity_velocity);
  report.sweeps += pr.factorisations;
  return report;
}

}  // namespace cdpile::cd
