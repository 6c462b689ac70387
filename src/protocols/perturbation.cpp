#include "unjam/protocols/perturbation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <stdexcept>

#include "perturbation_rate.hpp"
#include "unjam/analysis/equilibrium.hpp"
#include "unjam/parallel/for_each_index.hpp"
#include "unjam/problem/inertia_bound.hpp"
#include "unjam/problem/kinematic_admissibility.hpp"
#include "unjam/protocols/static_solve.hpp"

namespace unjam {

struct RateBaseSlot {
  std::once_flag once;
  RateBase rate;
};

// The shared inertia LP of a base's contact openings (PerturbationBase::opening_inertia_lp).
struct OpeningInertiaLp {
  std::once_flag once;
  std::unique_ptr<HeldContactInertia> lp;
  std::vector<Contact> contacts;  // of the unperturbed step's problem, in its order
  int dofs = 0;                   // its degrees of freedom (the cell's included)
};

const char* ToString(CellCondition condition) {
  return condition == CellCondition::kFixedPressure ? "fixed-pressure" : "fixed-volume";
}

CellCondition CellConditionFromString(const std::string& name) {
  if (name == "fixed-pressure") return CellCondition::kFixedPressure;
  if (name == "fixed-volume") return CellCondition::kFixedVolume;
  throw std::invalid_argument("unknown cell condition '" + name +
                              "' (known: fixed-pressure, fixed-volume)");
}

namespace {
bool LemkeOptionsGiven(const PerturbationOptions& o) {
  return o.solver.lemke.warm_start || o.solver.lemke.pivots_per_row > 0 ||
         o.solver.lemke.box_rate_first || o.prefer_quasi_static;
}

bool FixedVolumeCell(const PerturbationOptions& options, const Scene& scene) {
  return scene.effects.pressure_bath.has_value() && options.cell == CellCondition::kFixedVolume;
}
}  // namespace

std::string PerturbationBackend(const PerturbationOptions& options, const Scene&) {
  if (options.backend != "auto") return options.backend;
  return LemkeOptionsGiven(options) ? "lemke" : "rate";
}

std::string StepBackend(const PerturbationOptions& options, const Scene& scene) {
  if (options.backend != "auto" && options.backend != "rate") return options.backend;
  // At fixed volume the stress level of rigid grains in a frozen cell is itself free (any
  // multiple of a self-stress balances), and Lemke's path from zero impulses ends on the
  // unloaded solution (F_crit ≈ 0, docs/perturbations.md); newton's proximal steps stay
  // nearest the static forces.
  if (!scene.effects.Frictional() || FixedVolumeCell(options, scene)) return "newton";
  return AutoLeavesLemkeForSize(options, scene) ? "newton" : "lemke";
}

bool AutoLeavesLemkeForSize(const PerturbationOptions& options, const Scene& scene) {
  const bool automatic =
      options.backend == "auto" || options.backend == "rate";  // "rate": auto, resolved
  if (!automatic || !scene.effects.Frictional() || FixedVolumeCell(options, scene)) return false;
  // An option only lemke reads says which backend the user means, whatever the size.
  if (LemkeOptionsGiven(options)) return false;
  // Lemke's paths lengthen faster than the packing grows, and its default budget (100 000
  // pivots) runs out: measured on `--sample 8 --seed 3` of packings made by the same recipe
  // (docs/perturbations.md, "Which backend `auto` picks"), lemke resolves 5 of 8 openings
  // at 1 287 contacts (newton 4, none of them quasi-static), none of 4 at 2 515 contacts
  // (6–8 minutes each) and none at 3 854 (12 minutes), where newton answers in 15–40 s.
  return ForceCarryingPairs(scene).size() > kLemkeAutoContacts;
}

std::string PerturbationFallback(const PerturbationOptions& options, const Scene& scene) {
  if (options.fallback == "none") return "";
  if (options.fallback != "auto")
    return options.fallback == PerturbationBackend(options, scene) ? "" : options.fallback;
  if (options.backend != "auto") return "";
  if (StepBackend(options, scene) == "lemke") return "ipopt";
  // Frictional steps that `auto` gives to newton have no fallback: at fixed volume lemke
  // ends on the unloaded solution, and on large packings its paths run out of pivots
  // after minutes, as ipopt's fixed point stalls (1e-3 on N = 3000 openings).
  if (scene.effects.Frictional()) return "";
  // Frictionless, at fixed pressure or without a bath: newton's proximal steps crawl along
  // a self-stress that the perturbation must unload (a disk lifted off a column: its
  // contact keeps the static force to within ξ), and lemke's path solves it exactly.
  return FixedVolumeCell(options, scene) ? "" : "lemke";
}

void Validate(const PerturbationOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(std::isfinite(o.gap) && o.gap > 0.0, "perturbation gap must be positive and finite");
  require(std::isfinite(o.dt) && o.dt > 0.0, "perturbation time step must be positive and finite");
  require(o.margin > 0.0, "contact margin must be positive");
  require(o.closed_gap_tolerance >= 0.0 && o.closed_gap_tolerance < o.gap,
          "closed-gap tolerance must be below the perturbation gap");
  require(o.response_tolerance > 0.0 && o.response_tolerance < 1.0,
          "response tolerance must be in (0, 1)");
  require(o.max_inertia_ratio > 0.0, "inertia ratio threshold must be positive");
  require(o.solver_tolerance >= 0.0, "solver tolerance must be positive");
  require(o.fallback == "auto" || o.fallback == "none" || MakeSolver(o.fallback) != nullptr,
          "unknown fallback backend");
  Validate(o.solver);
}

double DetectionMargin(const PerturbationOptions& options) {
  return std::max(options.margin, 1e3 * options.gap);
}

double SolverToleranceFor(const PerturbationOptions& options, const PerturbationBase& base) {
  if (options.solver_tolerance > 0.0) return options.solver_tolerance;
  const double force = base.mean_contact_force > 0.0 ? base.mean_contact_force : 1.0;
  return options.response_tolerance * options.gap * 0.5 * base.mean_mass /
         (force * options.dt * options.dt);
}

namespace {

using Clock = std::chrono::steady_clock;

// The static state perturbations start from: at rest, without the prescribed effects of
// an earlier perturbation.
Scene AtRest(const Scene& scene) {
  Scene rest = scene;
  BringToRest(rest);
  rest.effects.prescribed_motion.clear();
  rest.effects.prescribed_gaps.clear();
  return rest;
}

Vec2 ForceVector(const Contact& c, const Eigen::Vector2d& f) {
  return f[0] * c.normal + f[1] * Perp(c.normal);
}

// Calls visit(f) with the force f that each contact exerts on particle p.
template <class Visit>
void ForEachForceOn(int p, const std::vector<Contact>& contacts,
                    const std::vector<Eigen::Vector2d>& forces, Visit visit) {
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    if (c.i == p) visit(Vec2(-ForceVector(c, forces[k])));
    if (!c.WithWall() && c.j == p) visit(ForceVector(c, forces[k]));
  }
}

// Σ of the contact forces acting on particle p.
Vec2 ContactForceOn(int p, const std::vector<Contact>& contacts,
                    const std::vector<Eigen::Vector2d>& forces) {
  Vec2 sum = Vec2::Zero();
  ForEachForceOn(p, contacts, forces, [&](const Vec2& f) { sum += f; });
  return sum;
}

// Effective weight F_y: the sum of the positive vertical components of the contact forces
// on particle p.
double EffectiveWeight(int p, const std::vector<Contact>& contacts,
                       const std::vector<Eigen::Vector2d>& forces) {
  double sum = 0.0;
  ForEachForceOn(p, contacts, forces, [&](const Vec2& f) { sum += std::max(f.y(), 0.0); });
  return sum;
}

// The scene of one perturbation: the static state plus the held gap or the prescribed shift.
Scene PerturbedScene(const PerturbationBase& base, const PerturbationTarget& t,
                     const PerturbationOptions& o) {
  Scene s = base.scene;
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    s.effects.prescribed_motion.push_back({t.i, (o.gap / o.dt) * t.direction, 0.0});
    return s;
  }
  if (o.cell == CellCondition::kFixedVolume) s.effects.pressure_bath.reset();
  const int k = FindContact(base.contacts, t.i, t.j, t.image);
  double gap = k >= 0 ? base.contacts[k].gap : MakeContact(base.scene, t.i, t.j, t.image).gap;
  if (std::abs(gap) <= o.closed_gap_tolerance) gap = 0.0;
  s.effects.prescribed_gaps.push_back({t.i, t.j, t.image, gap + o.gap});
  return s;
}

std::vector<ContactForceChange> ForceChanges(const PerturbationBase& base,
                                             const StaticSolution& after) {
  std::vector<ContactForceChange> out;
  out.reserve(after.contacts.size());
  // Both lists are sorted by key (detection order); the perturbed one may hold one more
  // contact (a held gap beyond the margin).
  std::size_t a = 0;
  for (std::size_t b = 0; b < after.contacts.size(); ++b) {
    const Contact& c = after.contacts[b];
    while (a < base.contacts.size() && ContactKeyLess(base.contacts[a], c)) ++a;
    ContactForceChange change{c.i,      c.j,
                              c.image,  base.scene.particles[c.i].position + c.branch_i,
                              c.normal, c.center_to_center};
    if (a < base.contacts.size() && SameContactKey(base.contacts[a], c)) {
      change.normal_before = base.forces[a][0];
      change.tangential_before = base.forces[a][1];
    }
    change.normal_after = after.forces[b][0];
    change.tangential_after = after.forces[b][1];
    out.push_back(change);
  }
  return out;
}

double PenetrationDepth(const Scene& scene, const std::vector<Vec2>& d, Vec2 origin, Vec2 axis) {
  double weighted = 0.0, total = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double magnitude = d[i].norm();
    if (magnitude == 0.0) continue;
    const Vec2 r = MinimumImage(scene.cell, scene.particles[i].position - origin);
    weighted += magnitude * std::abs(r.dot(axis));
    total += magnitude;
  }
  return total > 0.0 ? weighted / total : 0.0;
}

// The force scale of each kind of degree of freedom (problem/inertia_bound.hpp): a grain's
// translation, the mean contact force; its spin, that force times its radius; the cell's
// strain, D V P_ext (the virial at the bath's pressure).
double TranslationScale(const PerturbationBase& base) {
  return base.mean_contact_force > 0.0 ? base.mean_contact_force : 1.0;
}
double CellScale(const Scene& scene) {
  const PressureBath& bath = *scene.effects.pressure_bath;
  return CellInertia(scene) / bath.cell_mass * bath.pressure;
}

// The largest inertial force of the answer over its scale: m_i |d_i| / Δt² of every grain,
// I_i |θ_i| / Δt² of every spin, and the cell's M_λ D V |ε| / Δt² under a pressure bath.
double InertiaRatio(const PerturbationBase& base, const PerturbationResult& r, double dt) {
  const double force = TranslationScale(base);
  double largest = 0.0;
  for (std::size_t i = 0; i < r.displacement.size(); ++i) {
    const Particle& p = base.scene.particles[i];
    largest = std::max(largest, p.Mass() * r.displacement[i].norm() / force);
    if (!r.rotation.empty())
      largest = std::max(largest, p.Inertia() * std::abs(r.rotation[i]) / (force * p.radius));
  }
  if (base.scene.effects.pressure_bath) {
    largest = std::max(largest,
                       CellInertia(base.scene) * std::abs(r.cell_strain) / CellScale(base.scene));
  }
  return largest / (dt * dt);
}

// s_d per degree of freedom of the posed step, in its layout (contact_problem.hpp).
Eigen::VectorXd InertiaScales(const PerturbationBase& base, const AssembledProblem& a) {
  const ContactProblem& p = a.problem;
  Eigen::VectorXd scale(p.NumDofs());
  const double force = TranslationScale(base);
  for (int b = 0; b < p.NumBodies(); ++b) {
    const int at = b * p.DofsPerBody();
    scale[at] = scale[at + 1] = force;
    if (p.frictional) scale[at + 2] = force * base.scene.particles[a.particle_of_body[b]].radius;
  }
  if (p.cell) scale[p.NumDofs() - 1] = CellScale(base.scene);
  return scale;
}

// The inertial work over the step, over ξ: grains, and the cell under a pressure bath (its
// strain ε = ΔL/L moves with mass M_λ D V, docs/method.md).
double InertialForce(const PerturbationBase& base, const PerturbationResult& r, double gap,
                     double dt) {
  double work = 0.0;
  for (std::size_t i = 0; i < r.displacement.size(); ++i) {
    const Particle& p = base.scene.particles[i];
    work +=
        p.Mass() * r.displacement[i].squaredNorm() + p.Inertia() * r.rotation[i] * r.rotation[i];
  }
  if (base.scene.effects.pressure_bath)
    work += CellInertia(base.scene) * r.cell_strain * r.cell_strain;
  return work / (gap * dt * dt);
}

// The largest displacement in units of ξ, at least 1: the solver tolerance is set for a
// response of size ξ, and a response n times larger is resolved by an n times larger one.
double ResponseSize(const std::vector<Vec2>& d, double gap) {
  double largest = 0.0;
  for (const Vec2& di : d) largest = std::max(largest, di.norm());
  return std::max(1.0, largest / gap);
}

void SetOriginAndReference(const PerturbationBase& base, const PerturbationTarget& t,
                           PerturbationResult& r) {
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    r.origin = base.scene.particles[t.i].position;
    r.axis = Vec2(0.0, 1.0);
    r.f_reference = EffectiveWeight(t.i, base.contacts, base.forces);
    return;
  }
  const int k = FindContact(base.contacts, t.i, t.j, t.image);
  const Contact c = k >= 0 ? base.contacts[k] : MakeContact(base.scene, t.i, t.j, t.image);
  r.origin = base.scene.particles[t.i].position + c.branch_i;
  r.axis = c.normal;
  r.f_reference = k >= 0 ? base.forces[k][0] : 0.0;
}

double CriticalForce(const PerturbationTarget& t, const StaticSolution& s) {
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    return 0.0 - t.direction.dot(
                     ContactForceOn(t.i, s.contacts, s.forces));  // +0, not −0, when nothing pushes
  }
  const int k = FindContact(s.contacts, t.i, t.j, t.image);
  return k >= 0 ? s.forces[k][0] : 0.0;
}

void CheckTarget(const PerturbationBase& base, const PerturbationTarget& t) {
  const int n = static_cast<int>(base.scene.particles.size());
  if (t.i < 0 || t.i >= n)
    throw std::invalid_argument("perturbation names particle " + std::to_string(t.i) +
                                ", which does not exist");
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    if (base.scene.particles[t.i].fixed)
      throw std::invalid_argument("particle " + std::to_string(t.i) +
                                  " is fixed and cannot be shifted");
    return;
  }
  if (t.j < 0 || t.j >= n || t.j == t.i)
    throw std::invalid_argument("perturbation names contact (" + std::to_string(t.i) + ", " +
                                std::to_string(t.j) + "), which does not exist");
}

}  // namespace

PerturbationBase PreparePerturbations(const Scene& static_scene,
                                      const PerturbationOptions& options) {
  if (static_scene.forces.empty()) {
    throw std::invalid_argument(
        "the packing stores no static forces: run `unjam solve FILE -o FILE` first");
  }
  Validate(options);
  PerturbationBase base;
  base.scene = AtRest(static_scene);
  base.contacts = DetectContacts(base.scene, DetectionMargin(options));
  const ForcesByContact stored(static_scene.forces);
  base.forces.assign(base.contacts.size(), Eigen::Vector2d::Zero());
  for (std::size_t k = 0; k < base.contacts.size(); ++k) {
    if (const ContactForce* f = stored.Find(base.contacts[k]))
      base.forces[k] = {f->normal, f->tangential};
  }
  const EquilibriumReport eq = CheckEquilibrium(base.scene, base.contacts, base.forces);
  base.mean_contact_force = eq.mean_contact_force;
  base.pressure = eq.pressure;
  for (const Particle& p : base.scene.particles) base.mean_radius += p.radius;
  base.mean_radius /= std::max<std::size_t>(1, base.scene.particles.size());
  const std::vector<char> movable = MovableParticles(base.scene);
  int free_particles = 0;
  for (std::size_t i = 0; i < movable.size(); ++i) {
    if (!movable[i]) continue;
    base.mean_mass += base.scene.particles[i].Mass();
    ++free_particles;
  }
  base.mean_mass = free_particles > 0 ? base.mean_mass / free_particles : 1.0;
  if (options.dynamic_precheck) base.opening_inertia_lp = std::make_shared<OpeningInertiaLp>();
  base.rate = std::make_shared<RateBaseSlot>();
  return base;
}

namespace {
// The speed above which a grain makes the step dynamic (InertiaRatio above the threshold),
// for the lightest grain that may move: any faster velocity makes every grain dynamic.
double DynamicSpeed(const PerturbationBase& base, const PerturbationOptions& options) {
  double lightest = std::numeric_limits<double>::infinity();
  for (const Particle& p : base.scene.particles) {
    if (!p.fixed) lightest = std::min(lightest, p.Mass());
  }
  const double force = base.mean_contact_force > 0.0 ? base.mean_contact_force : 1.0;
  return options.max_inertia_ratio * force * options.dt / lightest;
}

// The one step of a perturbation: a static solve of the perturbed scene.
StaticSolveOptions StepOptions(const PerturbationBase& base, const PerturbationOptions& options) {
  StaticSolveOptions solve;
  solve.dt = options.dt;
  solve.closed_gap_tolerance = options.closed_gap_tolerance;
  solve.margin = DetectionMargin(options);
  solve.backend = StepBackend(options, base.scene);
  solve.solver = options.solver;
  solve.solver.tolerance = SolverToleranceFor(options, base);
  solve.solver.lemke.velocity_scale = options.gap / options.dt;
  solve.solver.newton.warm_probe = true;  // the static forces are the warm start
  if (options.prefer_quasi_static) solve.solver.lemke.velocity_bound = DynamicSpeed(base, options);
  solve.nearest_member = options.nearest_member;
  return solve;
}

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
}  // namespace

StaticProblem PosePerturbationProblem(const PerturbationBase& base,
                                      const PerturbationTarget& target,
                                      const PerturbationOptions& options) {
  CheckTarget(base, target);
  return PoseStaticProblem(PerturbedScene(base, target, options), StepOptions(base, options));
}

namespace {
// The small-gap regime (check_linearity). Tolerances: the displacements are resolved to 1 %
// of their size (response_tolerance), so 5 % leaves room for two such solves; F_crit of a
// linear response moves only by its inertial part, O(ξ) (below 3e-5 of F_cont measured).
constexpr double kLinearityGapFactor = 10.0;
constexpr double kLinearityMisfit = 0.05;
constexpr double kLinearityForceChange = 1e-3;  // of the mean contact force

double LinearityMisfit(const std::vector<Vec2>& d, const std::vector<Vec2>& d_scaled,
                       double factor) {
  double largest = 0.0, misfit = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    largest = std::max(largest, d_scaled[i].norm());
    misfit = std::max(misfit, (d_scaled[i] - factor * d[i]).norm());
  }
  if (largest > 0.0) return misfit / largest;
  return misfit == 0.0
             ? 0.0
             : std::numeric_limits<double>::infinity();  // nothing moves at either gap: linear
}

// The basis of a solution of the same base (another gap) for the contacts of `posed`, or
// empty if it has none. A contact it did not have (detected within the larger margin of
// a larger gap) enters as open: no impulse variable basic.
std::vector<std::uint8_t> BasisFor(const StaticProblem& posed, const StaticSolution& from) {
  if (from.basis.empty()) return {};
  const ContactProblem& p = posed.assembled.problem;
  std::vector<std::uint8_t> basis(p.NumContacts(), 0);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const Contact& c = posed.contacts[posed.assembled.source_contact[k]];
    const int at = FindContact(from.contacts, c.i, c.j, c.image);
    if (at >= 0) basis[k] = from.basis[at];
  }
  return basis;
}

// What one solution of the step measures, into r (its target, origin and reference set).
void Measure(const PerturbationBase& base, const PerturbationOptions& options,
             const StaticSolveOptions& solve, const StaticSolution& s, PerturbationResult& r) {
  r.solve = s.report;
  r.f_crit = CriticalForce(r.target, s);
  r.displacement = s.displacement;  // the shifted particle's included: its shift
  r.rotation = s.rotation;
  r.cell_strain = s.cell_strain;
  r.force_changes = ForceChanges(base, s);
  r.penetration_depth = PenetrationDepth(base.scene, r.displacement, r.origin, r.axis);
  if (PeriodicY(base.scene.cell.periodicity))
    r.pressure_change = s.equilibrium.pressure - base.pressure;
  r.inertia_ratio = InertiaRatio(base, r, options.dt);
  r.inertial_force = InertialForce(base, r, options.gap, options.dt);
  r.equilibrium_residual = s.equilibrium.residual;
  r.quasi_static = r.inertia_ratio <= options.max_inertia_ratio;
  // The residual is relative to the solution's own force scale; a solution with runaway
  // forces (pushing into a rigid column) must not pass by inflating it.
  const double scale_ratio = base.mean_contact_force > 0.0
                                 ? s.equilibrium.mean_contact_force / base.mean_contact_force
                                 : 1.0;
  const double absolute = r.solve.residual * std::max(1.0, scale_ratio);
  r.resolved = absolute <= solve.solver.tolerance * ResponseSize(r.displacement, options.gap);
  r.status = !r.resolved       ? PerturbationStatus::kNotConverged
             : !r.quasi_static ? PerturbationStatus::kDynamic
                               : PerturbationStatus::kOk;
}

// Solves the posed step with solve.backend and measures the answer into r; where that
// leaves the step unresolved, solves it once more with the fallback backend (if any) and
// keeps that answer if it is resolved. The message keeps the first backend's account.
StaticSolution SolveAndMeasure(const PerturbationBase& base, const Scene& perturbed,
                               StaticProblem posed, const StaticSolveOptions& solve,
                               const PerturbationOptions& options, PerturbationResult& r) {
  const std::string fallback = PerturbationFallback(options, base.scene);
  std::optional<StaticProblem> spare;
  if (!fallback.empty()) spare = posed;
  StaticSolution s = SolveStatic(perturbed, std::move(posed), solve);
  Measure(base, options, solve, s, r);
  if (r.resolved || !spare) return s;
  StaticSolveOptions second = solve;
  second.backend = fallback;
  spare->guess.basis.clear();
  StaticSolution s2 = SolveStatic(perturbed, std::move(*spare), second);
  PerturbationResult r2 = r;
  Measure(base, options, second, s2, r2);
  const std::string first = r.solve.backend + ": " + r.solve.message;
  if (!r2.resolved) {
    r.solve.message += "; then " + r2.solve.backend + ": " + r2.solve.message;
    return s;
  }
  r2.solve.message = "after " + first + "; " + r2.solve.message;
  r = std::move(r2);
  return s2;
}

const RateBase& RateBaseOf(const PerturbationBase& base, const PerturbationOptions& options) {
  RateBaseSlot& slot = *base.rate;
  std::call_once(slot.once, [&] { slot.rate = PrepareRateBase(base, StepOptions(base, options)); });
  return slot.rate;
}

std::string PathAccount(const RatePathResult& path) {
  char text[200];
  std::snprintf(text, sizeof text, "rate path: %s after %d events, %d turns%s%s",
                ToString(path.end), path.events, path.turns, path.message.empty() ? "" : ", ",
                path.message.c_str());
  return text;
}

void JudgeLinearity(const PerturbationBase& base, const PerturbationResult& scaled,
                    PerturbationResult& r);

std::string FormatResidual(double residual) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", residual);
  return text;
}

// The step's solution on the path's final contact states, measured into r.
void MeasureOnPattern(const PerturbationBase& base, const RateBase& rb, const RateTarget& rt,
                      const RatePathResult& path, const PerturbationOptions& options,
                      const StaticSolveOptions& solve, const Scene& perturbed,
                      const StaticProblem& posed, const std::string& account,
                      PerturbationResult& r) {
  SolveResult step = StepOnPattern(rb, rt, path, posed);
  step.report.iterations = path.events;
  step.report.message =
      account + "; the step on its pattern: residual " + FormatResidual(step.report.residual);
  StaticSolution s = SolutionOf(perturbed, posed, step, options.dt);
  Measure(base, options, solve, s, r);
  const int closing = ContactClosedAt(posed, step.impulses, kLinearityGapFactor);
  if (r.status == PerturbationStatus::kOk && closing >= 0) {
    const Contact& c = posed.contacts[static_cast<std::size_t>(
        posed.assembled.source_contact[static_cast<std::size_t>(closing)])];
    r.linear = false;
    r.status = PerturbationStatus::kNonlinear;
    r.solve.message += "; at 10 xi the response closes the open contact (" + std::to_string(c.i) +
                       ", " + std::to_string(c.j) + ")";
  }
}

// The small-gap check of a rate answer: the step at 10ξ solved on the same contact states.
// Where that is no solution of the step (its residual above the tolerance), the response
// at 10ξ is not 10 times this one: nonlinear.
void CheckLinearityOnPattern(const PerturbationBase& base, const PerturbationTarget& target,
                             const RateBase& rb, const RateTarget& rt, const RatePathResult& path,
                             const PerturbationOptions& options, PerturbationResult& r) {
  PerturbationOptions scaled = options;
  scaled.gap *= kLinearityGapFactor;
  scaled.max_inertia_ratio *= kLinearityGapFactor;  // a linear response's inertia grows with ξ
  const StaticSolveOptions solve = StepOptions(base, scaled);
  const Scene perturbed = PerturbedScene(base, target, scaled);
  const StaticProblem posed = PoseStaticProblem(perturbed, solve);
  PerturbationResult check;
  check.target = target;
  SetOriginAndReference(base, target, check);
  MeasureOnPattern(base, rb, rt, path, scaled, solve, perturbed, posed, "", check);
  r.solve.message += "; 10 xi check: residual " + FormatResidual(check.solve.residual);
  if (!check.resolved) {
    r.linear = false;
    r.status = PerturbationStatus::kNonlinear;
    r.solve.message += ", not a solution of the step at 10 xi";
    return;
  }
  JudgeLinearity(base, check, r);
}

// The perturbation solved as the rigid limit of stiff contacts (perturbation_rate.hpp):
// its answer, or none where the path gives no definite one (`account` then says why, and
// the step is solved by a backend).
std::optional<PerturbationResult> PerturbByRate(const PerturbationBase& base,
                                                const PerturbationTarget& target,
                                                const PerturbationOptions& options,
                                                const StaticSolveOptions& solve,
                                                const Scene& perturbed, const StaticProblem& posed,
                                                PerturbationResult r, Clock::time_point start,
                                                std::string& account) {
  if (base.rate == nullptr) return std::nullopt;
  const RateBase& rb = RateBaseOf(base, options);
  const RateTarget rt = PoseRateTarget(rb, target, options);
  if (!rt.refused.empty()) {
    account = "rate path: " + rt.refused;
    return std::nullopt;
  }
  if (!rt.problem.released_rows.empty()) {
    // Released forces (the held contact's friction): is there still a static network?
    const RateStaticLp lp = SolveRateStaticLp(rt.problem);
    if (lp.decided && !lp.feasible) {
      PerturbationResult d = std::move(r);
      d.solve.status = SolveStatus::kConverged;
      d.solve.iterations = lp.iterations;
      d.resolved = true;
      d.status = PerturbationStatus::kDynamic;
      return DecidedWithoutSolving(
          base, "static LP",
          "no static network holds the packing with the perturbation's forces released (" +
              lp.message + "): dynamic, not solved",
          std::move(d), start);
    }
  }
  const RatePathResult path = FollowRatePath(rt.problem);
  account = PathAccount(path);
  if (path.end != RatePathEnd::kCollapse) return std::nullopt;
  MeasureOnPattern(base, rb, rt, path, options, solve, perturbed, posed, account, r);
  if (!r.resolved) {  // the path's pattern is no solution of the step: the step solver decides
    account += "; its pattern is no solution of the step (residual " +
               FormatResidual(r.solve.residual) + ")";
    return std::nullopt;
  }
  if (r.status == PerturbationStatus::kOk && options.check_linearity)
    CheckLinearityOnPattern(base, target, rb, rt, path, options, r);
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

// The whole measurement at one gap; `continued`: the answer at another gap, whose basis
// the solve tries first (check_by_continuation; the warm start stays the static forces,
// from which newton resolves a frictionless response further than from that answer);
// `answer`: this one's solution.
PerturbationResult PerturbOnce(const PerturbationBase& base, const PerturbationTarget& target,
                               const PerturbationOptions& options,
                               const StaticSolution* continued = nullptr,
                               StaticSolution* answer = nullptr) {
  const auto start = Clock::now();
  CheckTarget(base, target);
  PerturbationResult r;
  r.target = target;
  SetOriginAndReference(base, target, r);

  const StaticSolveOptions solve = StepOptions(base, options);
  const Scene perturbed = PerturbedScene(base, target, options);
  // Blocked perturbations have no response to measure: say so instead of reporting what a
  // solver makes of an infeasible step (runaway forces, or penetrations spread below its
  // tolerance). An opening under a pressure bath is never blocked: a uniform expansion
  // of the cell opens every contact (u_n = λ l·n > 0), so it needs no check.
  const bool always_admissible = target.kind == PerturbationTarget::Kind::kContactOpening &&
                                 options.cell == CellCondition::kFixedPressure &&
                                 base.scene.effects.pressure_bath.has_value();
  StaticProblem posed = PoseStaticProblem(perturbed, solve);
  if (continued != nullptr) posed.guess.basis = BasisFor(posed, *continued);
  if (!posed.assembled.violated_immovable.empty()) {
    // A particle shifted into a fixed one: no impulse can keep that contact closed.
    const Contact& c = posed.contacts[posed.assembled.violated_immovable.front()];
    return Blocked(base, "known motion", DescribeImmovableViolation(c), std::move(r), start);
  }
  if (!always_admissible) {
    const KinematicAdmissibility kinematics = CheckKinematicAdmissibility(posed.assembled.problem);
    if (kinematics.decided && !kinematics.admissible)
      return Blocked(base, "kinematic LP", kinematics.message, std::move(r), start);
  }
  // A shift's LP is the static state's with the shifted particle's balance dropped: the
  // stored forces satisfy it, so its bound is zero and it can decide nothing.
  if (options.dynamic_precheck && target.kind == PerturbationTarget::Kind::kContactOpening) {
    if (auto dynamic = DynamicBeforeSolving(base, posed, options, r, start))
      return std::move(*dynamic);
  }
  std::string rate_account;
  if (PerturbationBackend(options, base.scene) == "rate" && continued == nullptr) {
    if (auto answered =
            PerturbByRate(base, target, options, solve, perturbed, posed, r, start, rate_account)) {
      return std::move(*answered);
    }
  }
  StaticSolution s = SolveAndMeasure(base, perturbed, std::move(posed), solve, options, r);
  if (!rate_account.empty())
    r.solve.message = rate_account + "; then " + r.solve.backend + ": " + r.solve.message;
  if (answer != nullptr) *answer = std::move(s);
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

// Compares a quasi-static result r with the same perturbation at 10ξ (`scaled`).
void JudgeLinearity(const PerturbationBase& base, const PerturbationResult& scaled,
                    PerturbationResult& r) {
  r.fcrit_10xi = scaled.f_crit;
  r.linearity_misfit = LinearityMisfit(r.displacement, scaled.displacement, kLinearityGapFactor);
  r.linear = scaled.quasi_static && r.linearity_misfit <= kLinearityMisfit &&
             std::abs(scaled.f_crit - r.f_crit) <= kLinearityForceChange * base.mean_contact_force;
  if (!r.linear) r.status = PerturbationStatus::kNonlinear;
}
}  // namespace

PerturbationResult Perturb(const PerturbationBase& base, const PerturbationTarget& target,
                           const PerturbationOptions& options) {
  const auto start = Clock::now();
  StaticSolution answer;
  PerturbationResult r = PerturbOnce(base, target, options, nullptr, &answer);
  // A rate answer had its own check at 10ξ, on its contact states (CheckLinearityOnPattern).
  if (!options.check_linearity || !r.ok() || r.solve.backend == "rate") return r;
  PerturbationOptions scaled = options;
  scaled.gap *= kLinearityGapFactor;
  // A linear response's inertia grows with the gap, so at 10ξ it is judged against a
  // threshold 10 times as high: the same regime, not a stricter one.
  scaled.max_inertia_ratio *= kLinearityGapFactor;
  // The inertia LP has no kinematics, so at 10ξ it differs only by the contacts the larger
  // margin adds (a relaxation): its bound, at most the one that passed at ξ, cannot exceed
  // a threshold 10 times as high.
  scaled.dynamic_precheck = false;
  // An answer of the fallback is checked by the fallback: the first backend left the step
  // at ξ unresolved, and would most likely fail again at 10ξ.
  const std::string fallback = PerturbationFallback(options, base.scene);
  if (!fallback.empty() && r.solve.backend == fallback) {
    scaled.backend = r.solve.backend;
    scaled.fallback = "none";
  }
  const PerturbationResult check =
      PerturbOnce(base, target, scaled, options.check_by_continuation ? &answer : nullptr);
  if (!check.resolved) {  // no verdict: the result cannot be certified
    r.resolved = false;
    r.status = PerturbationStatus::kNotConverged;
    r.solve.message += (r.solve.message.empty() ? "" : "; ") +
                       std::string("the 10 xi check did not converge: ") + check.solve.message;
  } else {
    JudgeLinearity(base, check, r);
    r.solve.message +=
        (r.solve.message.empty() ? "" : "; ") + std::string("10 xi check: ") + check.solve.message;
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

std::vector<PerturbationTarget> ContactTargets(const PerturbationBase& base) {
  std::vector<PerturbationTarget> out;
  for (const ContactForce& f : ForceCarryingPairs(base.scene)) {
    PerturbationTarget t;
    t.kind = PerturbationTarget::Kind::kContactOpening;
    t.i = f.i;
    t.j = f.j;
    t.image = f.image;
    out.push_back(t);
  }
  return out;
}

std::vector<PerturbationTarget> SampleTargets(std::vector<PerturbationTarget> all, int count,
                                              std::uint64_t seed) {
  const int n = static_cast<int>(all.size());
  if (count >= n) return all;
  // Partial Fisher–Yates with an explicit modulus: the same sample on every platform.
  std::vector<int> index(n);
  for (int k = 0; k < n; ++k) index[k] = k;
  std::mt19937_64 rng(seed);
  for (int k = 0; k < count; ++k) {
    const int pick = k + static_cast<int>(rng() % static_cast<std::uint64_t>(n - k));
    std::swap(index[k], index[pick]);
  }
  index.resize(count);
  std::sort(index.begin(), index.end());
  std::vector<PerturbationTarget> out;
  for (int k : index) out.push_back(all[k]);
  return out;
}

namespace {
// One free particle per bin of about one mean diameter across the width: the one that
// `better` prefers (highest or lowest centre).
template <class Better>
std::vector<PerturbationTarget> PerBin(const PerturbationBase& base, Vec2 direction,
                                       Better better) {
  const Scene& s = base.scene;
  if (!s.effects.gravity || !PeriodicX(s.cell.periodicity)) {
    throw std::invalid_argument("--top and --bottom need a gravity packing periodic in x");
  }
  const double width = s.cell.size.x();
  const int bins = std::max(1, static_cast<int>(std::lround(width / (2.0 * base.mean_radius))));
  std::vector<int> chosen(bins, -1);
  for (int i = 0; i < static_cast<int>(s.particles.size()); ++i) {
    const Particle& p = s.particles[i];
    if (p.fixed) continue;
    const double x = p.position.x() - width * std::floor(p.position.x() / width);
    const int b = std::min(bins - 1, static_cast<int>(x / width * bins));
    if (chosen[b] < 0 || better(p.position.y(), s.particles[chosen[b]].position.y())) chosen[b] = i;
  }
  std::vector<PerturbationTarget> out;
  for (int i : chosen) {
    if (i < 0) continue;
    PerturbationTarget t;
    t.kind = PerturbationTarget::Kind::kParticleShift;
    t.i = i;
    t.direction = direction;
    out.push_back(t);
  }
  return out;
}
}  // namespace

std::vector<PerturbationTarget> TopTargets(const PerturbationBase& base) {
  return PerBin(base, Vec2(0.0, -1.0), [](double y, double best) { return y > best; });
}

PerturbationTarget ParticleShift(const PerturbationBase& base, int particle, Vec2 direction) {
  const int n = static_cast<int>(base.scene.particles.size());
  if (particle < 0 || particle >= n) {
    throw std::invalid_argument("particle " + std::to_string(particle) +
                                " does not exist: the packing has " + std::to_string(n) +
                                " particles (0.." + std::to_string(n - 1) + ")");
  }
  if (base.scene.particles[particle].fixed)
    throw std::invalid_argument("particle " + std::to_string(particle) +
                                " is fixed and cannot be shifted");
  PerturbationTarget t;
  t.kind = PerturbationTarget::Kind::kParticleShift;
  t.i = particle;
  t.direction = direction.normalized();
  return t;
}

double EffectiveWeightOf(const PerturbationBase& base, int p) {
  return EffectiveWeight(p, base.contacts, base.forces);
}

std::vector<PerturbationTarget> BottomTargets(const PerturbationBase& base) {
  return PerBin(base, Vec2(0.0, 1.0), [](double y, double best) { return y < best; });
}

std::string ToString(const ShiftSelection& selection) {
  const std::string particle = std::to_string(selection.particle);
  switch (selection.kind) {
    case ShiftSelection::Kind::kTop: return "top";
    case ShiftSelection::Kind::kBottom: return "bottom";
    case ShiftSelection::Kind::kDown: return "shift-down " + particle;
    case ShiftSelection::Kind::kUp: return "shift-up " + particle;
  }
  return "";
}

std::vector<PerturbationTarget> ShiftTargets(const PerturbationBase& base,
                                             const ShiftSelection& selection) {
  if (selection.kind == ShiftSelection::Kind::kTop) return TopTargets(base);
  if (selection.kind == ShiftSelection::Kind::kBottom) return BottomTargets(base);
  const Vec2 direction(0.0, selection.kind == ShiftSelection::Kind::kDown ? -1.0 : 1.0);
  try {
    return {ParticleShift(base, selection.particle, direction)};
  } catch (const std::invalid_argument& e) {
    // ParticleShift names the particle; the user needs to know which option gave it.
    throw std::invalid_argument("--" + ToString(selection) + ": " + e.what());
  }
}

void PerturbAll(const PerturbationBase& base, const std::vector<PerturbationTarget>& targets,
                const PerturbationOptions& options, const PerturbSchedule& schedule,
                const std::function<void(int, const PerturbationResult&)>& on_result) {
  parallel::Schedule pool;
  pool.threads = schedule.threads;
  pool.as_finished = schedule.as_finished;
  if (schedule.start_before) {
    pool.may_start = [at = *schedule.start_before] {
      return std::chrono::steady_clock::now() < at;
    };
  }
  // Each result is held from when it exists until it is reported, then freed: only results
  // that wait for an earlier one (target order) are held.
  std::vector<std::optional<PerturbationResult>> results(targets.size());
  parallel::ForEachIndex(
      static_cast<int>(targets.size()), pool,
      [&](int k) { results[k] = Perturb(base, targets[k], options); },
      [&](int k) {
        const PerturbationResult r = std::move(*results[k]);
        results[k].reset();
        on_result(k, r);
      });
}

void PerturbAll(const PerturbationBase& base, const std::vector<PerturbationTarget>& targets,
                const PerturbationOptions& options, int threads,
                const std::function<void(int, const PerturbationResult&)>& on_result) {
  PerturbSchedule schedule;
  schedule.threads = threads;
  PerturbAll(base, targets, options, schedule, on_result);
}

}  // namespace unjam
