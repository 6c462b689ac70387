#include "ipopt_lp.hpp"

#include <limits>
#include <vector>

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

namespace unjam::indeterminacy_internal {

namespace {

using Ipopt::Index;
using Ipopt::Number;

// The force ensemble as an Ipopt problem over f / F: constraints A f = b / F and
// ±f_t − μ f_n ≤ 0, bounds f_n ≥ 0, objective sign · f_n,k. Linear: zero Hessian.
class ForceLp : public Ipopt::TNLP {
 public:
  ForceLp(const EquilibriumSystem& s, int column, double sign, int fixed) : s_(s), column_(column), sign_(sign), fixed_(fixed) {
    for (int k = 0; k < s.matrix.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(s.matrix, k); it; ++it) {
        rows_.push_back(static_cast<Index>(it.row()));
        cols_.push_back(static_cast<Index>(it.col()));
        values_.push_back(it.value());
      }
    }
    const int cone_rows = s.frictional ? s.NumUnknowns() : 0;  // two per contact
    for (int r = 0; r < cone_rows; ++r) {
      const int k = r / 2;
      const double side = r % 2 == 0 ? 1.0 : -1.0;
      rows_.insert(rows_.end(), {s.NumRows() + r, s.NumRows() + r});
      cols_.insert(cols_.end(), {2 * k + 1, 2 * k});
      values_.insert(values_.end(), {side, -s.mu});
    }
    m_ = s.NumRows() + cone_rows;
  }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_hess, IndexStyleEnum& style) override {
    n = s_.NumUnknowns();
    m = m_;
    nnz_jac = static_cast<Index>(values_.size());
    nnz_hess = 0;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
    const double inf = 1e20;
    const int stride = s_.UnknownsPerContact();
    for (Index c = 0; c < n; ++c) {
      const bool tangential = stride == 2 && c % 2 == 1;
      xl[c] = tangential ? -inf : 0.0;
      xu[c] = inf;
      if (c == fixed_) xl[c] = xu[c] = 0.0;
    }
    for (Index r = 0; r < m; ++r) {
      if (r < s_.NumRows()) gl[r] = gu[r] = s_.load[r] / s_.force_scale;
      else gl[r] = -inf, gu[r] = 0.0;
    }
    return true;
  }
  bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
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
    for (std::size_t e = 0; e < values_.size(); ++e) g[rows_[e]] += values_[e] * x[cols_[e]];
    return true;
  }
  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index* irow, Index* jcol, Number* values) override {
    if (values == nullptr) {
      for (std::size_t e = 0; e < rows_.size(); ++e) irow[e] = rows_[e], jcol[e] = cols_[e];
    } else {
      for (std::size_t e = 0; e < values_.size(); ++e) values[e] = values_[e];
    }
    return true;
  }
  bool eval_h(Index, const Number*, bool, Number, Index, const Number*, bool, Index, Index*, Index*, Number*) override {
    return true;  // linear program: no Hessian entries
  }
  void finalize_solution(Ipopt::SolverReturn, Index, const Number*, const Number*, const Number*, Index,
                         const Number*, const Number*, Number obj, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    objective_ = obj;
  }
  double objective() const { return objective_; }

 private:
  const EquilibriumSystem& s_;
  int column_;
  double sign_;
  int fixed_;
  Index m_ = 0;
  std::vector<Index> rows_, cols_;
  std::vector<double> values_;
  double objective_ = 0.0;
};

}  // namespace

Bound IpoptBound(const EquilibriumSystem& system, int normal_column, double sign, int fixed_tangential,
                 double tolerance, long long& iterations) {
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
    case Ipopt::Infeasible_Problem_Detected:
      b.status = BoundStatus::kInfeasible;
      break;
    case Ipopt::Diverging_Iterates:
      b.status = BoundStatus::kUnbounded;
      break;
    default:
      b.status = BoundStatus::kFailed;
  }
  return b;
}

}  // namespace unjam::indeterminacy_internal
