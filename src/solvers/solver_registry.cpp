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

void NsgsParameters::Validate() const {
  if (max_sweeps < 0) Reject("nsgs.max_sweeps", max_sweeps, "must be >= 0");
  if (!(relaxation > 0.0 && relaxation < 2.0))
    Reject("nsgs.relaxation", relaxation, "must lie in (0, 2)");
  if (check_interval < 1) Reject("nsgs.check_interval", check_interval, "must be >= 1");
  if (threads < 1) Reject("nsgs.threads", threads, "must be >= 1");
}

void NewtonParameters::Validate() const {
  if (max_iterations < 0) Reject("newton.max_iterations", max_iterations, "must be >= 0");
  if (!(regularization >= 0.0) || !std::isfinite(regularization))
    Reject("newton.regularization", regularization, "must be a finite number >= 0");
  if (!(warmup_tolerance > 0.0) || !std::isfinite(warmup_tolerance))
    Reject("newton.warmup_tolerance", warmup_tolerance, "must be a positive finite number");
  if (warmup_max_sweeps < 0) Reject("newton.warmup_max_sweeps", warmup_max_sweeps, "must be >= 0");
}

void DeSaxceParameters::Validate() const {
  if (max_outer_iterations < 0)
    Reject("de_saxce.max_outer_iterations", max_outer_iterations, "must be >= 0");
}

void IpoptParameters::Validate() const {
  if (max_iterations < 0) Reject("ipopt.max_iterations", max_iterations, "must be >= 0");
}

void NloptParameters::Validate() const {
  if (max_evaluations < 1) Reject("nlopt.max_evaluations", max_evaluations, "must be >= 1");
}

void LemkeParameters::Validate() const {
  if (max_pivots < 0) Reject("lemke.max_pivots", max_pivots, "must be >= 0");
  if (!(velocity_scale >= 0.0) || !std::isfinite(velocity_scale))
    Reject("lemke.velocity_scale", velocity_scale, "must be a finite number >= 0");
  if (pivots_per_row < 0) Reject("lemke.pivots_per_row", pivots_per_row, "must be >= 0");
}

void SolverOptions::SetIterationLimit(int n) {
  nsgs.max_sweeps = n;
  newton.warmup_max_sweeps = n;
  de_saxce.max_outer_iterations = n;
  lemke.max_pivots = n;
}

void Validate(const SolverOptions& o) {
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
    Reject("tolerance", o.tolerance, "must be a positive finite number");
  if (!(o.time_limit > 0.0)) Reject("time_limit", o.time_limit, "must be positive (seconds)");
  o.nsgs.Validate();
  o.newton.Validate();
  o.de_saxce.Validate();
  o.ipopt.Validate();
  o.nlopt.Validate();
  o.lemke.Validate();
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
