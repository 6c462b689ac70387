#include "unjam/solvers/pattern_polish.hpp"
#include "sparse_lu.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/SparseCore>
#include <Eigen/UmfPackSupport>

#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

// CorrectStates changes the states of the contacts whose natural-map error is at least
// this share of the largest one.
constexpr double kWorstShare = 0.5;

// What the step's system is made of whatever the pattern: assembled once for all the
// correction rounds of one SolveOnPattern.
struct StepParts {
  explicit StepParts(const ContactProblem& p)
      : h(AssembleJacobian(p)), h_rows(h), inv_mass(InverseMassDiagonal(p)),
        offset(VelocityOffset(p)), v_free(FreeVelocityVector(p)) {
    for (Eigen::Index d = 0; d < inv_mass.size(); ++d)
      mass_scale = std::max(mass_scale, 1.0 / inv_mass[d]);
  }
  Eigen::SparseMatrix<double> h;
  Eigen::SparseMatrix<double, Eigen::RowMajor> h_rows;
  Eigen::VectorXd inv_mass, offset, v_free;
  double mass_scale = 0.0;
};

SolveResult SolveOnStates(const ContactProblem& p, const StepParts& parts,
                          const Eigen::VectorXd& start, const std::vector<ContactState>& states) {
  using Triplet = Eigen::Triplet<double>;
  const int stride = p.UnknownsPerContact();
  Eigen::VectorXd impulses = start;
  // The impulses that move the grains: one column per force component the contact's state
  // leaves free, and one velocity row each.
  std::vector<Triplet> e;  // contact unknowns × force components
  std::vector<int> velocity_rows;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ProblemContact& c = p.contacts[static_cast<std::size_t>(k)];
    const int col = static_cast<int>(velocity_rows.size());
    if (c.kind == ConstraintKind::kBilateral) {
      if (stride == 2 && c.mu == 0.0) impulses[k * stride + 1] = 0.0;
      e.emplace_back(k * stride, col, 1.0);
      velocity_rows.push_back(k * stride);
      continue;
    }
    const ContactState s = states[static_cast<std::size_t>(k)];
    if (s == ContactState::kOpen) {  // exactly no force, not a rounding of zero
      for (int d = 0; d < stride; ++d) impulses[k * stride + d] = 0.0;
      continue;
    }
    if (s == ContactState::kStick || stride == 1) {
      for (int d = 0; d < stride; ++d) {
        e.emplace_back(k * stride + d, static_cast<int>(velocity_rows.size()), 1.0);
        velocity_rows.push_back(k * stride + d);
      }
      continue;
    }
    const double sigma = s == ContactState::kSlidePositive ? 1.0 : -1.0;
    impulses[k * stride + 1] = -sigma * c.mu * impulses[k * stride];  // on the edge exactly
    e.emplace_back(k * stride, col, 1.0);
    e.emplace_back(k * stride + 1, col, -sigma * c.mu);
    velocity_rows.push_back(k * stride);
  }
  const int dofs = p.NumDofs(), comps = static_cast<int>(velocity_rows.size());
  Eigen::SparseMatrix<double> e_matrix(p.NumUnknowns(), comps);
  e_matrix.setFromTriplets(e.begin(), e.end());
  const Eigen::SparseMatrix<double>& h = parts.h;
  const Eigen::SparseMatrix<double> hte = h.transpose() * e_matrix;
  const Eigen::VectorXd& inv_mass = parts.inv_mass;
  const Eigen::VectorXd& offset = parts.offset;

  // [ M   −HᵀE ] [v]   [M v_free + Hᵀ r]
  // [ H_s  −εI ] [λ] = [ −offset_s ]      (ε only fixes λ along the pattern's self-stresses)
  std::vector<Triplet> a;
  for (int d = 0; d < dofs; ++d) a.emplace_back(d, d, 1.0 / inv_mass[d]);
  for (int col = 0; col < hte.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(hte, col); it; ++it)
      a.emplace_back(static_cast<int>(it.row()), dofs + col, -it.value());
  }
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& h_rows = parts.h_rows;
  Eigen::VectorXd rhs(dofs + comps);
  rhs.head(dofs) = parts.v_free.cwiseQuotient(inv_mass) + h.transpose() * impulses;
  const double regularisation = 1e-14 * parts.mass_scale;
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
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  solvers_internal::ChooseOrdering(lu, system.rows(), solvers_internal::kPatternMetisRows);
  lu.compute(system);
  if (lu.info() != Eigen::Success) {
    out.impulses = impulses;
    out.report.status = SolveStatus::kNumericalFailure;
    out.report.message = "the step on the pattern: singular system";
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

}  // namespace

SolveResult SolveOnStates(const ContactProblem& p, const Eigen::VectorXd& start,
                          const std::vector<ContactState>& states) {
  return SolveOnStates(p, StepParts(p), start, states);
}

namespace {

// The state the answer's motion and forces ask contact k for (its own where they agree).
ContactState AskedState(const ContactProblem& p, const SolveResult& r, const Eigen::VectorXd& u,
                        int k, ContactState s, double tol, double slip_tol) {
  const int stride = p.UnknownsPerContact();
  const double mu = p.contacts[static_cast<std::size_t>(k)].mu;
  const double rn = r.impulses[stride * k], rt = stride == 2 ? r.impulses[2 * k + 1] : 0.0;
  if (s == ContactState::kStick) {
    if (rn < -tol) return ContactState::kOpen;
    if (mu * rn - rt < -tol) return ContactState::kSlideNegative;
    if (mu * rn + rt < -tol) return ContactState::kSlidePositive;
    return s;
  }
  if (s == ContactState::kOpen) return u[stride * k] < 0.0 ? ContactState::kStick : s;
  const double sigma = s == ContactState::kSlidePositive ? 1.0 : -1.0;
  if (rn < -tol) return ContactState::kOpen;
  if (sigma * u[2 * k + 1] < -slip_tol) return ContactState::kStick;
  return s;
}

}  // namespace

bool CorrectStates(const ContactProblem& p, const SolveResult& r, const std::vector<char>& frozen,
                   std::vector<ContactState>& states) {
  const int stride = p.UnknownsPerContact();
  const Eigen::VectorXd u = PosedContactVelocity(p, r.impulses);
  double scale = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k)
    scale = std::max(scale, std::abs(r.impulses[stride * k]));
  const double tol = 1e-15 * std::max(scale, 1e-300);
  // A slip this small next to the answer's largest contact velocity is none: the contact
  // sits on the edge of its cone without turning back.
  const double slip_tol = 1e-12 * std::max(u.lpNorm<Eigen::Infinity>(), 1e-300);
  const ResidualEvaluator evaluator(p);
  std::vector<double> errors(static_cast<std::size_t>(p.NumContacts()));
  evaluator.Errors(r.impulses, evaluator.Velocities(r.impulses), 0, p.NumContacts(), errors);
  std::vector<std::pair<int, ContactState>> asked;
  double worst = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k) {
    if (frozen[static_cast<std::size_t>(k)] != 0 ||
        p.contacts[static_cast<std::size_t>(k)].kind == ConstraintKind::kBilateral)
      continue;
    const ContactState s = states[static_cast<std::size_t>(k)];
    const ContactState next = AskedState(p, r, u, k, s, tol, slip_tol);
    if (next == s) continue;
    asked.emplace_back(k, next);
    worst = std::max(worst, errors[static_cast<std::size_t>(k)]);
  }
  // Only the contacts that break their law most (by the natural map, within kWorstShare of
  // the worst) change in one round: changing every contact that breaks it, dozens of them
  // by rounding alone, oscillates on hyperstatic piles and never reaches their answer.
  for (const auto& [k, next] : asked) {
    if (errors[static_cast<std::size_t>(k)] >= kWorstShare * worst)
      states[static_cast<std::size_t>(k)] = next;
  }
  return !asked.empty();
}

SolveResult SolveOnPattern(const ContactProblem& p, const Eigen::VectorXd& impulses,
                           std::vector<ContactState> states, const std::vector<char>& frozen,
                           int rounds) {
  SolveResult out = SolveOnStates(p, impulses, states);
  SolveResult best = out;
  int since_best = 0;
  // An answer at round-off is exact: corrections would act on contacts that break their law
  // by rounding only, and can lead away from it.
  for (int round = 0;
       round < rounds && since_best < kPatternStallRounds && out.report.converged() &&
       out.report.residual > kRoundOffResidual && CorrectStates(p, out, frozen, states);
       ++round) {
    out = SolveOnStates(p, impulses, states);
    ++since_best;
    if (out.report.converged() && out.report.residual < best.report.residual) {
      best = out;
      since_best = 0;
    }
  }
  return best;
}

std::vector<ContactState> StatesOf(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  const int stride = p.UnknownsPerContact();
  const Eigen::VectorXd u = PosedContactVelocity(p, impulses);
  std::vector<ContactState> states(static_cast<std::size_t>(p.NumContacts()), ContactState::kOpen);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const double rho = ResidualWeight(p, k);
    const double closing = impulses[stride * k] - rho * u[stride * k];
    if (!(closing > 0.0)) continue;
    ContactState& s = states[static_cast<std::size_t>(k)];
    s = ContactState::kStick;
    if (stride == 1) continue;
    const double trial = impulses[2 * k + 1] - rho * u[2 * k + 1];
    const double limit = p.contacts[static_cast<std::size_t>(k)].mu * closing;
    // The friction opposes the slip: r_t = −μ r_n for a positive slip.
    if (trial < -limit) s = ContactState::kSlidePositive;
    else if (trial > limit) s = ContactState::kSlideNegative;
  }
  return states;
}

SolveResult PolishOnPattern(const ContactProblem& p, const SolveResult& approximate,
                            double tolerance) {
  // An answer at round-off has nothing to gain; a non-finite one has no pattern.
  if (p.NumContacts() == 0 || !approximate.impulses.allFinite() ||
      approximate.report.residual <= kRoundOffResidual)
    return approximate;
  const std::vector<char> frozen(static_cast<std::size_t>(p.NumContacts()), 0);
  const SolveResult polished =
      SolveOnPattern(p, approximate.impulses, StatesOf(p, approximate.impulses), frozen);
  const double residual = polished.report.residual;
  const bool usable = polished.report.converged() && polished.impulses.allFinite() &&
                      residual < approximate.report.residual;
  if (!usable || (!approximate.report.converged() && !(residual <= tolerance))) return approximate;
  SolveResult out = approximate;
  out.impulses = polished.impulses;
  out.report.residual = residual;
  out.report.status = SolveStatus::kConverged;
  out.basis.clear();  // a pivoting backend's basis need not be the polished pattern's
  char text[160];
  std::snprintf(text, sizeof text, "solved exactly on its contact pattern: residual %.3g to %.3g",
                approximate.report.residual, residual);
  out.report.message += (out.report.message.empty() ? "" : "; ") + std::string(text);
  return out;
}

}  // namespace unjam
