// Perturbations decided before their step is solved: blocked (no motion obeys the step's
// non-penetration) or dynamic (no answer can end near rest: the inertia LP).
#include <chrono>
#include <cmath>
#include <cstdio>

#include "perturbation_internal.hpp"
#include "unjam/problem/inertia_bound.hpp"

namespace unjam {
namespace perturbation_internal {

// A perturbation decided before any solve: no force is measured (F_crit is NaN) and nothing
// moves. `decided_by` is reported as its backend, `why` as its message.
PerturbationResult DecidedWithoutSolving(const PerturbationBase& base,
                                         const std::string& decided_by, const std::string& why,
                                         PerturbationResult r, Clock::time_point start) {
  const std::size_t n = base.scene.particles.size();
  r.f_crit = std::nan("");
  r.displacement.assign(n, Vec2::Zero());
  r.rotation.assign(n, 0.0);
  r.solve.backend = decided_by;
  r.solve.message = why;
  r.quasi_static = false;
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

PerturbationResult Blocked(const PerturbationBase& base, const std::string& decided_by,
                           const std::string& why, PerturbationResult r, Clock::time_point start) {
  r.solve.status = SolveStatus::kNumericalFailure;
  r.resolved = false;
  r.status = PerturbationStatus::kBlocked;
  return DecidedWithoutSolving(base, decided_by, why, std::move(r), start);
}

namespace {
// The LP's bound is known to CLP's tolerance, 1e-9 in its units; a bound this many times
// above the threshold leaves no doubt (on the dynamic openings measured it is 1e-4 to 2e-2).
constexpr double kDynamicBoundFactor = 10.0;

// The contact of each problem contact of a posed step, in the problem's order.
std::vector<Contact> ProblemContacts(const StaticProblem& posed) {
  std::vector<Contact> out;
  for (int source : posed.assembled.source_contact) out.push_back(posed.contacts[source]);
  return out;
}

bool SameContacts(const std::vector<Contact>& a, const std::vector<Contact>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].i != b[k].i || a[k].j != b[k].j || a[k].image != b[k].image) return false;
  }
  return true;
}

// The inertia LP's bound for a posed contact opening: continued from the unperturbed LP
// (solved once per base) where the step has the unperturbed step's contacts, otherwise
// solved from scratch.
InertiaBound StepInertiaBound(const PerturbationBase& base, const StaticProblem& posed,
                              const PerturbationOptions& options) {
  const ContactProblem& p = posed.assembled.problem;
  if (IsUnloaded(p))
    return {};  // fixed volume: zero forces balance it, and the shared LP is not this step's
  OpeningInertiaLp* shared = base.opening_inertia_lp.get();
  if (shared != nullptr) {
    std::call_once(shared->once, [&] {
      const StaticProblem unperturbed = PoseStaticProblem(base.scene, StepOptions(base, options));
      shared->contacts = ProblemContacts(unperturbed);
      shared->dofs = unperturbed.assembled.problem.NumDofs();
      shared->lp = std::make_unique<HeldContactInertia>(unperturbed.assembled.problem,
                                                        InertiaScales(base, unperturbed.assembled));
    });
    int held = -1;
    for (int k = 0; k < p.NumContacts(); ++k) {
      if (p.contacts[k].kind == ConstraintKind::kBilateral) held = k;
    }
    // The same step but for the held contact (at fixed volume the cell is frozen: another
    // step, and an unloaded one).
    const bool same_step =
        p.NumDofs() == shared->dofs && SameContacts(ProblemContacts(posed), shared->contacts);
    if (held >= 0 && same_step && shared->lp->ready()) return shared->lp->WithHeld(held);
  }
  return SmallestInertia(p, InertiaScales(base, posed.assembled));
}

}  // namespace

// A step that no answer can end near rest: dynamic, decided by the inertia LP, whose bound
// is reported as the inertia ratio (docs/perturbations.md, "Dynamic before solving").
std::optional<PerturbationResult> DynamicBeforeSolving(const PerturbationBase& base,
                                                       const StaticProblem& posed,
                                                       const PerturbationOptions& options,
                                                       const PerturbationResult& r,
                                                       Clock::time_point start) {
  const InertiaBound bound = StepInertiaBound(base, posed, options);
  if (!bound.decided || bound.ratio <= kDynamicBoundFactor * options.max_inertia_ratio)
    return std::nullopt;
  PerturbationResult d = r;
  d.solve.status = SolveStatus::kConverged;
  d.solve.iterations = bound.iterations;
  d.resolved = true;
  d.status = PerturbationStatus::kDynamic;
  d.inertia_ratio = bound.ratio;
  char why[200];
  std::snprintf(why, sizeof why,
                "no impulses in the contact cones keep the largest inertial force below %.3g of "
                "its scale: dynamic, not solved",
                bound.ratio);
  return DecidedWithoutSolving(base, "inertia LP", why, std::move(d), start);
}

}  // namespace perturbation_internal
}  // namespace unjam
