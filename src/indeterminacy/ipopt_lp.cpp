#include "ipopt_lp.hpp"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include "ensemble_lp.hpp"

namespace unjam::indeterminacy_internal {

namespace {

using Ipopt::Index;
using Ipopt::Number;

// The force ensemble (ensemble_lp.hpp) as an Ipopt problem, objective sign · f_n,k (with
// f_t of contact `fixed` held at 0). Linear: zero Hessian.
class ForceLp : public Ipopt::TNLP {
 public:
  ForceLp(const EquilibriumSystem& s, int column, double sign, int fixed)
      : lp_(EnsembleLp(s)), column_(column), sign_(sign), fixed_(fixed) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_hess,
                    IndexStyleEnum& style) override {
    n = static_cast<Index>(lp_.col_lower.size());
    m = static_cast<Index>(lp_.row_lower.size());
    nnz_jac = static_cast<Index>(lp_.values.size());
    nnz_hess = 0;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
    // Ipopt reads |bounds| ≥ 1e19 as none; the infinities pass as they are.
    for (Index c = 0; c < n; ++c) {
      xl[c] = c == fixed_ ? 0.0 : lp_.col_lower[c];
      xu[c] = c == fixed_ ? 0.0 : lp_.col_upper[c];
    }
    for (Index r = 0; r < m; ++r) {
      gl[r] = lp_.row_lower[r];
      gu[r] = lp_.row_upper[r];
    }
    return true;
  }
  bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool,
                          Number*) override {
    for (Index c = 0; c < n; ++c) x[c] = 0.0;
    return true;
  }
  bool eval_f(Index, const Number* x, bool, Number& f) override {
    f = sign_ * x[column_];
    return true;
  }
  bool eval_grad_f(Index n, const Number*, bool, Number* g) override {
    for (Index c = 0; c < n; ++c) g[c] = 0.0;
    g[column_] = sign_;
    return true;
  }
  bool eval_g(Index, const Number* x, bool, Index m, Number* g) override {
    for (Index r = 0; r < m; ++r) g[r] = 0.0;
    for (std::size_t e = 0; e < lp_.values.size(); ++e)
      g[lp_.rows[e]] += lp_.values[e] * x[lp_.cols[e]];
    return true;
  }
  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index* irow, Index* jcol,
                  Number* values) override {
    if (values == nullptr) {
      for (std::size_t e = 0; e < lp_.rows.size(); ++e)
        irow[e] = lp_.rows[e], jcol[e] = lp_.cols[e];
    } else {
      for (std::size_t e = 0; e < lp_.values.size(); ++e) values[e] = lp_.values[e];
    }
    return true;
  }
  bool eval_h(Index, const Number*, bool, Number, Index, const Number*, bool, Index, Index*, Index*,
              Number*) override {
    return true;  // linear program: no Hessian entries
  }
  void finalize_solution(Ipopt::SolverReturn, Index, const Number*, const Number*, const Number*,
                         Index, const Number*, const Number*, Number obj, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    objective_ = obj;
  }
  double objective() const { return objective_; }

 private:
  LpTriplets lp_;
  int column_;
  double sign_;
  int fixed_;
  double objective_ = 0.0;
};

}  // namespace

Bound IpoptBound(const EquilibriumSystem& system, int normal_column, double sign,
                 int fixed_tangential, double tolerance, long long& iterations) {
  Ipopt::SmartPtr<ForceLp> lp = new ForceLp(system, normal_column, sign, fixed_tangential);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", tolerance);
  app->Options()->SetStringValue("hessian_constant", "yes");
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  app->Options()->SetStringValue("mehrotra_algorithm", "yes");
  app->Options()->SetIntegerValue("max_iter", 1000);
  Bound b;
  if (app->Initialize() != Ipopt::Solve_Succeeded) return b;
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(lp);
  if (Ipopt::IsValid(app->Statistics())) iterations += app->Statistics()->IterationCount();
  switch (status) {
    case Ipopt::Solve_Succeeded:
    case Ipopt::Solved_To_Acceptable_Level:
      b.status = BoundStatus::kOptimal;
      b.value = sign * lp->objective() * system.force_scale;
      break;
    case Ipopt::Infeasible_Problem_Detected: b.status = BoundStatus::kInfeasible; break;
    case Ipopt::Diverging_Iterates: b.status = BoundStatus::kUnbounded; break;
    default: b.status = BoundStatus::kFailed;
  }
  return b;
}

}  // namespace unjam::indeterminacy_internal
