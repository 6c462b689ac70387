// The De Saxcé fixed point shared by the convex backends (ipopt, nlopt). See de_saxce.cpp.
//
// The convex step, with W, q of contact_problem.hpp (ũ = W r + q) and a frozen shift s:
//     minimise ½ rᵀ W r + (q + s)ᵀ r   over r ∈ K = Π_k K_k,
// K_k the Coulomb cone {|r_t| ≤ μ r_n} (frictional), the half-line r_n ≥ 0 (frictionless),
// or {r_n free, r_t = 0} for a held (bilateral) contact. Its optimality conditions are
//     r_k ∈ K_k,  ũ_k + s_k ∈ K_k*,  r_k ⊥ (ũ_k + s_k),
// and with s_k = (μ_k |u_t,k|, 0) at the solution itself they are exactly Signorini–Coulomb
// (De Saxcé's bipotential; Acary, Cadoux, Lemaréchal, Marcote 2011).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/problem/delassus_problem.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

// What the convex step needs to know of each contact, whichever form the problem comes in
// (contact_problem.hpp or delassus_problem.hpp). A Delassus-form problem is frictional with
// two unknowns per contact (μ may be 0); `diagonal` is (W_nn, W_tt) of the contact, zero for
// a contact without degrees of freedom (its impulse is held at 0).
struct ContactLayout {
  int per_contact = 1;  // unknowns per contact
  bool frictional = false;
  std::vector<ContactLaw> laws;           // per contact
  std::vector<Eigen::Vector2d> diagonal;  // per contact
  int NumContacts() const { return static_cast<int>(laws.size()); }
  int NumUnknowns() const { return per_contact * NumContacts(); }
  // A frictional unilateral contact with μ > 0 and degrees of freedom: its cone is posed.
  bool ConeRows(int k) const {
    return frictional && laws[k].kind == ConstraintKind::kUnilateral && laws[k].mu > 0.0 &&
           !Inert(k);
  }
  bool Inert(int k) const { return diagonal[k].isZero(0.0); }
};
ContactLayout LayoutOf(const ContactProblem& problem);
ContactLayout LayoutOf(const DelassusProblem& problem);

// The convex step is a minimisation only for a symmetric W: for a Delassus-form problem,
// an empty string if W equals Wᵀ to a relative tolerance (kSymmetryTolerance × max |W_ij|),
// otherwise why it is refused.
constexpr double kSymmetryTolerance = 1e-10;
std::string AsymmetryOf(const DelassusProblem& problem);
// The convex step is convex only for a positive semidefinite W: an empty string if
// W + τ I (τ = kDefinitenessTolerance × max |W_ij|) has no negative pivot in its sparse
// LDLᵀ factorisation (by Sylvester's law of inertia: no eigenvalue of W below −τ),
// otherwise why it is refused. A W with a negative eigenvalue, which Siconos' 00237 and
// 00727 have (−8e-8, −5e-8), makes ½ rᵀ W r + sᵀ r non-convex: the library then returns
// one of several local minima and the fixed point stalls. τ keeps the PSD but singular W
// of a hyperstatic packing (round-off eigenvalues near 0) out of the test.
constexpr double kDefinitenessTolerance = 1e-9;
std::string IndefinitenessOf(const DelassusProblem& problem);
// Both refusals of the convex backends, the first that applies.
std::string NotConvexOf(const DelassusProblem& problem);
// The refusal of a backend that cannot pose `problem` (kUnsupported, zero impulses).
SolveResult Unsupported(const DelassusProblem& problem, const std::string& backend,
                        const std::string& why);

// The convex step's law at a frozen shift: the fixed point's measures and helpers.
// Vectors are laid out as the impulses, UnknownsPerContact() per contact; `velocity` is the
// posed velocity ũ = W r + q of `impulses`.
class ConvexLaw {
 public:
  explicit ConvexLaw(const ContactProblem& problem);
  explicit ConvexLaw(const DelassusProblem& problem);

  // s_k = (μ_k |u_t,k|, 0) for frictional unilateral contacts, 0 elsewhere.
  Eigen::VectorXd Shift(const Eigen::VectorXd& velocity) const;
  // The unjam residual (residual.hpp) with the shift frozen at `shift` instead of μ|u_t|:
  // max_k ‖r_k − Π_K(r_k − ρ_k (ũ_k + s_k))‖ / scale. Equal to ComputeResidual when
  // shift = Shift(velocity); the measure of a convex step's accuracy.
  double Residual(const Eigen::VectorXd& impulses, const Eigen::VectorXd& velocity,
                  const Eigen::VectorXd& shift) const;
  // How much the natural map can move when the shift changes from `before` to `after`:
  // max_k ρ_k |Δs_k| / scale, in the units of the residual.
  double ShiftChange(const Eigen::VectorXd& impulses, const Eigen::VectorXd& before,
                     const Eigen::VectorXd& after) const;
  // The impulses with every unilateral contact that the natural map finds open
  // (Π_K(r_k − ρ_k (ũ_k + s_k)) = 0) set to exactly 0. An interior point leaves such
  // contacts at a value of the order of its barrier parameter, which the max-norm residual
  // sees as an error relative to the mean impulse (and as the whole scale when every
  // contact opens).
  Eigen::VectorXd ZeroOpenContacts(const Eigen::VectorXd& impulses, const Eigen::VectorXd& velocity,
                                   const Eigen::VectorXd& shift) const;

  double rho(int k) const { return rho_[k]; }

 private:
  Eigen::Vector2d Local(const Eigen::VectorXd& x, int k) const;
  Eigen::Vector2d MapArgument(const Eigen::VectorXd& impulses, const Eigen::VectorXd& velocity,
                              const Eigen::VectorXd& shift, int k) const;
  double Scale(const Eigen::VectorXd& impulses) const;

  ContactLayout layout_;
  std::vector<double> rho_;      // ResidualWeight: 1 / W_nn
  double fallback_scale_ = 1.0;  // ComputeResidual's scale when every impulse vanishes
};

// One convex solve, as a library reports it.
struct ConvexStep {
  Eigen::VectorXd impulses;
  bool solved = false;                                   // the library reports success
  SolveStatus failure = SolveStatus::kNumericalFailure;  // what a failure means for the report
  std::string library_status;  // the library's own name for how it stopped
  int iterations = 0;          // the library's iterations (or evaluations)
};

class ConvexStepSolver {
 public:
  virtual ~ConvexStepSolver() = default;
  // Solves the convex step with shift `shift` from `start`, aiming at
  // ConvexLaw::Residual ≤ `tolerance`, and stops after `time_limit` wall-clock seconds
  // (failure kIterationLimit).
  virtual ConvexStep Solve(const Eigen::VectorXd& shift, const Eigen::VectorXd& start,
                           double tolerance, double time_limit) = 0;
  // What one library iteration is called in the report ("Ipopt iterations").
  virtual std::string IterationName() const = 0;
  // Whether each solve adds a proximal term centred on its start (ipopt_solver.cpp): the
  // same shift then poses another convex problem once the start has moved.
  virtual bool Proximal() const { return false; }
};

// The fixed point on the shift, or the convex relaxation alone
// (options.de_saxce.convex_relaxation). report.iterations counts convex solves; the true
// residual of the returned impulses (the best seen) is always in report.residual. Both
// forms: the posed velocity is PosedContactVelocity (body form) or W r + q (Delassus form),
// the residual ComputeResidual.
SolveResult SolveByDeSaxceFixedPoint(const ContactProblem& problem, const SolverOptions& options,
                                     const SolverGuess& guess, const std::string& backend,
                                     ConvexStepSolver& step);
SolveResult SolveByDeSaxceFixedPoint(const DelassusProblem& problem, const SolverOptions& options,
                                     const SolverGuess& guess, const std::string& backend,
                                     ConvexStepSolver& step);

}  // namespace unjam
