// The convex step of the De Saxcé fixed point (de_saxce.hpp) as a sparse QP for Ipopt:
//
//     minimise ½ rᵀ W r + (q + s)ᵀ r
//     subject to  μ_k r_n,k − r_t,k ≥ 0,  μ_k r_n,k + r_t,k ≥ 0    (frictional, μ_k > 0)
//                 r_n,k ≥ 0                                       (frictionless, or μ_k = 0
//                                                                  with r_t,k = 0)
//                 r_n,k free, r_t,k = 0                           (held contact)
//
// r_n ≥ 0 is left out where the two cone rows imply it: a third active constraint at the
// apex would make every open contact degenerate for the interior point.
//
// Why the cell rate is lifted. A pressure bath adds c cᵀ / (M_λ D V) to W (c_k the cell
// arms, one per contact): W = W_b + m_λ c cᵀ is dense. With one more variable y and one
// equality row y = cᵀ r_n, the objective ½ rᵀ W_b r + ½ m_λ y² + (q + s)ᵀ r keeps the Hessian
// as sparse as the contact network and the Jacobian gains one row of N_c entries.
//
// Delassus form (SolveDelassus): Q is W itself (symmetrised, ½(W + Wᵀ), after checking that
// W is symmetric to a relative 1e-10: de_saxce.hpp, AsymmetryOf), the offset q, no cell
// variable; bounds and cone rows as above with every contact frictional (μ = 0: r_t = 0),
// and a contact whose diagonal block of W vanishes held at r = 0.
//
// Scaling. Impulses are divided by an impulse scale S (the residual's scale of each solve's
// start) and the objective by S² w̄ (w̄ the mean W_nn), so that a gradient entry is an
// impulse relative to S, like the unjam residual, and Ipopt's tolerances mean roughly the
// same thing as ours. y is measured in units of S·C, C = Σ|c_k|, so the cell row has unit
// entries on average. Derivatives are constant (hessian_constant, jac_*_constant), the
// linear solver is MUMPS (the only one in Debian's Ipopt), and Mehrotra's predictor–
// corrector suits a convex QP.
//
// Why a proximal term. W is singular along every self-stress (Hᵀr = 0). Where a self-stress
// fits inside every cone it touches (disks wedged between two walls with friction,
// problems/hard/column-200.unjam; a hexagonal pile on a floor), the convex step's optimal face
// is unbounded along it, and an interior point drifts to infinity on it (the central path
// leads to the face's analytic centre). A step of the column at rest came back with impulses
// 10⁹ times the weights, residual 3e-14 relative to them, and its absolute error moved the
// grains: overlap 4.6 radii and energy created after 10 steps; a 20-wide hexagonal pile's
// static forces came back 10⁵ times its load. So each convex solve minimises ε/2 |x − x₀|²
// more, x₀ its start (the fixed point's iterate): strictly convex, bounded, and a fixed point
// x = x₀ of the loop solves the exact law all the same. The convex relaxation, solved once,
// has none.
#include "ipopt_solver.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <Eigen/SparseCore>

#include "de_saxce.hpp"
#include "deadline.hpp"
#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

using Ipopt::Index;
using Ipopt::Number;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

constexpr double kInfinity = 2e19;         // Ipopt reads |bound| ≥ 1e19 as none
constexpr double kToleranceFloor = 1e-13;  // on Ipopt's scaled KKT error (SetTolerance)
// ε of the proximal term, relative to the mean W_nn (the scaled Q has unit mean diagonal).
// It must hold the drift, yet leave the soft modes of a large packing (small eigenvalues of
// Q) alone, or every convex solve lands ε/λ short of the step's solution and the fixed point
// crawls. Measured: 1e-12 keeps the hexagonal piles' forces at their load (20, 40 and 400
// wide) and a cold N = 3000 packing in one convex solve (34 iterations, 5.8e-11); 1e-11 took
// that packing 199 iterations, 1e-10 57 s and 1e-6 112 s without converging.
constexpr double kProximalWeight = 1e-12;

// The scaled QP: x = (r / S, y / (S C)), objective ½ xᵀ Q x + ((q + s) / (S w̄))ᵀ x, rows
// J x. Q and J do not depend on S.
struct ScaledQp {
  int unknowns = 0;
  double delassus_scale = 1.0;  // w̄
  SparseMatrix hessian;         // Q, symmetric, both triangles
  SparseMatrix rows;            // J, row-major use through triplets
  Triplets hessian_lower;
  Triplets row_entries;
  Eigen::VectorXd offset;     // q / w̄
  Eigen::VectorXd cell_arms;  // c, per unknown (0 on tangential rows)
  double cell_unit = 1.0;     // C = Σ|c_k|
  std::vector<double> x_lower, x_upper, g_lower, g_upper;
  int Variables() const { return static_cast<int>(x_lower.size()); }
};

void SetBounds(const ContactLayout& p, int k, ScaledQp& qp) {
  const int m = p.per_contact;
  const ContactLaw& c = p.laws[k];
  const bool inert = p.Inert(k);  // no degrees of freedom: r = 0
  const bool cone_rows = p.ConeRows(k);
  qp.x_lower[k * m] =
      inert ? 0.0 : (c.kind == ConstraintKind::kBilateral || cone_rows ? -kInfinity : 0.0);
  qp.x_upper[k * m] = inert ? 0.0 : kInfinity;
  if (m == 2) {
    qp.x_lower[k * m + 1] = cone_rows ? -kInfinity : 0.0;
    qp.x_upper[k * m + 1] = cone_rows ? kInfinity : 0.0;
  }
}

// Cone rows (two per frictional contact) and the cell row y − cᵀ r_n = 0.
void AddRows(const ContactLayout& p, bool cell, ScaledQp& qp) {
  int row = 0;
  for (int k = 0; k < p.NumContacts(); ++k) {
    if (!p.ConeRows(k)) continue;
    for (double sign : {-1.0, 1.0}) {
      qp.row_entries.emplace_back(row, 2 * k, p.laws[k].mu);
      qp.row_entries.emplace_back(row, 2 * k + 1, sign);
      qp.g_lower.push_back(0.0);
      qp.g_upper.push_back(kInfinity);
      ++row;
    }
  }
  if (!cell) return;
  qp.row_entries.emplace_back(row, qp.unknowns, 1.0);
  for (int i = 0; i < qp.unknowns; ++i) {
    if (qp.cell_arms[i] != 0.0)
      qp.row_entries.emplace_back(row, i, -qp.cell_arms[i] / qp.cell_unit);
  }
  qp.g_lower.push_back(0.0);
  qp.g_upper.push_back(0.0);
}

// w̄, the mean W_nn (1 without contacts or normal curvature).
double DelassusScale(const ContactLayout& layout) {
  double sum_wnn = 0.0;
  for (int k = 0; k < layout.NumContacts(); ++k) sum_wnn += layout.diagonal[k][0];
  return sum_wnn > 0.0 ? sum_wnn / layout.NumContacts() : 1.0;
}

// The bounds and rows, once Q and the offset are in place.
void Constrain(const ContactLayout& layout, bool cell, ScaledQp& qp) {
  const int n = static_cast<int>(qp.hessian.rows());
  qp.x_lower.assign(n, -kInfinity);
  qp.x_upper.assign(n, kInfinity);
  for (int k = 0; k < layout.NumContacts(); ++k) SetBounds(layout, k, qp);
  AddRows(layout, cell, qp);
  qp.rows.resize(static_cast<Eigen::Index>(qp.g_lower.size()), n);
  qp.rows.setFromTriplets(qp.row_entries.begin(), qp.row_entries.end());
}

ScaledQp MakeScaledQp(const ContactProblem& p) {
  const ContactLayout layout = LayoutOf(p);
  ScaledQp qp;
  qp.unknowns = p.NumUnknowns();
  const int n = qp.unknowns + (p.cell ? 1 : 0);
  qp.delassus_scale = DelassusScale(layout);

  const SparseMatrix h = AssembleJacobian(p);
  if (p.cell) {
    qp.cell_arms = h.col(p.NumDofs() - 1);
    qp.cell_unit = std::max(qp.cell_arms.lpNorm<1>(), 1e-300);
  }
  const int body_dofs = p.NumBodies() * p.DofsPerBody();  // the cell column, if any, is last
  const SparseMatrix h_b = h.leftCols(body_dofs);         // the cell enters through y
  const SparseMatrix w_b =
      h_b * InverseMassDiagonal(p).head(body_dofs).asDiagonal() * h_b.transpose();
  Triplets q;
  for (int col = 0; col < w_b.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(w_b, col); it; ++it) {
      const double v = it.value() / qp.delassus_scale;
      q.emplace_back(static_cast<int>(it.row()), col, v);
      if (it.row() >= col) qp.hessian_lower.emplace_back(static_cast<int>(it.row()), col, v);
    }
  }
  if (p.cell) {
    const double v = p.cell->inv_mass * qp.cell_unit * qp.cell_unit / qp.delassus_scale;
    q.emplace_back(qp.unknowns, qp.unknowns, v);
    qp.hessian_lower.emplace_back(qp.unknowns, qp.unknowns, v);
  }
  qp.hessian.resize(n, n);
  qp.hessian.setFromTriplets(q.begin(), q.end());
  qp.offset = Eigen::VectorXd::Zero(n);
  qp.offset.head(qp.unknowns) = DelassusOffset(p) / qp.delassus_scale;
  Constrain(layout, static_cast<bool>(p.cell), qp);
  return qp;
}

// Q + εI on the impulses: the proximal term ε/2 |x − x₀|² of each convex solve (the linear
// part −ε x₀ is added per solve). See "Why a proximal term" at the top of the file.
ScaledQp WithProximalTerm(ScaledQp qp, double epsilon) {
  if (epsilon == 0.0) return qp;
  SparseMatrix identity(qp.hessian.rows(), qp.hessian.cols());
  Triplets diagonal;
  for (int i = 0; i < qp.unknowns; ++i) diagonal.emplace_back(i, i, epsilon);
  identity.setFromTriplets(diagonal.begin(), diagonal.end());
  qp.hessian = SparseMatrix(qp.hessian + identity);
  qp.hessian_lower.clear();
  for (int col = 0; col < qp.hessian.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(qp.hessian, col); it; ++it) {
      if (it.row() >= col)
        qp.hessian_lower.emplace_back(static_cast<int>(it.row()), col, it.value());
    }
  }
  return qp;
}

// The Delassus form: Q = ½(W + Wᵀ) / w̄ (W symmetric to kSymmetryTolerance, AsymmetryOf),
// offset q / w̄, no cell variable.
ScaledQp MakeScaledQp(const DelassusProblem& p) {
  const ContactLayout layout = LayoutOf(p);
  ScaledQp qp;
  qp.unknowns = p.NumUnknowns();
  qp.delassus_scale = DelassusScale(layout);
  const SparseMatrix w = p.w;
  const SparseMatrix wt = w.transpose();
  const SparseMatrix symmetric = 0.5 * (w + wt) / qp.delassus_scale;
  Triplets q;
  for (int col = 0; col < symmetric.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(symmetric, col); it; ++it) {
      q.emplace_back(static_cast<int>(it.row()), col, it.value());
      if (it.row() >= col)
        qp.hessian_lower.emplace_back(static_cast<int>(it.row()), col, it.value());
    }
  }
  qp.hessian.resize(qp.unknowns, qp.unknowns);
  qp.hessian.setFromTriplets(q.begin(), q.end());
  qp.offset = p.q / qp.delassus_scale;
  Constrain(layout, false, qp);
  return qp;
}

class ConvexQpTnlp : public Ipopt::TNLP {
 public:
  ConvexQpTnlp(const ScaledQp& qp, Eigen::VectorXd linear, Eigen::VectorXd start, double time_limit)
      : qp_(qp), linear_(std::move(linear)), start_(std::move(start)), solution_(start_),
        deadline_(time_limit) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_hess,
                    IndexStyleEnum& style) override {
    n = qp_.Variables();
    m = static_cast<Index>(qp_.g_lower.size());
    nnz_jac = static_cast<Index>(qp_.row_entries.size());
    nnz_hess = static_cast<Index>(qp_.hessian_lower.size());
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
    std::copy_n(qp_.x_lower.data(), n, xl);
    std::copy_n(qp_.x_upper.data(), n, xu);
    std::copy_n(qp_.g_lower.data(), m, gl);
    std::copy_n(qp_.g_upper.data(), m, gu);
    return true;
  }
  bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool,
                          Number*) override {
    std::copy_n(start_.data(), n, x);
    return true;
  }
  bool eval_f(Index n, const Number* x, bool, Number& f) override {
    const Eigen::Map<const Eigen::VectorXd> v(x, n);
    f = 0.5 * v.dot(qp_.hessian * v) + linear_.dot(v);
    return true;
  }
  bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
    const Eigen::Map<const Eigen::VectorXd> v(x, n);
    Eigen::Map<Eigen::VectorXd>(g, n) = qp_.hessian * v + linear_;
    return true;
  }
  bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
    Eigen::Map<Eigen::VectorXd>(g, m) = qp_.rows * Eigen::Map<const Eigen::VectorXd>(x, n);
    return true;
  }
  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index* irow, Index* jcol,
                  Number* values) override {
    for (std::size_t e = 0; e < qp_.row_entries.size(); ++e) {
      if (values == nullptr) {
        irow[e] = qp_.row_entries[e].row();
        jcol[e] = qp_.row_entries[e].col();
      } else {
        values[e] = qp_.row_entries[e].value();
      }
    }
    return true;
  }
  bool eval_h(Index, const Number*, bool, Number obj_factor, Index, const Number*, bool, Index,
              Index* irow, Index* jcol, Number* values) override {
    // The rows are linear: only the objective has curvature.
    for (std::size_t e = 0; e < qp_.hessian_lower.size(); ++e) {
      if (values == nullptr) {
        irow[e] = qp_.hessian_lower[e].row();
        jcol[e] = qp_.hessian_lower[e].col();
      } else {
        values[e] = obj_factor * qp_.hessian_lower[e].value();
      }
    }
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    solution_ = Eigen::Map<const Eigen::VectorXd>(x, n);
  }
  // Ipopt 3.11 has no wall-clock limit of its own: the solve's deadline stops it here
  // (User_Requested_Stop).
  bool intermediate_callback(Ipopt::AlgorithmMode, Index, Number, Number, Number, Number, Number,
                             Number, Number, Number, Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override {
    return !deadline_.Passed();
  }
  const Eigen::VectorXd& solution() const { return solution_; }
  bool TimedOut() const { return deadline_.Passed(); }

 private:
  const ScaledQp& qp_;
  Eigen::VectorXd linear_;
  Eigen::VectorXd start_;
  Eigen::VectorXd solution_;
  solvers_internal::Deadline deadline_;
};

const char* StatusName(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates: return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop: return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found: return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom: return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition: return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option: return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected: return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception: return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown: return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory: return "Insufficient_Memory";
    case Ipopt::Internal_Error: return "Internal_Error";
  }
  return "unknown status";
}

template <class Problem>
class IpoptStep final : public ConvexStepSolver {
 public:
  IpoptStep(const Problem& p, const SolverOptions& o)
      : p_(p), proximal_(o.de_saxce.convex_relaxation ? 0.0 : kProximalWeight),
        qp_(WithProximalTerm(MakeScaledQp(p), proximal_)), app_(IpoptApplicationFactory()) {
    Ipopt::OptionsList& options = *app_->Options();
    options.SetIntegerValue("print_level", 0);
    options.SetStringValue("sb", "yes");
    options.SetStringValue("hessian_constant", "yes");
    options.SetStringValue("jac_c_constant", "yes");
    options.SetStringValue("jac_d_constant", "yes");
    options.SetStringValue("mehrotra_algorithm", "yes");
    options.SetIntegerValue("max_iter", o.ipopt.max_iterations);
    // "": no ipopt.opt from the working directory; results must not depend on where unjam runs.
    initialized_ = app_->Initialize("") == Ipopt::Solve_Succeeded;
  }

  ConvexStep Solve(const Eigen::VectorXd& shift, const Eigen::VectorXd& start, double tolerance,
                   double time_limit) override {
    ConvexStep out;
    out.impulses = start;
    if (!initialized_) {
      out.library_status = "Ipopt could not be initialised";
      return out;
    }
    SetTolerance(tolerance);
    const double scale = ComputeResidual(p_, start).scale;  // S
    Eigen::VectorXd linear = qp_.offset / scale;
    linear.head(qp_.unknowns) += shift / (scale * qp_.delassus_scale);
    const Eigen::VectorXd x0 = ScaledStart(start, scale);
    linear.head(qp_.unknowns) -= proximal_ * x0.head(qp_.unknowns);
    Ipopt::SmartPtr<ConvexQpTnlp> tnlp = new ConvexQpTnlp(qp_, linear, x0, time_limit);
    const Ipopt::ApplicationReturnStatus status = app_->OptimizeTNLP(tnlp);
    if (Ipopt::IsValid(app_->Statistics())) out.iterations = app_->Statistics()->IterationCount();
    out.impulses = scale * tnlp->solution().head(qp_.unknowns);
    out.solved = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
    out.failure = status == Ipopt::Maximum_Iterations_Exceeded ||
                          status == Ipopt::Maximum_CpuTime_Exceeded ||
                          (status == Ipopt::User_Requested_Stop && tnlp->TimedOut())
                      ? SolveStatus::kIterationLimit
                      : SolveStatus::kNumericalFailure;
    out.library_status = std::string("Ipopt ") + StatusName(status);
    return out;
  }

  std::string IterationName() const override { return "Ipopt iterations"; }
  bool Proximal() const override { return proximal_ > 0.0; }

 private:
  // Ipopt's own tolerances on the scaled problem, not below 1e-13: its KKT error stalls
  // near 5e-14 on rounding (measured), and asking for less runs it to its iteration limit.
  // Complementarity needs far more, and costs nothing: the barrier leaves an impulse
  // r_n ≈ (r_n ũ_n)/ũ_n on an open contact, large where the gap is nearly closed (small
  // ũ_n), which moves the neighbours once zeroed; and a degenerate contact (closed, no
  // force: r_n = ũ_n = 0 at the solution) keeps both near √(r_n ũ_n). Measured from cold on
  // the bundled N = 500 packings, complementarity target (× the inner tolerance) against
  // the residual reached: 1e-6 leaves 2.5e-12 on the frictional one (tolerance 1e-12,
  // stalled) and 8e-10 on the frictionless one from its stored forces; 1e-12 reaches
  // 1.2e-15 on both, in as many Ipopt iterations. The barrier floor and the bound
  // relaxation (default 1e-8) follow, so that neither limits the accuracy.
  void SetTolerance(double tolerance) {
    Ipopt::OptionsList& options = *app_->Options();
    const double kkt = std::max(tolerance, kToleranceFloor);
    options.SetNumericValue("tol", kkt);
    options.SetNumericValue("dual_inf_tol", kkt);
    options.SetNumericValue("constr_viol_tol", kkt);
    options.SetNumericValue("acceptable_tol", 10.0 * kkt);
    options.SetNumericValue("compl_inf_tol", 1e-12 * tolerance);
    options.SetNumericValue("mu_min", std::min(1e-11, 1e-14 * tolerance));
    options.SetNumericValue("bound_relax_factor", std::min(1e-8, 0.01 * tolerance));
  }

  Eigen::VectorXd ScaledStart(const Eigen::VectorXd& impulses, double scale) const {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(qp_.Variables());
    x.head(qp_.unknowns) = impulses / scale;
    if (qp_.Variables() > qp_.unknowns)
      x[qp_.unknowns] = qp_.cell_arms.dot(x.head(qp_.unknowns)) / qp_.cell_unit;  // y = cᵀ r_n
    return x;
  }

  const Problem& p_;
  const double proximal_;  // ε of the proximal term (0 for the convex relaxation)
  const ScaledQp qp_;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app_;
  bool initialized_ = false;
};

// See IpoptSolver::DoSolve.
std::mutex& MumpsLock() {
  static std::mutex mumps;
  return mumps;
}

}  // namespace

SolveResult IpoptSolver::DoSolve(const ContactProblem& p, const SolverOptions& options,
                                 const SolverGuess& guess) {
  // MUMPS is not thread-safe, and Ipopt 3.11 does not guard it (3.14 added a mutex), while
  // perturb solves in parallel threads: one Ipopt solve at a time in the process, from the
  // creation of the application (MUMPS instances live in it) to its destruction.
  const std::lock_guard<std::mutex> lock(MumpsLock());
  IpoptStep<ContactProblem> step(p, options);
  return SolveByDeSaxceFixedPoint(p, options, guess, Name(), step);
}

SolveResult IpoptSolver::DoSolveDelassus(const DelassusProblem& p, const SolverOptions& options,
                                         const SolverGuess& guess) {
  const std::string not_convex = NotConvexOf(p);
  if (!not_convex.empty()) return Unsupported(p, Name(), not_convex);
  const std::lock_guard<std::mutex> lock(MumpsLock());
  IpoptStep<DelassusProblem> step(p, options);
  return SolveByDeSaxceFixedPoint(p, options, guess, Name(), step);
}

}  // namespace unjam
