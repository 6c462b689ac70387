// A perturbation's static base, the scene and step it poses, and a run of many in parallel.
// The rest of a perturbation lives beside it: which ones a run makes
// (perturbation_targets.cpp), which backend solves the step (perturbation_backend.cpp),
// what is decided before solving (perturbation_decide.cpp), the solve itself with the rate
// solve first (perturbation_solve.cpp, perturbation_rate.cpp) and what an answer measures
// (perturbation_measure.cpp); perturbation_internal.hpp is what they share.
#include "unjam/protocols/perturbation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include "perturbation_internal.hpp"
#include "unjam/analysis/equilibrium.hpp"
#include "unjam/parallel/for_each_index.hpp"

namespace unjam {

const char* ToString(CellCondition condition) {
  return condition == CellCondition::kFixedPressure ? "fixed-pressure" : "fixed-volume";
}

CellCondition CellConditionFromString(const std::string& name) {
  if (name == "fixed-pressure") return CellCondition::kFixedPressure;
  if (name == "fixed-volume") return CellCondition::kFixedVolume;
  throw std::invalid_argument("unknown cell condition '" + name +
                              "' (known: fixed-pressure, fixed-volume)");
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
// The static state perturbations start from: at rest, without the prescribed effects of
// an earlier perturbation.
Scene AtRest(const Scene& scene) {
  Scene rest = scene;
  BringToRest(rest);
  rest.effects.prescribed_motion.clear();
  rest.effects.prescribed_gaps.clear();
  return rest;
}
}  // namespace

namespace perturbation_internal {

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

}  // namespace perturbation_internal

using namespace perturbation_internal;

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
  base.rate = std::make_shared<RateBaseSlot>();
  return base;
}

StaticProblem PosePerturbationProblem(const PerturbationBase& base,
                                      const PerturbationTarget& target,
                                      const PerturbationOptions& options) {
  CheckTarget(base, target);
  return PoseStaticProblem(PerturbedScene(base, target, options), StepOptions(base, options));
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
