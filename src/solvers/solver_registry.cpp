// The one place where backends are chosen by name, and the shared option rules.
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "ipopt_solver.hpp"
#include "lemke.hpp"
#include "newton.hpp"
#include "nlopt_solver.hpp"
#include "nsgs.hpp"
#include "unjam/solvers/contact_solver.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

const char* ToString(SolveStatus status) {
  switch (status) {
    case SolveStatus::kConverged: return "converged";
    case SolveStatus::kIterationLimit: return "iteration-limit";
    case SolveStatus::kNumericalFailure: return "numerical-failure";
    case SolveStatus::kUnsupported: return "unsupported";
    case SolveStatus::kRelaxedModel: return "relaxed-model";
  }
  return "unknown";
}

const char* ToString(SweepOrder order) {
  switch (order) {
    case SweepOrder::kRandom: return "random";
    case SweepOrder::kForward: return "forward";
    case SweepOrder::kSymmetric: return "symmetric";
    case SweepOrder::kLocal: return "local";
    case SweepOrder::kHeight: return "height";
  }
  return "unknown";
}

SweepOrder SweepOrderFromString(const std::string& name) {
  std::string known;
  for (SweepOrder o : {SweepOrder::kRandom, SweepOrder::kForward, SweepOrder::kSymmetric,
                       SweepOrder::kLocal, SweepOrder::kHeight}) {
    if (name == ToString(o)) return o;
    known += (known.empty() ? "" : ", ") + std::string(ToString(o));
  }
  throw std::invalid_argument("unknown sweep order '" + name + "' (" + known + ")");
}

const char* ToString(NloptAlgorithm algorithm) {
  switch (algorithm) {
    case NloptAlgorithm::kLbfgs: return "lbfgs";
    case NloptAlgorithm::kCcsaq: return "ccsaq";
  }
  return "unknown";
}

NloptAlgorithm NloptAlgorithmFromString(const std::string& name) {
  for (NloptAlgorithm a : {NloptAlgorithm::kLbfgs, NloptAlgorithm::kCcsaq}) {
    if (name == ToString(a)) return a;
  }
  throw std::invalid_argument("unknown NLopt algorithm '" + name + "' (lbfgs, ccsaq)");
}

namespace {
[[noreturn]] void Reject(const std::string& field, double value, const std::string& rule) {
  std::ostringstream os;
  os << "solver option " << field << " = " << value << ": " << rule;
  throw std::invalid_argument(os.str());
}
}  // namespace

void Validate(const SolverOptions& o) {
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
    Reject("tolerance", o.tolerance, "must be a positive finite number");
  if (o.max_iterations < 0) Reject("max_iterations", o.max_iterations, "must be >= 0");
  if (!(o.relaxation > 0.0 && o.relaxation < 2.0))
    Reject("relaxation", o.relaxation, "must lie in (0, 2)");
  if (o.check_interval < 1) Reject("check_interval", o.check_interval, "must be >= 1");
  if (o.threads < 1) Reject("threads", o.threads, "must be >= 1");
  if (o.newton_max_iterations < 0)
    Reject("newton_max_iterations", o.newton_max_iterations, "must be >= 0");
  if (!(o.newton_regularization >= 0.0) || !std::isfinite(o.newton_regularization))
    Reject("newton_regularization", o.newton_regularization, "must be a finite number >= 0");
  if (!(o.newton_warmup_tolerance > 0.0) || !std::isfinite(o.newton_warmup_tolerance))
    Reject("newton_warmup_tolerance", o.newton_warmup_tolerance,
           "must be a positive finite number");
  if (o.ipopt_max_iterations < 0)
    Reject("ipopt_max_iterations", o.ipopt_max_iterations, "must be >= 0");
  if (o.nlopt_max_evaluations < 1)
    Reject("nlopt_max_evaluations", o.nlopt_max_evaluations, "must be >= 1");
  if (!(o.lemke_velocity_scale >= 0.0) || !std::isfinite(o.lemke_velocity_scale))
    Reject("lemke_velocity_scale", o.lemke_velocity_scale, "must be a finite number >= 0");
  if (!(o.lemke_velocity_bound >= 0.0) || !std::isfinite(o.lemke_velocity_bound))
    Reject("lemke_velocity_bound", o.lemke_velocity_bound, "must be a finite number >= 0");
  if (o.lemke_pivots_per_row < 0)
    Reject("lemke_pivots_per_row", o.lemke_pivots_per_row, "must be >= 0");
}

SolveResult ContactSolver::SolveDelassus(const DelassusProblem& p, const SolverOptions& options) {
  Validate(p);
  Validate(options);
  SolveResult result;
  result.impulses = Eigen::VectorXd::Zero(p.NumUnknowns());
  result.report.backend = Name();
  result.report.status = SolveStatus::kUnsupported;
  result.report.residual = ComputeResidual(p, result.impulses).residual;
  result.report.message =
      "backend '" + Name() +
      "' solves body problems only, not Delassus-form (W, q) problems (docs/backends.md)";
  return result;
}

std::vector<std::string> AvailableBackends() {
  return {"nsgs", "newton", "ipopt", "nlopt", "lemke"};
}

std::unique_ptr<ContactSolver> MakeSolver(const std::string& name) {
  if (name == "nsgs") return std::make_unique<NsgsSolver>();
  if (name == "newton") return std::make_unique<NewtonSolver>();
  if (name == "ipopt") return std::make_unique<IpoptSolver>();
  if (name == "nlopt") return std::make_unique<NloptSolver>();
  if (name == "lemke") return std::make_unique<LemkeSolver>();
  std::string known;
  for (const std::string& b : AvailableBackends()) known += (known.empty() ? "" : ", ") + b;
  throw std::invalid_argument("unknown backend '" + name + "' (available: " + known + ")");
}

}  // namespace unjam
