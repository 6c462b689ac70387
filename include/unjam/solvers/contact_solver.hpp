// One small interface for every backend: a ContactProblem in, impulses and a report out.
// Backends never see the scene. ContactSolver::Solve is the one entry point: it checks the
// problem, the options and the guess, runs the backend (DoSolve), and reports the wall time
// and the residual (residual.hpp) of the returned impulses, whatever the backend claims.
// What a solve starts from (SolverGuess) comes beside the problem, not in it, so that one
// problem can be solved from several starts.
//
// A problem may also come in Delassus form (W, q, laws: delassus_problem.hpp), e.g. read
// from another code's file. A backend solves it through DoSolveDelassus if it can; the
// default refuses it with SolveStatus::kUnsupported and a message, so that a backend
// written for body problems needs no change (docs/backends.md has the support table).
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/problem/delassus_problem.hpp"

namespace unjam {

// Friction coefficients up to this count as nearly frictionless: newton starts such a step
// from its frictionless solution (newton.cpp), and `unjam pack --backend auto` gives such
// packings newton steps, as frictionless ones (docs/backends.md, docs/performance.md).
inline constexpr double kNearlyFrictionless = 1e-4;

// kRelaxedModel: the convex relaxation (SolverOptions::de_saxce.convex_relaxation) was
// solved to the tolerance, but its impulses do not obey the exact Coulomb law to it
// (docs/backends.md).
enum class SolveStatus {
  kConverged,
  kIterationLimit,
  kNumericalFailure,
  kUnsupported,
  kRelaxedModel
};
const char* ToString(SolveStatus status);

// kLocal: NSGS renumbers the bodies along the contact graph (Cuthill–McKee) and sorts the
// contacts by their bodies, then sweeps blocks of kLocalBlock neighbouring contacts in a
// random order, each block front to back: random at the scale of blocks, but each block
// reads one small region of memory in sequence (a random order over all contacts waits for
// memory once the contacts outgrow the cache; docs/performance.md).
// kHeight: NSGS sorts the contacts by ProblemContact::height (bottom first) and sweeps
// them up, down, up, …: on a pile the same convergence per sweep as kRandom, at a lower
// cost per sweep (docs/performance.md, "Sweep order of a pile"). Problems without
// heights (all 0, or the Delassus form) are swept as kSymmetric.
enum class SweepOrder { kRandom, kForward, kSymmetric, kLocal, kHeight };
inline constexpr int kLocalBlock = 64;
inline constexpr int kParallelContacts = 1000;
const char* ToString(SweepOrder order);
SweepOrder SweepOrderFromString(const std::string& name);  // throws std::invalid_argument

// NLopt algorithms the nlopt backend offers for its bound-constrained convex step.
enum class NloptAlgorithm { kLbfgs, kCcsaq };  // NLOPT_LD_LBFGS, NLOPT_LD_CCSAQ
const char* ToString(NloptAlgorithm algorithm);
NloptAlgorithm NloptAlgorithmFromString(const std::string& name);  // throws std::invalid_argument

// NSGS: the nsgs backend, and newton's NSGS warm-up (which reads every field but
// max_sweeps; NewtonParameters::warmup_max_sweeps bounds it).
struct NsgsParameters {
  int max_sweeps = 100000;  // sweeps over all contacts
  // Over-relaxation factor in (0, 2); 1 = plain Gauss–Seidel.
  double relaxation = 1.0;
  SweepOrder order = SweepOrder::kRandom;
  std::uint64_t seed = 1;  // random sweep order
  // The true residual is evaluated every `check_interval` sweeps (it costs a sweep).
  int check_interval = 10;
  // On body problems: threads that sweep at once (nsgs_domains.hpp). Each takes one
  // domain of the contact graph; the contacts between domains are swept after them. The
  // answer is deterministic for a given thread count, and threads = 1 is plain NSGS.
  // Problems below kParallelContacts contacts are swept on one thread whatever this says.
  int threads = 1;
  // Throws std::invalid_argument naming the field, the value and the rule.
  void Validate() const;
};

// Newton (newton.cpp).
struct NewtonParameters {
  // Iteration limit (each one a sparse LU factorisation), the smallest proximal
  // regularisation ε of sticking rows relative to the local Delassus diagonal, and the
  // residual to which NSGS warms up before the first Newton step (newton.cpp).
  int max_iterations = 200;
  double regularization = 1e-10;
  double warmup_tolerance = 1e-5;
  // Sweeps of its NSGS warm-up (the limit of each round's warm-up; newton.cpp).
  int warmup_max_sweeps = 100000;
  // From the guess (SolverGuess::impulses), up to 30 Newton iterations alone before the NSGS
  // warm-up (the probe). On a perturbation the warm start, the static forces, is often
  // within Newton's reach; in time stepping the previous step's impulses are not
  // (measured: 1.6x the time per step on a frictionless N = 200 packing). Set by the
  // perturbation protocol; off elsewhere.
  bool warm_probe = false;
  void Validate() const;  // as NsgsParameters::Validate
};

// The De Saxcé fixed point of ipopt and nlopt (de_saxce.hpp).
struct DeSaxceParameters {
  // Outer iterations of the fixed point (one convex solve each).
  int max_outer_iterations = 100000;
  // Solve the convex relaxation once (no De Saxcé shift) instead of the exact Coulomb law.
  // A different physical model: sliding contacts separate (docs/backends.md).
  bool convex_relaxation = false;
  void Validate() const;  // as NsgsParameters::Validate
};

// ipopt's convex solves.
struct IpoptParameters {
  // Interior-point iterations allowed to one convex solve (Ipopt's max_iter).
  int max_iterations = 1000;
  void Validate() const;  // as NsgsParameters::Validate
};

// nlopt's convex solves.
struct NloptParameters {
  // The algorithm, and the objective-and-gradient evaluations allowed to one convex solve
  // (NLopt's maxeval; one evaluation is two sparse products with the Jacobian).
  NloptAlgorithm algorithm = NloptAlgorithm::kLbfgs;
  int max_evaluations = 200000;
  void Validate() const;  // as NsgsParameters::Validate
};

// lemke (lemke.cpp).
struct LemkeParameters {
  // Pivots over all its runs.
  int max_pivots = 100000;
  // The velocity scale of the answer, which sizes the perturbed runs' perturbation
  // (lemke.cpp); 0: the largest |velocity offset| of the problem. A perturbation sets ξ/Δt.
  double velocity_scale = 0.0;
  // The pivots per complementarity row that each of its runs may take before the next run
  // is tried (all runs together stay within max_pivots); 0: 20, and 200 in the rate form
  // (lemke.cpp).
  int pivots_per_row = 0;
  void Validate() const;  // as NsgsParameters::Validate
};

// What a solve is asked for: the tolerance every backend reads, and each backend's own
// parameters, which the other backends ignore.
struct SolverOptions {
  double tolerance = 1e-10;  // on the unjam residual (docs/residual.md)
  // Wall-clock seconds the solve may take (`--max-seconds`): at the limit the backend
  // returns its best iterate with status kIterationLimit and a message that says so.
  // Infinite: no limit.
  double time_limit = std::numeric_limits<double>::infinity();
  NsgsParameters nsgs;
  NewtonParameters newton;
  DeSaxceParameters de_saxce;  // ipopt and nlopt
  IpoptParameters ipopt;
  NloptParameters nlopt;
  LemkeParameters lemke;
  // One iteration limit for whichever backend runs (`--max-iter`): NSGS sweeps, the sweeps
  // of newton's NSGS warm-up, the De Saxcé outer iterations of ipopt and nlopt, and lemke's
  // pivots over all its runs.
  void SetIterationLimit(int n);
};
// Throws std::invalid_argument naming the option, the value and the rule: the tolerance,
// then each backend's parameters in turn (their Validate).
void Validate(const SolverOptions& options);

struct SolveReport {
  SolveStatus status = SolveStatus::kNumericalFailure;
  bool converged() const { return status == SolveStatus::kConverged; }
  std::string backend;
  std::string message;
  int iterations = 0;
  double residual = 0.0;  // the unjam residual of the returned impulses
  double seconds = 0.0;
  std::int64_t contact_updates = 0;  // NSGS: local solves performed
};

struct SolveResult {
  Eigen::VectorXd
      impulses;  // UnknownsPerContact() per contact: (r_n[, r_t]); 2 per contact in W form
  SolveReport report;
  // Pivoting backends (lemke): per contact, which of its complementarity variables the
  // answer's basis holds (SolverGuess::basis), the basis the path ended on or,
  // for an answer that is no one basis's solution, the one its stick/slide/open pattern
  // implies; empty from other backends.
  std::vector<std::uint8_t> basis;
};

// Where a solve starts (as Drake's SolveWithGuess). Both fields may be empty: a cold start.
struct SolverGuess {
  // Impulses to start from, NumUnknowns() of them (the previous step's, or the static
  // forces before a perturbation); empty: zero impulses.
  Eigen::VectorXd impulses;
  // For pivoting backends (lemke, which solves it first as it is; the others ignore it):
  // per contact, the basis of a previous answer (SolveResult::basis), bit k set if the
  // k-th complementarity variable of the contact's law (lemke.cpp: r_n, a, b, s; p, m if
  // bilateral; r_n if frictionless) is basic. The answer at gap ξ passes it to the step at
  // 10ξ, whose contacts are the same. Empty: none.
  std::vector<std::uint8_t> basis;
};

class ContactSolver {
 public:
  virtual ~ContactSolver() = default;
  virtual std::string Name() const = 0;
  // Raised when a change of the backend changes which answer it gives to the same problem
  // (not its accuracy), so that results saved by an earlier version are not mixed with
  // new ones (`perturb -o DIR` refuses to resume them). 1 for a backend never changed so.
  virtual int AnswerRevision() const { return 1; }
  // Throws std::invalid_argument for an inconsistent problem (Validate(ContactProblem)),
  // options (Validate(SolverOptions)) or guess (sizes other than empty or the problem's);
  // report.seconds times the backend alone, and report.residual is ComputeResidual's of
  // the returned impulses.
  SolveResult Solve(const ContactProblem& problem, const SolverOptions& options,
                    const SolverGuess& guess = {});
  // The same laws posed on ũ = W r + q, checked by Validate(DelassusProblem), timed and
  // judged as Solve. A backend without this form answers status kUnsupported, zero
  // impulses and a message naming the backend.
  SolveResult SolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                            const SolverGuess& guess = {});

 protected:
  // The backend proper, on a problem, options and guess already checked (a guess is empty
  // or of the problem's size). It fills the impulses (NumUnknowns() of them), the basis
  // and the report; the entry point overwrites the report's residual and seconds.
  virtual SolveResult DoSolve(const ContactProblem& problem, const SolverOptions& options,
                              const SolverGuess& guess) = 0;
  // Default: the refusal described at SolveDelassus.
  virtual SolveResult DoSolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                                      const SolverGuess& guess);
};

// The one place where backends are chosen by name. Throws std::invalid_argument for an
// unknown name, listing the known ones.
std::unique_ptr<ContactSolver> MakeSolver(const std::string& name);
std::vector<std::string> AvailableBackends();

}  // namespace unjam
