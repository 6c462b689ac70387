// Local perturbations of a static packing, each one contact-dynamics step from the same
// static state (docs/perturbations.md):
//   - contact opening: contact K is held open at a gap ξ (a bilateral, frictionless
//     constraint); every other contact keeps Signorini–Coulomb. The force on K is the
//     critical force F_crit (positive = pushing the two grains apart, like a contact force).
//   - particle shift: particle P is moved by ξ along a direction ŝ (prescribed motion for
//     one step). F_crit = −ŝ·Σ f (the contact forces on P): positive when the packing
//     resists the shift.
// The step is quasi-static: its Δt (default 1) makes the inertial forces m ξ/Δt² negligible
// next to the contact forces, so F_crit does not depend on Δt or ξ, and the displacements
// are proportional to ξ. The step is solved to a tolerance proportional to ξ.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/contacts/contact.hpp"
#include "unjam/problem/contact_problem.hpp"
#include "unjam/protocols/perturbation_status.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/scene/scene.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

// What happens to the periodic cell during a contact opening.
enum class CellCondition { kFixedPressure, kFixedVolume };
const char* ToString(CellCondition condition);
CellCondition CellConditionFromString(const std::string& name);  // throws std::invalid_argument

struct PerturbationOptions {
  double gap = 1e-9;  // ξ, length units
  double dt = 1.0;    // the quasi-static step
  CellCondition cell = CellCondition::kFixedPressure;
  // Contacts are those of the static state with gap < max(margin, 1000 ξ) (a response
  // of size ξ, amplified by lever arms, may close them); gaps below closed_gap_tolerance
  // count as exactly closed (well below ξ).
  double margin = 1e-6;
  double closed_gap_tolerance = 1e-12;
  // "auto" (PerturbationBackend): the rate solve ("rate": the quasi-rigid loading path in
  // the self-stress space, then the step solved exactly on its contact states;
  // docs/perturbations.md, "How a perturbation is solved"); where it gives no definite
  // answer, the whole step is solved by StepBackend. A lemke-only option names lemke.
  std::string backend = "auto";
  // When the backend leaves a step unresolved, it is solved once more by this one
  // (PerturbationFallback): "auto" (where `backend` is "auto": ipopt after lemke, lemke
  // after newton on frictionless steps at fixed pressure, none otherwise), "none", or a
  // backend name. On the μ = 10 packing lemke's paths end on rays on openings
  // that ipopt's De Saxcé fixed point resolves (docs/perturbations.md, "Fallback").
  std::string fallback = "auto";
  SolverOptions solver;  // its tolerance is replaced, see SolverToleranceFor
  // Wanted accuracy of the displacements, as a fraction of ξ (see SolverToleranceFor).
  double response_tolerance = 1e-2;
  double solver_tolerance = 0.0;  // > 0: use this solver tolerance instead
  // The response counts as quasi-static when the largest inertial force m|d|/Δt² is below
  // this fraction of the mean contact force.
  double max_inertia_ratio = 1e-6;
  // The small-gap test, per perturbation: solve every quasi-static response again
  // at 10ξ and keep it only if it is linear in ξ (status "nonlinear" otherwise; see
  // PerturbationResult::linear). Doubles the cost of the quasi-static ones. On by default:
  // on frictional packings one quasi-static response in ten (μ = 0.5) to two in three
  // (μ = 0.1) depends on ξ, and a number that depends on ξ is not a critical force.
  bool check_linearity = true;
  // How the check solves the step at 10ξ. Continued (the default): first on the answer's
  // own basis, its stick/slide/open pattern (lemke; other backends give no basis and
  // solve as at ξ), and only if that does not solve the step at 10ξ as the answer at ξ
  // was solved. A response linear in ξ is then found as the same member of the step's
  // family of solutions. Cold (false): as the answer at ξ was solved, which asks more:
  // that the solver picks the same member at both gaps. On frictional packings it does
  // not for many openings whose answer is linear (docs/perturbations.md).
  bool check_by_continuation = true;
  // Pick the member of the step's family of solutions nearest the static forces among
  // those with the answer's motion pattern (StaticSolveOptions::nearest_member).
  bool nearest_member = false;
};
void Validate(const PerturbationOptions& options);  // throws std::invalid_argument
double DetectionMargin(const PerturbationOptions& options);
// Up to this many force-carrying contacts "auto" gives frictional steps at fixed pressure
// to lemke, above it to newton (perturbation.cpp says why).
inline constexpr std::size_t kLemkeAutoContacts = 2000;
// The backend a perturbation uses: options.backend, or for "auto" the rate solve ("rate"),
// or lemke when a lemke-only option is set.
std::string PerturbationBackend(const PerturbationOptions& options, const Scene& scene);
// The backend that solves the whole step where the rate solve gives no definite answer (or
// options.backend if it names one): lemke on frictional packings of up to
// kLemkeAutoContacts contacts, newton on larger ones, on frictionless ones (exact too, and
// 20× faster) and at fixed volume (where Lemke picks the unloaded solution of a stress
// level that the frozen cell leaves free).
std::string StepBackend(const PerturbationOptions& options, const Scene& scene);
// Whether "auto" leaves a frictional step at fixed pressure to newton only because the
// packing has more than kLemkeAutoContacts contacts (where lemke would resolve what newton
// stalls on, given minutes and a larger budget): the case in which `perturb` names lemke.
bool AutoLeavesLemkeForSize(const PerturbationOptions& options, const Scene& scene);
// The backend of the second solve of an unresolved step, or "" for none: options.fallback
// resolved ("auto", when options.backend is "auto" too: ipopt after lemke, lemke after
// newton on frictionless steps at fixed pressure, none otherwise; a backend the user names
// is not second-guessed).
std::string PerturbationFallback(const PerturbationOptions& options, const Scene& scene);
// options.backend and options.fallback with "auto" resolved for this scene, as every
// command runs them (the fallback first: its "auto" depends on the backend's).
void ResolveBackends(PerturbationOptions& options, const Scene& scene);

// One perturbation's target: a contact (by key) or a particle and a shift direction.
struct PerturbationTarget {
  enum class Kind { kContactOpening, kParticleShift } kind = Kind::kContactOpening;
  int i = -1, j = -1;  // contact: its key; shift: i = the particle
  std::array<int, 2> image = {0, 0};
  Vec2 direction = Vec2(0.0, -1.0);  // shift direction ŝ (unit)
};

struct ContactForceChange {
  int i = -1, j = -1;
  std::array<int, 2> image = {0, 0};
  Vec2 point = Vec2::Zero();     // contact point (periodic: as seen from i)
  Vec2 normal = Vec2(1.0, 0.0);  // from i to j
  Vec2 branch = Vec2::Zero();    // centre-to-centre vector l (periodic image included)
  double normal_before = 0.0, normal_after = 0.0;
  double tangential_before = 0.0, tangential_after = 0.0;
};

struct PerturbationResult {
  PerturbationTarget target;
  Vec2 origin = Vec2::Zero();  // the contact point, or the shifted particle's centre
  Vec2 axis = Vec2(1.0, 0.0);  // the contact normal, or the vertical (0, 1)
  double f_crit = 0.0;
  double f_reference = 0.0;        // F_cont (opening) or F_y, the effective weight (shift)
  std::vector<Vec2> displacement;  // per particle (non-affine part under a pressure bath)
  std::vector<double> rotation;    // per particle
  std::vector<ContactForceChange> force_changes;  // every contact of the union of both states
  double penetration_depth = 0.0;                 // δ = Σ|d_i| |r_i·n| / Σ|d_i|
  double cell_strain = 0.0;                       // λ = ΔL/L (fixed pressure)
  double pressure_change = 0.0;  // P_after − P_before from the virial (periodic cells)
  // The largest inertial force over its scale: max_i m_i |d_i| / Δt² over the mean contact
  // force F̄, I_i |θ_i| / Δt² over F̄ R_i, and the cell's M_λ D V |ε| / Δt² over D V P_ext.
  double inertia_ratio = 0.0;
  // The part of F_crit that accelerates the grains and the cell: [Σ (m_i |d_i|² + I_i θ_i²)
  // + M_λ D V λ²] / (ξ Δt²). By virtual work over the step, a frictionless quasi-static
  // opening has F_crit = F_cont + inertial_force: O(ξ), however small each grain's inertial
  // force, because the opened mechanism moves every grain.
  double inertial_force = 0.0;
  double equilibrium_residual = 0.0;  // of the perturbed forces, free particles
  SolveReport solve;
  bool quasi_static = false;  // inertia_ratio ≤ max_inertia_ratio
  // The solve resolved the response to response_tolerance of its own size: its residual,
  // measured against the static force scale (not the perturbed one, which a runaway
  // solution inflates), is below the tolerance times max(1, largest |d_i| / ξ).
  bool resolved = false;
  // With check_linearity, on a quasi-static response: F_crit of the same perturbation at
  // 10ξ, and max_i |d_i(10ξ) − 10 d_i(ξ)| / max_i |d_i(10ξ)|. NaN when not checked.
  double fcrit_10xi = std::numeric_limits<double>::quiet_NaN();
  double linearity_misfit = std::numeric_limits<double>::quiet_NaN();
  // Not checked, or linear in ξ: at 10ξ the response is quasi-static, its displacements
  // are 10 times these (misfit ≤ 5 %) and F_crit is the same (to 1e-3 ⟨F_cont⟩). A
  // step whose solutions form a family may end on another member at another ξ.
  bool linear = true;
  // Resolved, quasi-static, linear: a result to use. Otherwise `status` says why not.
  bool ok() const { return resolved && quasi_static && linear; }
  // "ok"; "dynamic" (resolved, not quasi-static); "not-converged" (not resolved);
  // "nonlinear" (quasi-static, but not the same response at 10ξ: check_linearity);
  // "blocked" (no motion satisfies the step's non-penetration: F_crit is NaN;
  // problem/kinematic_admissibility.hpp). A `dynamic` decided before solving (the rate
  // solve's static LP) has F_crit NaN and no motion.
  PerturbationStatus status = PerturbationStatus::kNotConverged;
  double seconds = 0.0;
};

struct RateBaseSlot;  // perturbation.cpp

// The static packing a set of perturbations starts from: the scene at rest with its
// stored forces (which must be static: checked once, see PreparePerturbations).
struct PerturbationBase {
  Scene scene;                          // velocities zero, forces stored
  std::vector<Contact> contacts;        // with gap < margin
  std::vector<Eigen::Vector2d> forces;  // stored static forces per contact (0 if none)
  double mean_contact_force = 0.0;
  double pressure = 0.0;  // virial pressure of the static forces (periodic)
  double mean_radius = 0.0;
  double mean_mass = 0.0;  // of the free particles
  // The unperturbed step in the coordinates of the rate problem (its self-stresses: a
  // sparse QR), made by the first perturbation that needs it, shared by all.
  std::shared_ptr<RateBaseSlot> rate;
};

// The unjam residual is an impulse error over the mean impulse F̄Δt (docs/residual.md). A
// normal velocity error δu costs ρ δu with ρ ≈ m̄/2, and becomes a displacement error
// Δt δu. Displacements accurate to response_tolerance · ξ thus need
//     residual ≤ response_tolerance · ξ · (m̄/2) / (F̄ Δt²).
double SolverToleranceFor(const PerturbationOptions& options, const PerturbationBase& base);

// Throws std::invalid_argument if the scene stores no forces.
PerturbationBase PreparePerturbations(const Scene& static_scene,
                                      const PerturbationOptions& options);

PerturbationResult Perturb(const PerturbationBase& base, const PerturbationTarget& target,
                           const PerturbationOptions& options);

// The contact problem Perturb solves for this target, with its guess (the static forces),
// for handing to backends directly (unjam compare).
StaticProblem PosePerturbationProblem(const PerturbationBase& base,
                                      const PerturbationTarget& target,
                                      const PerturbationOptions& options);

// Targets. Force-carrying contacts between two particles (fixed ones included), in the
// order of the stored forces; a sample is drawn without replacement, deterministically
// from the seed, and kept in that order.
std::vector<PerturbationTarget> ContactTargets(const PerturbationBase& base);
std::vector<PerturbationTarget> SampleTargets(std::vector<PerturbationTarget> all, int count,
                                              std::uint64_t seed);
// Gravity packings periodic in x (std::invalid_argument otherwise): the width is cut into
// bins of about one mean diameter; per bin the free particle with the highest centre (top,
// shifted down) or the lowest (bottom, shifted up).
std::vector<PerturbationTarget> TopTargets(const PerturbationBase& base);
std::vector<PerturbationTarget> BottomTargets(const PerturbationBase& base);
// One particle shifted along a unit `direction` (any packing; std::invalid_argument for a
// particle that does not exist or is fixed, naming it).
PerturbationTarget ParticleShift(const PerturbationBase& base, int particle, Vec2 direction);

// The particle shifts that `unjam perturb` and `unjam bounds` both take: --top, --bottom,
// --shift-down P, --shift-up P. Both commands choose them here, so that a shift's row is the
// same in both (and `--shift-down P` gives the row `--top` gives P).
struct ShiftSelection {
  enum class Kind { kTop, kBottom, kDown, kUp };
  Kind kind = Kind::kTop;
  int particle = -1;  // kDown and kUp: the particle pushed
};
// The selection as its option reads without the dashes: "top", "bottom", "shift-down P",
// "shift-up P".
std::string ToString(const ShiftSelection& selection);
// The targets of a selection: TopTargets or BottomTargets, or the one ParticleShift down or
// up. A particle that does not exist or is fixed is refused (std::invalid_argument) naming
// the option: "--shift-down 3: particle 3 is fixed and cannot be shifted".
std::vector<PerturbationTarget> ShiftTargets(const PerturbationBase& base,
                                             const ShiftSelection& selection);
// F_y of particle p in the static state: the sum of the positive vertical components of the
// contact forces on it (a shift's reference force).
double EffectiveWeightOf(const PerturbationBase& base, int p);

// How PerturbAll hands out its targets and reports their results.
struct PerturbSchedule {
  int threads = 1;
  // Report each result as soon as it exists, in the order the perturbations finish, rather
  // than in target order: a long run then writes each record the moment it exists, and an
  // interruption loses only the perturbations still being solved.
  bool as_finished = false;
  // No target is started at or after this instant (a long run's budget); those started
  // finish and are reported. None: every target is run.
  std::optional<std::chrono::steady_clock::time_point> start_before;
};

// Runs the targets and reports each result to `on_result` (called from the calling thread)
// without keeping them: an ensemble of large packings needs the memory of a few results.
// In target order unless `as_finished`. Result k belongs to target k whatever the thread
// count (each perturbation is deterministic). An exception in a perturbation is rethrown
// after the workers stop.
void PerturbAll(const PerturbationBase& base, const std::vector<PerturbationTarget>& targets,
                const PerturbationOptions& options, const PerturbSchedule& schedule,
                const std::function<void(int, const PerturbationResult&)>& on_result);
// Every target on `threads` threads, in target order.
void PerturbAll(const PerturbationBase& base, const std::vector<PerturbationTarget>& targets,
                const PerturbationOptions& options, int threads,
                const std::function<void(int, const PerturbationResult&)>& on_result);

}  // namespace unjam
