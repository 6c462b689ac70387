// NSGS on a Delassus-form problem ũ = W r + q: block Gauss–Seidel over the 2×2 diagonal
// blocks, as Siconos' fc2d_nsgs. The posed velocity u = W r + q is kept up to date column
// by column, so one contact update costs the non-zeros of its two columns of W.
//
// Local problem of contact k with the other impulses frozen: u_k = A r_k + b with A = W_kk
// and b = u_k − A r_k(old). Unlike the body form (nsgs.cpp), A need not be diagonal (another
// code's W may couple normal and tangent), so the exact 2D Signorini–Coulomb solution is
// found by trying each case in turn:
//   b_n ≥ 0                                  → r = 0                        (opens)
//   r = −A⁻¹ b with |r_t| ≤ μ r_n            → sticking
//   r = r_n (1, −sμ), r_n = −b_n/(A_nn − sμ A_nt), s = ±1, with s·u_t ≥ 0  → sliding
// For a diagonal A these are the closed forms of nsgs.cpp. A held (bilateral) contact takes
// r_n = −b_n/A_nn of either sign and r_t = 0. Over-relaxation blends the old and the new
// impulse and projects back onto the cone, as in nsgs.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "nsgs.hpp"
#include "sweeps.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

// The sticking impulse −A⁻¹b, if A is invertible and it lies in the cone.
bool Sticking(const Eigen::Matrix2d& a, const Eigen::Vector2d& b, double mu, Eigen::Vector2d& r) {
  const double det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  if (!(det > 0.0)) return false;
  r = Eigen::Vector2d(a(0, 1) * b[1] - a(1, 1) * b[0], a(1, 0) * b[0] - a(0, 0) * b[1]) / det;
  return r[0] >= 0.0 && std::abs(r[1]) <= mu * r[0];
}

// The sliding impulse r_n (1, −sμ) with slip direction s = sign(u_t), if one fits.
bool Sliding(const Eigen::Matrix2d& a, const Eigen::Vector2d& b, double mu, Eigen::Vector2d& r) {
  for (const double s : {1.0, -1.0}) {
    const double d = a(0, 0) - s * mu * a(0, 1);
    if (!(d > 0.0)) continue;
    const double rn = -b[0] / d;
    const double ut = (a(1, 0) - s * mu * a(1, 1)) * rn + b[1];
    if (s * ut >= 0.0) {
      r = Eigen::Vector2d(rn, -s * mu * rn);
      return true;
    }
  }
  return false;
}

// Exact solution of u = A r + b under the law of one contact.
Eigen::Vector2d SolveLocal(const Eigen::Matrix2d& a, const Eigen::Vector2d& b,
                           const ContactLaw& law) {
  if (!(a(0, 0) > 0.0)) return Eigen::Vector2d::Zero();  // r cannot change its own u_n
  if (law.kind == ConstraintKind::kBilateral) return Eigen::Vector2d(-b[0] / a(0, 0), 0.0);
  if (b[0] >= 0.0) return Eigen::Vector2d::Zero();
  Eigen::Vector2d r;
  if (Sticking(a, b, law.mu, r) || Sliding(a, b, law.mu, r)) return r;
  // No case fits, which needs an indefinite block: the decoupled estimate on the cone, and
  // the residual will say how far it is.
  const double rt = a(1, 1) > 0.0 ? -b[1] / a(1, 1) : 0.0;
  return ProjectOnCone(Eigen::Vector2d(-b[0] / a(0, 0), rt), law.mu);
}

class DelassusSweeper {
 public:
  // From `start` (the guess's impulses, or empty: zero).
  DelassusSweeper(const DelassusProblem& p, double omega, const Eigen::VectorXd& start)
      : p_(p), omega_(omega) {
    blocks_.resize(p.NumContacts());
    for (int k = 0; k < p.NumContacts(); ++k) {
      for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) blocks_[k](i, j) = p.w.coeff(2 * k + i, 2 * k + j);
      }
    }
    r_ = start.size() == p.NumUnknowns() ? start : Eigen::VectorXd::Zero(p.NumUnknowns());
    u_ = p.w * r_ + p.q;
  }

  void Sweep(const std::vector<std::uint32_t>& order) {
    for (const std::uint32_t k : order) Update(static_cast<int>(k));
  }

  const Eigen::VectorXd& impulses() const { return r_; }

 private:
  void Update(int k) {
    const Eigen::Matrix2d& a = blocks_[k];
    const ContactLaw& law = p_.laws[k];
    const Eigen::Vector2d old = r_.segment<2>(2 * k);
    const Eigen::Vector2d b = u_.segment<2>(2 * k) - a * old;
    Eigen::Vector2d r = SolveLocal(a, b, law);
    const bool bilateral = law.kind == ConstraintKind::kBilateral;
    if (omega_ != 1.0) {
      r = (1.0 - omega_) * old + omega_ * r;
      if (!bilateral) r[0] = std::max(r[0], 0.0);
    }
    const double bound = bilateral ? 0.0 : law.mu * r[0];
    r[1] = std::clamp(r[1], -bound, bound);
    const Eigen::Vector2d delta = r - old;
    for (int j = 0; j < 2; ++j) {
      if (delta[j] == 0.0) continue;
      for (Eigen::SparseMatrix<double>::InnerIterator it(p_.w, 2 * k + j); it; ++it)
        u_[it.row()] += it.value() * delta[j];
    }
    r_.segment<2>(2 * k) = r;
  }

  const DelassusProblem& p_;
  const double omega_;
  std::vector<Eigen::Matrix2d> blocks_;
  Eigen::VectorXd r_;
  Eigen::VectorXd u_;  // W r + q
};

}  // namespace

SolveResult NsgsSolver::DoSolveDelassus(const DelassusProblem& p, const SolverOptions& options,
                                        const SolverGuess& guess) {
  DelassusSweeper sweeper(p, options.nsgs.relaxation, guess.impulses);
  SolveResult result;
  result.report.backend = Name();
  auto sweep = [&](const std::vector<std::uint32_t>& order) { sweeper.Sweep(order); };
  auto residual = [&] { return ComputeResidual(p, sweeper.impulses()).residual; };
  solvers_internal::RunSweeps(p.NumContacts(), options, sweep, residual, result.report);
  result.impulses = sweeper.impulses();
  return result;
}

}  // namespace unjam
