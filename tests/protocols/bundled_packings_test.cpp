// Data-driven tests over problems/*.unjam (src/protocols/static_solve.cpp on saved states):
// every bundled packing is static, at its external load, and re-solving it keeps its forces.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <tuple>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/static_solve.hpp"

namespace unjam {
namespace {

std::vector<std::string> BundledPackings() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(UNJAM_SOURCE_DIR "/problems")) {
    if (entry.path().extension() == ".unjam") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

using Key = std::tuple<int, int, int, int>;
std::map<Key, ContactForce> ByKey(const std::vector<ContactForce>& forces) {
  std::map<Key, ContactForce> out;
  for (const ContactForce& f : forces) out[{f.i, f.j, f.image[0], f.image[1]}] = f;
  return out;
}

class BundledPacking : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledPacking, IsStaticAtItsLoadAndKeepsItsForces) {
  const Scene scene = ReadPacking(GetParam());
  ASSERT_FALSE(scene.forces.empty()) << "a bundled packing stores its static forces";
  for (const Particle& p : scene.particles) ASSERT_EQ(p.velocity, Vec2::Zero());
  StaticSolveOptions options;
  options.solver.tolerance = 1e-10;
  const StaticSolution s = SolveStatic(scene, options);
  ASSERT_TRUE(s.report.converged()) << s.report.message;
  EXPECT_LT(s.equilibrium.residual, 1e-8);
  if (scene.effects.pressure_bath) {
    EXPECT_NEAR(s.equilibrium.pressure / scene.effects.pressure_bath->pressure, 1.0, 1e-8);
  }
  // Started from the stored forces, the solve stays on them.
  const auto stored = ByKey(scene.forces);
  const auto solved = ByKey(ToContactForces(s));
  ASSERT_EQ(stored.size(), solved.size());
  const double scale = s.equilibrium.mean_contact_force;
  for (const auto& [key, f] : stored) {
    ASSERT_TRUE(solved.count(key));
    EXPECT_NEAR(solved.at(key).normal, f.normal, 1e-8 * scale);
    EXPECT_NEAR(solved.at(key).tangential, f.tangential, 1e-8 * scale);
  }
}

TEST_P(BundledPacking, FrictionlessForcesAreUniqueFromAColdStart) {
  Scene scene = ReadPacking(GetParam());
  if (scene.effects.Frictional()) GTEST_SKIP() << "frictional forces are not unique";
  const auto stored = ByKey(scene.forces);
  scene.forces.clear();
  StaticSolveOptions options;
  // Cold NSGS on a jammed packing converges diffusively (~1e5 sweeps at N = 500).
  options.solver.tolerance = 1e-10;
  options.solver.nsgs.max_sweeps = 2000000;
  options.solver.nsgs.order = SweepOrder::kSymmetric;
  const StaticSolution s = SolveStatic(scene, options);
  ASSERT_TRUE(s.report.converged()) << s.report.message;
  const Coordination z = ComputeCoordination(scene, s.contacts, s.forces);
  const int carrying = static_cast<int>(scene.particles.size()) - z.rattlers;
  EXPECT_EQ(z.force_carrying_contacts, 2 * (carrying - 1) + 1) << "isostatic";
  for (const auto& [key, f] : ByKey(ToContactForces(s))) {
    ASSERT_TRUE(stored.count(key));
    // Both solutions have residual <= 1e-10; a jammed isostatic packing has a Delassus
    // condition number of ~5e4 (measured: residual 1e-9 gives force errors ~5e-5), so each
    // is within ~5e-6 of the exact forces.
    EXPECT_NEAR(f.normal, stored.at(key).normal, 2e-5 * s.equilibrium.mean_contact_force);
  }
}

INSTANTIATE_TEST_SUITE_P(Problems, BundledPacking, ::testing::ValuesIn(BundledPackings()),
                         [](const auto& info) {
                           std::string name = std::filesystem::path(info.param).stem().string();
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace unjam
