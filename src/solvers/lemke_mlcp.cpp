#include "lemke_mlcp.hpp"
#include "deadline.hpp"
#include "splitmix64.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/UmfPackSupport>

namespace unjam::lemke_internal {

const char* ToString(LemkeOutcome outcome) {
  switch (outcome) {
    case LemkeOutcome::kSolved: return "solved";
    case LemkeOutcome::kRay: return "ray";
    case LemkeOutcome::kCycle: return "cycle";
    case LemkeOutcome::kPivotLimit: return "pivot-limit";
    case LemkeOutcome::kSingularBasis: return "singular-basis";
  }
  return "?";
}

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// Refactorise after this many product-form updates: each update costs one pass over a
// dense vector per solve, and round-off grows with their number.
constexpr int kRefactorInterval = 200;

// The variables, numbered: free x_f = f, w_i = nf + i, z_i = nf + n + i, z₀ = nf + 2n.
// The constraint matrix, one column per variable, rows (free rows; complementarity rows):
//   x_f: (e_f; −D e_f)   w_i: (0; e_i)   z_i: (−P e_i; −E e_i)   z₀: (0; −1)
// with right-hand side (x0; e).
class Tableau {
 public:
  explicit Tableau(const Mlcp& p) : nf_(p.NumFree()), n_(p.NumComplementary()) {
    std::vector<Eigen::Triplet<double>> t;
    for (int f = 0; f < nf_; ++f) t.emplace_back(f, f, 1.0);
    AddBlock(t, p.d, nf_, 0, -1.0);
    for (int i = 0; i < n_; ++i) t.emplace_back(nf_ + i, nf_ + i, 1.0);
    AddBlock(t, p.p, 0, nf_ + n_, -1.0);
    AddBlock(t, p.e_matrix, nf_, nf_ + n_, -1.0);
    columns_.resize(Rows(), Z0());
    columns_.setFromTriplets(t.begin(), t.end());
    rhs_.resize(Rows());
    rhs_ << p.x0, p.e;
    if (p.perturbation.size() == n_) rhs_.tail(n_) += p.perturbation;
    z0_column_ = Eigen::VectorXd::Zero(Rows());
    z0_column_.tail(n_).setConstant(-1.0);  // covering vector 1
  }
  int Rows() const { return nf_ + n_; }
  int Z0() const { return nf_ + 2 * n_; }
  int W(int i) const { return nf_ + i; }
  int Z(int i) const { return nf_ + n_ + i; }
  bool IsFree(int var) const { return var < nf_; }
  int Complement(int var) const { return var < nf_ + n_ ? var + n_ : var - n_; }
  const Eigen::VectorXd& Rhs() const { return rhs_; }
  // The polish: the right-hand side of the unperturbed problem.
  void RemovePerturbation(const Mlcp& p) { rhs_.tail(n_) = p.e; }
  Eigen::VectorXd Column(int var) const {
    return var == Z0() ? z0_column_ : Eigen::VectorXd(columns_.col(var));
  }
  SparseMatrix Basis(const std::vector<int>& basic) const {
    std::vector<Eigen::Triplet<double>> t;
    for (int pos = 0; pos < Rows(); ++pos) {
      if (basic[pos] == Z0()) {
        for (int row = 0; row < Rows(); ++row) {
          if (z0_column_[row] != 0.0) t.emplace_back(row, pos, z0_column_[row]);
        }
        continue;
      }
      for (SparseMatrix::InnerIterator it(columns_, basic[pos]); it; ++it)
        t.emplace_back(it.row(), pos, it.value());
    }
    SparseMatrix b(Rows(), Rows());
    b.setFromTriplets(t.begin(), t.end());
    return b;
  }

 private:
  static void AddBlock(std::vector<Eigen::Triplet<double>>& t, const SparseMatrix& m, int row0,
                       int col0, double sign) {
    for (int k = 0; k < m.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(m, k); it; ++it)
        t.emplace_back(row0 + it.row(), col0 + it.col(), sign * it.value());
    }
  }
  int nf_, n_;
  SparseMatrix columns_;  // all but z₀
  Eigen::VectorXd z0_column_;
  Eigen::VectorXd rhs_;
};

// B⁻¹ as an LU factorisation of the basis at the last refactorisation followed by the
// eta matrices of the pivots since. The first `free_rows` positions hold the free variables,
// which never leave the basis, so no pivot is at them: the etas keep only the rows below,
// and a solve updates only those (its first `free_rows` values are the factorisation's
// alone, and no caller reads them between refactorisations). The rows that are kept come
// out bit for bit as with whole etas, in a third less memory traffic on the piles.
class BasisInverse {
 public:
  explicit BasisInverse(int free_rows) : free_rows_(free_rows) {}
  bool Factorise(const SparseMatrix& basis) {
    basis_ = basis;
    basis_.makeCompressed();
    lu_ = std::make_unique<Eigen::UmfPackLU<SparseMatrix>>();
    // No iterative refinement inside every solve (UMFPACK's default is 2 steps, each a
    // product and a solve): the path needs only the pivot signs, and the final basis is
    // refined once (Finish).
    lu_->umfpackControl()(UMFPACK_IRSTEP) = 0;
    lu_->compute(basis_);
    etas_.clear();
    return lu_->info() == Eigen::Success;
  }
  Eigen::VectorXd Solve(const Eigen::VectorXd& v) const {
    Eigen::VectorXd y = lu_->solve(v);
    const Eigen::Index bounded = y.size() - free_rows_;
    for (const Eta& eta : etas_) {
      const double yr = y[eta.position] / eta.column[eta.position - free_rows_];
      if (yr != 0.0) y.tail(bounded) -= yr * eta.column;
      y[eta.position] = yr;
    }
    return y;
  }
  void Update(int position, const Eigen::VectorXd& column) {
    etas_.push_back({position, column.tail(column.size() - free_rows_)});
  }
  int Updates() const { return static_cast<int>(etas_.size()); }
  const SparseMatrix& Matrix() const { return basis_; }

 private:
  struct Eta {
    int position;
    Eigen::VectorXd column;  // rows free_rows_ and below
  };
  int free_rows_;
  SparseMatrix basis_;
  std::unique_ptr<Eigen::UmfPackLU<SparseMatrix>> lu_;
  std::vector<Eta> etas_;
};

class Lemke {
 public:
  Lemke(const Mlcp& p, double tie_tolerance)
      : problem_(p), tab_(p), nf_(p.NumFree()), n_(p.NumComplementary()),
        tie_tolerance_(tie_tolerance), inverse_(nf_) {}

  LemkeResult Run(int max_pivots, const solvers_internal::Deadline& deadline) {
    basic_.resize(tab_.Rows());
    for (int f = 0; f < nf_; ++f) basic_[f] = f;
    for (int i = 0; i < n_; ++i) basic_[nf_ + i] = tab_.W(i);
    if (!Refactorise()) return Fail(LemkeOutcome::kSingularBasis, "the initial basis is singular");
    if (n_ == 0) return Finish();
    if (!problem_.given_basis.empty()) return SolveGivenBasis();
    // β = B⁻¹ rhs are the basic values at z₀ = 0, and they rise by B⁻¹d per unit of z₀.
    const Eigen::VectorXd rise = -inverse_.Solve(tab_.Column(tab_.Z0()));
    int row = FirstBlockingRow(rise);
    if (row == -2) return Fail(LemkeOutcome::kSingularBasis, "the covering vector does not cover");
    if (row < 0) return Finish();
    int entering = tab_.Z0();
    Eigen::VectorXd alpha = -rise;
    while (true) {
      const int leaving = basic_[row];
      Pivot(row, entering, std::move(alpha));
      if (leaving == tab_.Z0()) return Finish();
      basis_hash_ ^= VariableKey(leaving) ^ VariableKey(entering);
      if (++visits_[basis_hash_] > kVisitsOfACycle) {
        return Fail(LemkeOutcome::kCycle, "a basis came back " + std::to_string(kVisitsOfACycle) +
                                              " times: the path cycles");
      }
      if (result_.pivots >= max_pivots)
        return Fail(LemkeOutcome::kPivotLimit, "pivot limit reached");
      if (deadline.Passed()) return Fail(LemkeOutcome::kPivotLimit, "time limit reached");
      if (inverse_.Updates() >= kRefactorInterval && !Refactorise()) {
        return Fail(LemkeOutcome::kSingularBasis, "a basis became numerically singular");
      }
      entering = tab_.Complement(leaving);
      alpha = inverse_.Solve(tab_.Column(entering));
      row = RatioTest(alpha);
      if (row < 0)
        return Fail(LemkeOutcome::kRay, "ray termination: no complementary solution on the path");
    }
  }

 private:
  // The row where z₀ enters: the basic variable that reaches zero last as z₀ decreases
  // from +∞; ties go to the largest index (the perturbation ε^i is smallest). −1: the
  // basis is already feasible at z₀ = 0; −2: a negative value that z₀ does not lift.
  int FirstBlockingRow(const Eigen::VectorXd& rise) const {
    int row = -1;
    double level = 0.0;
    for (int pos = nf_; pos < tab_.Rows(); ++pos) {
      if (beta_[pos] >= 0.0) continue;
      if (rise[pos] <= 0.0) return -2;
      const double z0 = -beta_[pos] / rise[pos];
      if (row < 0 || z0 >= level) row = pos, level = z0;
    }
    return row;
  }

  // Mlcp::given_basis, solved as it is.
  LemkeResult SolveGivenBasis() {
    if (static_cast<int>(problem_.given_basis.size()) != n_)
      return Fail(LemkeOutcome::kSingularBasis, "the given basis has the wrong size");
    for (int i = 0; i < n_; ++i) basic_[nf_ + i] = problem_.given_basis[i] ? tab_.Z(i) : tab_.W(i);
    if (!Refactorise()) return Fail(LemkeOutcome::kSingularBasis, "the given basis is singular");
    if (Finish().outcome != LemkeOutcome::kSolved) return result_;
    result_.polish_violation = std::max(0.0, -beta_.tail(n_).minCoeff());
    return result_;
  }

  // Zobrist keys (splitmix64 of the variable's index): the basis's hash is the XOR of the
  // keys of its variables, so a pivot updates it in O(1). A collision among the at most
  // 10⁶ bases of a run has probability below 10⁻⁷.
  static std::uint64_t VariableKey(int variable) {
    return solvers_internal::SplitMix64Hash(static_cast<std::uint64_t>(variable));
  }

  bool Refactorise() {
    ++result_.factorisations;
    if (!inverse_.Factorise(tab_.Basis(basic_))) return false;
    beta_ = inverse_.Solve(tab_.Rhs());
    return beta_.allFinite();
  }

  void Pivot(int row, int entering, Eigen::VectorXd alpha) {
    // (The first pivot, z₀ entering, has α < 0 and β < 0 in its row.)
    const double t =
        alpha[row] > 0.0 ? std::max(beta_[row], 0.0) / alpha[row] : beta_[row] / alpha[row];
    beta_.tail(n_) -= t * alpha.tail(n_);  // the free values are recomputed at Finish
    beta_[row] = t;
    basic_[row] = entering;
    inverse_.Update(row, alpha);
    ++result_.pivots;
  }

  // The blocking row of the entering column α, over bounded basic variables with α_p > 0.
  // Harris' two passes: the largest step that leaves no basic value below −δ, then the
  // rows that block within it count as tied (exact degeneracies come out of the solves a
  // few ulps apart). Among them z₀ first (the path ends), then the lexicographic rule.
  // δ = tie_tolerance × the largest basic value.
  int RatioTest(const Eigen::VectorXd& alpha) const {
    double alpha_scale = 0.0, beta_scale = 0.0;
    for (int pos = 0; pos < tab_.Rows(); ++pos) {
      if (tab_.IsFree(basic_[pos])) continue;
      alpha_scale = std::max(alpha_scale, std::abs(alpha[pos]));
      beta_scale = std::max(beta_scale, std::abs(beta_[pos]));
    }
    const double pivot_tolerance = 1e-11 * alpha_scale;
    const double delta = tie_tolerance_ * beta_scale;
    double step = std::numeric_limits<double>::infinity();
    for (int pos = 0; pos < tab_.Rows(); ++pos) {
      if (tab_.IsFree(basic_[pos]) || alpha[pos] <= pivot_tolerance) continue;
      step = std::min(step, (std::max(beta_[pos], 0.0) + delta) / alpha[pos]);
    }
    if (step == std::numeric_limits<double>::infinity()) return -1;
    std::vector<int> tied;
    for (int pos = 0; pos < tab_.Rows(); ++pos) {
      if (tab_.IsFree(basic_[pos]) || alpha[pos] <= pivot_tolerance) continue;
      if (std::max(beta_[pos], 0.0) / alpha[pos] > step) continue;
      if (basic_[pos] == tab_.Z0()) return pos;
      tied.push_back(pos);
    }
    return Lexicographic(tied, alpha);
  }

  // Among tied rows, the lexicographically smallest row of B⁻¹ (its complementarity
  // columns, in order) divided by α: the rule of the perturbed right-hand side e + (ε, ε², …).
  int Lexicographic(std::vector<int> tied, const Eigen::VectorXd& alpha) const {
    for (int j = 0; j < n_ && tied.size() > 1; ++j) {
      const Eigen::VectorXd column = inverse_.Solve(Eigen::VectorXd::Unit(tab_.Rows(), nf_ + j));
      double best = std::numeric_limits<double>::infinity(), scale = 0.0;
      for (int pos : tied) {
        best = std::min(best, column[pos] / alpha[pos]);
        scale = std::max(scale, std::abs(column[pos] / alpha[pos]));
      }
      std::vector<int> next;
      for (int pos : tied) {
        if (column[pos] / alpha[pos] <= best + 1e-12 * scale) next.push_back(pos);
      }
      tied.swap(next);
    }
    return tied.front();
  }

  LemkeResult Finish() {
    // A fresh factorisation of the final basis and one step of iterative refinement: the
    // answer is that of this basis to round-off, not of the product-form updates.
    // A perturbed run's basis is solved for the given right-hand side (the polish).
    const bool perturbed = problem_.perturbation.size() == n_;
    if (perturbed) tab_.RemovePerturbation(problem_);
    if (!Refactorise()) return Fail(LemkeOutcome::kSingularBasis, "the final basis is singular");
    beta_ += inverse_.Solve(tab_.Rhs() - inverse_.Matrix() * beta_);
    for (int pos = nf_; perturbed && pos < tab_.Rows(); ++pos) {
      result_.polish_violation = std::max(result_.polish_violation, -beta_[pos]);
    }
    result_.outcome = LemkeOutcome::kSolved;
    result_.x = beta_.head(nf_);
    result_.z = Eigen::VectorXd::Zero(n_);
    result_.z_basic.assign(n_, 0);
    for (int pos = 0; pos < tab_.Rows(); ++pos) {
      const int var = basic_[pos];
      if (var >= tab_.Z(0) && var < tab_.Z0()) {
        result_.z[var - tab_.Z(0)] = std::max(0.0, beta_[pos]);
        result_.z_basic[var - tab_.Z(0)] = 1;
      }
    }
    return result_;
  }

  LemkeResult Fail(LemkeOutcome outcome, const std::string& message) {
    result_.outcome = outcome;
    result_.message = message;
    result_.x =
        beta_.size() == tab_.Rows() ? Eigen::VectorXd(beta_.head(nf_)) : Eigen::VectorXd::Zero(nf_);
    result_.z = Eigen::VectorXd::Zero(n_);
    return result_;
  }

  const Mlcp& problem_;
  Tableau tab_;
  int nf_, n_;
  double tie_tolerance_;
  std::uint64_t basis_hash_ = 0;  // of the bases after z₀ entered (the start's is not needed)
  // Visits per basis. In floating point a path may pass a basis twice and then leave it
  // another way (its values differ by round-off, so the ties fall differently), and go on to
  // a solution; kVisitsOfACycle visits are taken as a cycle. Measured: one path of the
  // 400-disk pile's top shifts passed a basis 19 times and then solved the step, so fewer
  // would cost answers; and fewer would save little, since the cycling paths there were
  // detected 80–5 000 pivots after their first repeat, of 11 000–22 000.
  static constexpr int kVisitsOfACycle = 20;
  std::unordered_map<std::uint64_t, int> visits_;
  std::vector<int> basic_;  // the variable basic at each position
  Eigen::VectorXd beta_;    // their values
  BasisInverse inverse_;
  LemkeResult result_;
};

}  // namespace

LemkeResult SolveMlcp(const Mlcp& problem, int max_pivots, double tie_tolerance,
                      double time_limit) {
  return Lemke(problem, tie_tolerance).Run(max_pivots, solvers_internal::Deadline(time_limit));
}

}  // namespace unjam::lemke_internal
