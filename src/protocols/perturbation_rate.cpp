#include "perturbation_rate.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <Eigen/UmfPackSupport>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

using Key = std::tuple<int, int, int, int>;
Key KeyOf(const Contact& c) { return {c.i, c.j, c.image[0], c.image[1]}; }

// Closed-contact index of every contact of a posed step, by key (−1: not closed).
std::vector<int> ClosedIndexOf(const RateBase& rb, const StaticProblem& posed) {
  std::map<Key, int> closed;
  for (std::size_t c = 0; c < rb.closed.size(); ++c) {
    const int k = rb.closed[c];
    closed[KeyOf(rb.posed.contacts[static_cast<std::size_t>(
        rb.posed.assembled.source_contact[static_cast<std::size_t>(k)])])] = static_cast<int>(c);
  }
  const ContactProblem& p = posed.assembled.problem;
  std::vector<int> out(static_cast<std::size_t>(p.NumContacts()), -1);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const auto it = closed.find(KeyOf(posed.contacts[static_cast<std::size_t>(
        posed.assembled.source_contact[static_cast<std::size_t>(k)])]));
    if (it != closed.end()) out[static_cast<std::size_t>(k)] = it->second;
  }
  return out;
}

Eigen::SparseMatrix<double> RowsOf(const Eigen::SparseMatrix<double>& h,
                                   const std::vector<int>& rows) {
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> t;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> by_row = h;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(by_row, rows[r]); it;
         ++it) {
      t.emplace_back(static_cast<int>(r), static_cast<int>(it.col()), it.value());
    }
  }
  Eigen::SparseMatrix<double> out(static_cast<Eigen::Index>(rows.size()), h.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

RateProblem ProblemOver(const RateBase& rb, Eigen::MatrixXd basis) {
  const ContactProblem& p = rb.posed.assembled.problem;
  const int stride = rb.UnknownsPerContact();
  RateProblem out;
  out.basis = std::move(basis);
  for (std::size_t c = 0; c < rb.closed.size(); ++c) {
    RateContact rc;
    rc.row_n = static_cast<int>(c) * stride;
    rc.row_t = stride == 2 ? rc.row_n + 1 : -1;
    rc.mu = p.contacts[static_cast<std::size_t>(rb.closed[c])].mu;
    rc.r0_n = rb.impulses[rc.row_n];
    rc.r0_t = stride == 2 ? rb.impulses[rc.row_t] : 0.0;
    out.contacts.push_back(rc);
  }
  return out;
}

int BodyColumn(const ContactProblem& p, int body, int component) {
  return body * p.DofsPerBody() + component;
}

}  // namespace

RateBase PrepareRateBase(const PerturbationBase& base, const StaticSolveOptions& step) {
  RateBase rb;
  rb.posed = PoseStaticProblem(base.scene, step);
  const ContactProblem& p = rb.posed.assembled.problem;
  const int stride = p.UnknownsPerContact();
  rb.closed_index.assign(static_cast<std::size_t>(p.NumContacts()), -1);
  std::vector<int> rows;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const Contact& c = rb.posed.contacts[static_cast<std::size_t>(
        rb.posed.assembled.source_contact[static_cast<std::size_t>(k)])];
    const bool loaded = p.initial_guess.size() > 0 && p.initial_guess[k * stride] != 0.0;
    if (!(std::abs(c.gap) <= step.closed_gap_tolerance) && !loaded) continue;
    rb.closed_index[static_cast<std::size_t>(k)] = static_cast<int>(rb.closed.size());
    rb.closed.push_back(k);
    for (int d = 0; d < stride; ++d) rows.push_back(k * stride + d);
  }
  rb.jacobian = RowsOf(AssembleJacobian(p), rows);
  rb.impulses.resize(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    rb.impulses[static_cast<Eigen::Index>(r)] =
        p.initial_guess.size() > 0 ? p.initial_guess[rows[r]] : 0.0;
  }
  rb.stresses = ComputeSelfStresses(rb.jacobian);
  return rb;
}

RateTarget PoseRateTarget(const RateBase& rb, const PerturbationTarget& t,
                          const PerturbationOptions& o) {
  RateTarget out;
  const ContactProblem& p = rb.posed.assembled.problem;
  const int stride = rb.UnknownsPerContact();
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    const int body = rb.posed.assembled.body_of_particle[static_cast<std::size_t>(t.i)];
    if (body < 0) {
      out.refused = "the particle has no degrees of freedom";
      return out;
    }
    std::vector<int> released;
    for (int d = 0; d < p.DofsPerBody(); ++d) released.push_back(BodyColumn(p, body, d));
    out.problem = ProblemOver(rb, ExtendSelfStresses(rb.stresses.basis, rb.jacobian, released));
    const Eigen::VectorXd motion = rb.jacobian.col(BodyColumn(p, body, 0)) * t.direction.x() +
                                   rb.jacobian.col(BodyColumn(p, body, 1)) * t.direction.y();
    // The shift opens (u_n = H v > 0) or presses the particle's contacts; the driver is
    // the compression it imposes, as the held contact's is for an opening.
    out.problem.driver = -(out.problem.basis.transpose() * motion);
    // F_crit = −ŝ·(Hᵀ r)_p: the contact impulses on p against the shift.
    const Eigen::MatrixXd hs = rb.jacobian.transpose() * out.problem.basis;
    const Eigen::VectorXd h0 = rb.jacobian.transpose() * rb.impulses;
    const int cx = BodyColumn(p, body, 0), cy = BodyColumn(p, body, 1);
    out.critical = -(t.direction.x() * hs.row(cx) + t.direction.y() * hs.row(cy)).transpose();
    out.critical_offset = -(t.direction.x() * h0[cx] + t.direction.y() * h0[cy]);
    return out;
  }
  int held = -1;
  for (std::size_t c = 0; c < rb.closed.size(); ++c) {
    const Contact& k = rb.posed.contacts[static_cast<std::size_t>(
        rb.posed.assembled.source_contact[static_cast<std::size_t>(rb.closed[c])])];
    if (k.i == t.i && k.j == t.j && k.image == t.image) held = static_cast<int>(c);
  }
  if (held < 0) {
    out.refused = "the contact is not closed in the static state";
    return out;
  }
  std::vector<int> released;  // a frozen cell no longer has to balance
  if (o.cell == CellCondition::kFixedVolume && p.cell) released.push_back(p.NumDofs() - 1);
  out.problem = ProblemOver(rb, ExtendSelfStresses(rb.stresses.basis, rb.jacobian, released));
  out.problem.contacts[static_cast<std::size_t>(held)].held = true;
  if (stride == 2) out.problem.released_rows.push_back(held * stride + 1);
  out.problem.driver = out.problem.basis.row(held * stride).transpose();
  out.critical = out.problem.basis.row(held * stride).transpose();
  out.critical_offset = rb.impulses[held * stride];
  return out;
}

namespace {

// The step's solution with the contacts in `states` (closed-contact order), from the
// forces `forces` (closed-contact unknowns) and the impulses that move the grains.
SolveResult SolveOnStates(const StaticProblem& perturbed, const std::vector<int>& closed,
                          const Eigen::VectorXd& forces, const std::vector<ContactState>& states) {
  using Triplet = Eigen::Triplet<double>;
  const ContactProblem& p = perturbed.assembled.problem;
  const int stride = p.UnknownsPerContact();

  // The path's forces on the perturbed step's contacts (zero on the ones it leaves open).
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(p.NumUnknowns());
  // The impulses that move the grains: one column per force component the contact's state
  // leaves free (both while it sticks, the normal one, with the friction on the edge, while
  // it slides; the held contact's normal one), and one velocity row each.
  std::vector<Triplet> e;  // contact unknowns × force components
  std::vector<int> velocity_rows;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int c = closed[static_cast<std::size_t>(k)];
    if (c < 0) continue;
    for (int d = 0; d < stride; ++d) impulses[k * stride + d] = forces[c * stride + d];
    const int col = static_cast<int>(velocity_rows.size());
    if (p.contacts[static_cast<std::size_t>(k)].kind == ConstraintKind::kBilateral) {
      // The held contact: its friction is released to zero exactly (the path's force
      // there is zero up to round-off).
      if (stride == 2 && p.contacts[static_cast<std::size_t>(k)].mu == 0.0)
        impulses[k * stride + 1] = 0.0;
      e.emplace_back(k * stride, col, 1.0);
      velocity_rows.push_back(k * stride);
      continue;
    }
    const ContactState s = states[static_cast<std::size_t>(c)];
    if (s == ContactState::kOpen) {  // exactly no force, not the path's rounding of zero
      for (int d = 0; d < stride; ++d) impulses[k * stride + d] = 0.0;
      continue;
    }
    if (s == ContactState::kStick) {
      for (int d = 0; d < stride; ++d) {
        e.emplace_back(k * stride + d, static_cast<int>(velocity_rows.size()), 1.0);
        velocity_rows.push_back(k * stride + d);
      }
      continue;
    }
    const double sigma = s == ContactState::kSlidePositive ? 1.0 : -1.0;
    // On the edge exactly: the path's forces drift off it by round-off over many events.
    impulses[k * stride + 1] =
        -sigma * p.contacts[static_cast<std::size_t>(k)].mu * impulses[k * stride];
    e.emplace_back(k * stride, col, 1.0);
    e.emplace_back(k * stride + 1, col, -sigma * p.contacts[static_cast<std::size_t>(k)].mu);
    velocity_rows.push_back(k * stride);
  }
  const int dofs = p.NumDofs(), comps = static_cast<int>(velocity_rows.size());
  Eigen::SparseMatrix<double> e_matrix(p.NumUnknowns(), comps);
  e_matrix.setFromTriplets(e.begin(), e.end());
  const Eigen::SparseMatrix<double> h = AssembleJacobian(p);
  const Eigen::SparseMatrix<double> hte = h.transpose() * e_matrix;
  const Eigen::VectorXd inv_mass = InverseMassDiagonal(p);
  const Eigen::VectorXd offset = VelocityOffset(p);

  // [ M   −HᵀE ] [v]   [M v_free + Hᵀ r]
  // [ H_s  −εI ] [λ] = [ −offset_s ]      (ε only fixes λ along the pattern's self-stresses)
  std::vector<Triplet> a;
  for (int d = 0; d < dofs; ++d) a.emplace_back(d, d, 1.0 / inv_mass[d]);
  for (int col = 0; col < hte.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(hte, col); it; ++it)
      a.emplace_back(static_cast<int>(it.row()), dofs + col, -it.value());
  }
  const Eigen::SparseMatrix<double, Eigen::RowMajor> h_rows = h;
  Eigen::VectorXd rhs(dofs + comps);
  const Eigen::VectorXd v_free = FreeVelocityVector(p);
  rhs.head(dofs) = v_free.cwiseQuotient(inv_mass) + h.transpose() * impulses;
  double mass_scale = 0.0;
  for (int d = 0; d < dofs; ++d) mass_scale = std::max(mass_scale, 1.0 / inv_mass[d]);
  const double regularisation = 1e-14 * mass_scale;
  for (int r = 0; r < comps; ++r) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(
             h_rows, velocity_rows[static_cast<std::size_t>(r)]);
         it; ++it) {
      a.emplace_back(dofs + r, static_cast<int>(it.col()), it.value());
    }
    a.emplace_back(dofs + r, dofs + r, -regularisation);
    rhs[dofs + r] = -offset[velocity_rows[static_cast<std::size_t>(r)]];
  }
  Eigen::SparseMatrix<double> system(dofs + comps, dofs + comps);
  system.setFromTriplets(a.begin(), a.end());
  SolveResult out;
  out.report.backend = "rate";
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu(system);
  if (lu.info() != Eigen::Success) {
    out.impulses = impulses;
    out.report.status = SolveStatus::kNumericalFailure;
    out.report.message = "the step on the path's pattern: singular system";
    out.report.residual = ComputeResidual(p, impulses).residual;
    return out;
  }
  // Proximal-point refinement: each solve shifts the regularisation to the last λ, so the
  // iterates solve the unregularised system wherever it has a solution, and ε only picks
  // λ along the pattern's self-stresses.
  const Eigen::VectorXd velocity_rhs = rhs.tail(comps);
  Eigen::VectorXd x = lu.solve(rhs);
  for (int round = 0; round < 8; ++round) {
    rhs.tail(comps) = velocity_rhs - regularisation * x.tail(comps);
    const Eigen::VectorXd next = lu.solve(rhs);
    const double change = (next - x).tail(comps).lpNorm<Eigen::Infinity>();
    x = next;
    if (!(change > 1e-15 * std::max(1.0, x.tail(comps).lpNorm<Eigen::Infinity>()))) break;
  }
  out.impulses = impulses + e_matrix * x.tail(comps);
  out.report.residual = ComputeResidual(p, out.impulses).residual;
  out.report.status = SolveStatus::kConverged;
  return out;
}

// Contacts whose state the impulses that move the grains (O(ξ) next to the path's forces)
// contradict: a contact left at the edge of its cone, or with no force, by the path is
// pushed out of it, an open one closes, a sliding one turns back. Each is given the state
// its O(ξ) motion asks for; returns whether any changed.
bool CorrectStates(const StaticProblem& perturbed, const std::vector<int>& closed,
                   const SolveResult& r, std::vector<ContactState>& states) {
  const ContactProblem& p = perturbed.assembled.problem;
  const int stride = p.UnknownsPerContact();
  const Eigen::VectorXd u = PosedContactVelocity(p, r.impulses);
  double scale = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k)
    scale = std::max(scale, std::abs(r.impulses[stride * k]));
  const double tol = 1e-15 * std::max(scale, 1e-300);
  // A slip this small next to the response's largest contact velocity is none: the contact
  // sits on the edge of its cone without turning back.
  const double slip_tol = 1e-12 * std::max(u.lpNorm<Eigen::Infinity>(), 1e-300);
  bool changed = false;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int c = closed[static_cast<std::size_t>(k)];
    if (c < 0 || p.contacts[static_cast<std::size_t>(k)].kind == ConstraintKind::kBilateral)
      continue;
    ContactState& s = states[static_cast<std::size_t>(c)];
    const double mu = p.contacts[static_cast<std::size_t>(k)].mu;
    const double rn = r.impulses[stride * k], rt = stride == 2 ? r.impulses[2 * k + 1] : 0.0;
    const ContactState before = s;
    if (s == ContactState::kStick) {
      if (rn < -tol) s = ContactState::kOpen;
      else if (mu * rn - rt < -tol) s = ContactState::kSlideNegative;
      else if (mu * rn + rt < -tol) s = ContactState::kSlidePositive;
    } else if (s == ContactState::kOpen) {
      if (u[stride * k] < 0.0) s = ContactState::kStick;
    } else {
      const double sigma = s == ContactState::kSlidePositive ? 1.0 : -1.0;
      if (rn < -tol) s = ContactState::kOpen;
      else if (sigma * u[2 * k + 1] < -slip_tol) s = ContactState::kStick;
    }
    changed = changed || s != before;
  }
  return changed;
}

}  // namespace

SolveResult StepOnPattern(const RateBase& rb, const RateTarget& rt, const RatePathResult& path,
                          const StaticProblem& perturbed) {
  const std::vector<int> closed = ClosedIndexOf(rb, perturbed);
  const Eigen::VectorXd forces = rb.impulses + rt.problem.basis * path.alpha;
  std::vector<ContactState> states = path.states;
  SolveResult out = SolveOnStates(perturbed, closed, forces, states);
  for (int round = 0;
       round < 20 && out.report.converged() && CorrectStates(perturbed, closed, out, states);
       ++round) {
    out = SolveOnStates(perturbed, closed, forces, states);
  }
  return out;
}

int ContactClosedAt(const StaticProblem& perturbed, const Eigen::VectorXd& impulses,
                    double factor) {
  const ContactProblem& p = perturbed.assembled.problem;
  const Eigen::VectorXd u = PosedContactVelocity(p, impulses);
  const int stride = p.UnknownsPerContact();
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ProblemContact& c = p.contacts[static_cast<std::size_t>(k)];
    const Contact& geometry = perturbed.contacts[static_cast<std::size_t>(
        perturbed.assembled.source_contact[static_cast<std::size_t>(k)])];
    if (c.kind != ConstraintKind::kUnilateral || !(geometry.gap > 0.0) ||
        impulses[k * stride] != 0.0)
      continue;
    // ũ_n = u_n − target, target = −gap/Δt: at `factor` times the motion the gap left is
    // gap + factor Δt u_n.
    const double un = u[k * stride] + c.target_velocity;
    if (factor * un - c.target_velocity < -1e-9 * std::abs(c.target_velocity)) return k;
  }
  return -1;
}

}  // namespace unjam
