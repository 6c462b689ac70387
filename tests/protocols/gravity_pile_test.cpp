// Tests for src/protocols/gravity_pile.cpp and relax.cpp: a small pile settles on its rough
// bed and is proven static; its bed carries exactly the weight of the pile; so at the
// protocols' time step and at twice it (with the tolerance tightened for it).
#include <gtest/gtest.h>

#include <cmath>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/protocols/gravity_pile.hpp"
#include "unjam/protocols/relax.hpp"

namespace unjam {
namespace {

struct Settled {
  Scene scene;
  RelaxReport report;
};

Settled SettlePile(double mu, std::uint64_t seed, double dt = 5e-3) {
  PileOptions pile;
  pile.particles = 60;
  pile.width = 12.0;
  pile.friction = mu;
  pile.seed = seed;
  StepOptions step;
  step.dt = dt;
  Simulation sim(MakeLoosePile(pile), step);
  RelaxOptions relax;
  relax.step_tolerance = LooseStepTolerance(dt / TimeUnit(pile));
  relax.max_steps = 100000;
  Settled out;
  out.report = RelaxToStatic(sim, relax);
  out.scene = sim.scene();
  return out;
}

TEST(GravityPile, LoosePileStartsAboveTheBedAtRest) {
  PileOptions pile;
  pile.particles = 200;
  pile.width = 20.0;
  const Scene s = MakeLoosePile(pile);
  int fixed = 0;
  for (const Particle& p : s.particles) {
    fixed += p.fixed;
    if (!p.fixed) {
      EXPECT_GT(p.position.y() - p.radius, 2.0);
    }
    EXPECT_EQ(p.velocity, Vec2::Zero());
  }
  EXPECT_GT(fixed, 10);
  EXPECT_EQ(s.cell.periodicity, Periodicity::kX);
  EXPECT_TRUE(DetectContacts(s, 0.0).size() <= static_cast<std::size_t>(fixed));  // bed only
}

// Static, nothing overlaps, no rattlers, the bed carries the whole weight, all at rest.
void ExpectStaticOnTheBed(const Settled& p, double mu) {
  ASSERT_TRUE(p.report.jammed) << "mu " << mu << ", steps " << p.report.steps;
  const StaticSolution& s = p.report.final_check;
  EXPECT_LT(s.equilibrium.residual, 1e-12);
  EXPECT_LT(MaxOverlap(p.scene), 1e-12) << "carrying contacts are closed exactly, nothing overlaps";
  // Under gravity every free particle rests on something: no rattlers.
  EXPECT_EQ(ComputeCoordination(p.scene, s.contacts, s.forces).rattlers, 0);
  // Newton's third law: the fixed bed carries the whole weight of the pile.
  double weight = 0.0;
  for (const Particle& q : p.scene.particles) weight += q.fixed ? 0.0 : q.Mass();
  double on_bed = 0.0;
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const Contact& c = s.contacts[k];
    const Vec2 f = s.forces[k][0] * c.normal + s.forces[k][1] * Perp(c.normal);  // on j
    if (p.scene.particles[c.i].fixed) on_bed -= f.y();  // the bed is i, the force on it is −f
    if (!c.WithWall() && p.scene.particles[c.j].fixed) on_bed += f.y();
  }
  EXPECT_NEAR(-on_bed, weight, 1e-10 * weight) << "mu " << mu;
  for (const Particle& q : p.scene.particles) EXPECT_EQ(q.velocity, Vec2::Zero());
}

TEST(GravityPile, SettlesStaticWithTheWeightOnTheBed) {
  for (double mu : {0.0, 0.5}) ExpectStaticOnTheBed(SettlePile(mu, 4), mu);
}

TEST(GravityPile, SettlesStaticAtTheProtocolTimeStepAndAtTwiceIt) {
  const Settled fine = SettlePile(0.5, 4);
  for (double dt : {kPackingTimeStep, 2.0 * kPackingTimeStep}) {
    const Settled p = SettlePile(0.5, 4, dt);
    ExpectStaticOnTheBed(p, 0.5);
    EXPECT_LT(p.report.steps, fine.report.steps)
        << "dt " << dt << ": a larger step settles in fewer steps";
  }
}

}  // namespace
}  // namespace unjam
