// Which perturbations a run makes: contact openings (all or a sample) and particle shifts
// (the top or bottom grain of each bin of a pile, or one named particle).
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "perturbation_internal.hpp"
#include "unjam/analysis/equilibrium.hpp"

namespace unjam {

using namespace perturbation_internal;

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
}  // namespace unjam
