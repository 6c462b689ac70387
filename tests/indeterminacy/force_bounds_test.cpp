// Admissible-force bounds and the degree of indeterminacy on cases with known answers: a
// disk in a V-groove (frictionless: a single network; frictional: the analytic interval, or
// no upper bound when friction can wedge the disk), a disk on a floor between two walls
// (hyperstatic: the squeeze between the walls is free), and the frictionless bundled
// packing (isostatic: zero widths, no indeterminacy).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <tuple>

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "test_scenes.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

using testing::Disk;
using testing::Floor;
using testing::VGroove;

std::vector<int> AllContacts(const EquilibriumSystem& s) {
  std::vector<int> all(s.contacts.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  return all;
}

TEST(ForceBounds, FrictionlessVGrooveHasOneNetwork) {
  const EquilibriumSystem s = BuildEquilibriumSystem(VGroove(1.2, 0.0));
  const BoundsReport r = ComputeForceBounds(s, AllContacts(s), {});
  ASSERT_TRUE(r.feasible);
  const double weight = std::numbers::pi, h = 1.6;
  for (const ContactBounds& b : r.bounds) {
    ASSERT_TRUE(b.min.ok() && b.max.ok());
    EXPECT_NEAR(b.min.value, weight / h, 1e-12);
    EXPECT_NEAR(b.max.value, weight / h, 1e-12);
  }
  const Indeterminacy nd = ForceIndeterminacy(s);
  EXPECT_EQ(nd.unknowns, 2);
  EXPECT_EQ(nd.rank, 2);
  EXPECT_EQ(nd.dimension, 0);
}

// Balance of the frictional groove: f_L = f_R = f, tangential forces ±s, h f + a s = m g,
// |s| ≤ μ f. Hence f ∈ [m g/(h + μ a), m g/(h − μ a)] (unbounded if h ≤ μ a), and m g / h
// when the contact transmits no tangential force.
TEST(ForceBounds, FrictionalVGrooveHasTheAnalyticInterval) {
  const double a = 1.2, h = 1.6, mu = 0.5, weight = std::numbers::pi;
  const EquilibriumSystem s = BuildEquilibriumSystem(VGroove(a, mu));
  const BoundsReport r = ComputeForceBounds(s, AllContacts(s), {});
  ASSERT_TRUE(r.feasible);
  for (const ContactBounds& b : r.bounds) {
    ASSERT_TRUE(b.min.ok() && b.max.ok() && b.max_without_friction.ok());
    EXPECT_NEAR(b.min.value, weight / (h + mu * a), 1e-10);
    EXPECT_NEAR(b.max.value, weight / (h - mu * a), 1e-10);
    EXPECT_NEAR(b.max_without_friction.value, weight / h, 1e-10);
  }
  EXPECT_EQ(ForceIndeterminacy(s).dimension, 1);  // 4 unknowns, 3 equations
}

// The two LP backends, an exact simplex and an interior point, agree on the analytic case.
TEST(ForceBounds, ClpAndIpoptAgree) {
  const EquilibriumSystem s = BuildEquilibriumSystem(VGroove(1.2, 0.5));
  BoundsOptions ipopt;
  ipopt.lp = LpBackend::kIpopt;
  const BoundsReport a = ComputeForceBounds(s, AllContacts(s), {});
  const BoundsReport b = ComputeForceBounds(s, AllContacts(s), {}, ipopt);
  ASSERT_TRUE(a.feasible && b.feasible);
  for (std::size_t k = 0; k < a.bounds.size(); ++k) {
    for (const auto& [x, y] :
         {std::pair{a.bounds[k].min, b.bounds[k].min}, std::pair{a.bounds[k].max, b.bounds[k].max},
          std::pair{a.bounds[k].max_without_friction, b.bounds[k].max_without_friction}}) {
      ASSERT_TRUE(x.ok() && y.ok());
      EXPECT_NEAR(x.value, y.value, 1e-6 * x.value);
    }
  }
  EXPECT_THROW(LpBackendFromString("simplex"), std::invalid_argument);
}

TEST(ForceBounds, FrictionThatCanWedgeTheDiskLeavesNoUpperBound) {
  const EquilibriumSystem s = BuildEquilibriumSystem(VGroove(1.2, 2.0));  // h < μ a
  const BoundsReport r = ComputeForceBounds(s, AllContacts(s), {});
  ASSERT_TRUE(r.feasible);
  for (const ContactBounds& b : r.bounds) {
    EXPECT_EQ(b.max.status, BoundStatus::kUnbounded);
    ASSERT_TRUE(b.min.ok());
    EXPECT_NEAR(b.min.value, std::numbers::pi / (1.6 + 2.0 * 1.2), 1e-10);
  }
}

// A disk on a floor touching two walls: the walls may squeeze it with any equal forces.
Scene BetweenWalls(double mu) {
  Scene s;
  s.cell.size = Vec2(2.0, 10.0);
  s.cell.walls = {Floor(), Wall{Vec2(0.0, 0.0), Vec2(1.0, 0.0)},
                  Wall{Vec2(2.0, 0.0), Vec2(-1.0, 0.0)}};
  s.effects.gravity = Vec2(0.0, -1.0);
  s.effects.friction = mu;
  s.particles = {Disk(1.0, 1.0, 1.0)};
  return s;
}

TEST(ForceBounds, HyperstaticDiskBetweenWallsHasAFreeSqueeze) {
  const EquilibriumSystem s = BuildEquilibriumSystem(BetweenWalls(0.0));
  ASSERT_EQ(s.contacts.size(), 3u);
  const BoundsReport r = ComputeForceBounds(s, AllContacts(s), {});
  ASSERT_TRUE(r.feasible);
  int floors = 0;
  for (const ContactBounds& b : r.bounds) {
    const bool floor = s.contacts[b.contact].normal.y() < -0.5;  // from the disk down to the floor
    if (floor) {
      ++floors;
      EXPECT_NEAR(b.min.value, std::numbers::pi, 1e-12);
      EXPECT_NEAR(b.max.value, std::numbers::pi, 1e-12);
    } else {
      EXPECT_NEAR(b.min.value, 0.0, 1e-12);
      EXPECT_EQ(b.max.status, BoundStatus::kUnbounded);
    }
  }
  EXPECT_EQ(floors, 1);
  EXPECT_EQ(ForceIndeterminacy(s).dimension, 1);                                          // 3 − 2
  EXPECT_EQ(ForceIndeterminacy(BuildEquilibriumSystem(BetweenWalls(0.5))).dimension, 3);  // 6 − 3
}

TEST(ForceBounds, AnUnsupportedDiskHasNoAdmissibleNetwork) {
  Scene s = VGroove(1.2, 0.0);
  s.particles[2].position.x() += 0.5;  // off the left support: only one contact left
  s.particles[2].position.y() = std::sqrt(4.0 - 0.7 * 0.7);
  const EquilibriumSystem system = BuildEquilibriumSystem(s);
  const BoundsReport r = ComputeForceBounds(system, AllContacts(system), {});
  EXPECT_FALSE(r.feasible);
  EXPECT_FALSE(r.message.empty());
  for (const ContactBounds& b : r.bounds) EXPECT_EQ(b.max.status, BoundStatus::kInfeasible);
}

TEST(ForceBounds, FrictionlessPackingIsIsostaticWithZeroWidths) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const BoundsReport r = ComputeForceBounds(s, AllContacts(s), StoredForcesOf(s, scene.forces));
  ASSERT_TRUE(r.feasible);
  for (const ContactBounds& b : r.bounds) {
    ASSERT_TRUE(b.min.ok() && b.max.ok());
    EXPECT_LT(b.max.value - b.min.value, 1e-8 * s.force_scale);
    // The stored forces balance to round-off (a certified packing): the unique network is
    // theirs, to the LP's accuracy.
    EXPECT_NEAR(b.max.value, b.reference, 1e-9 * s.force_scale);
  }
  EXPECT_EQ(ForceIndeterminacy(s).dimension, 0);
}

// A pile under gravity: the stored (static) forces are one admissible network, so every
// interval holds them. CLP's dual simplex once called this ensemble infeasible.
TEST(ForceBounds, PileIntervalsHoldTheStoredForces) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const BoundsReport r = ComputeForceBounds(s, AllContacts(s), StoredForcesOf(s, scene.forces));
  ASSERT_TRUE(r.feasible) << r.message;
  for (const ContactBounds& b : r.bounds) {
    ASSERT_TRUE(b.min.ok());
    EXPECT_LE(b.min.value, b.reference + 1e-9 * s.force_scale);
    if (b.max.ok()) {
      EXPECT_GE(b.max.value, b.reference - 1e-9 * s.force_scale);
    }
  }
}

// Warm starts, cold starts and threads give the same bounds.
TEST(ForceBounds, WarmColdAndThreadedAgree) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const std::vector<int> some = {0, 17, 101, 230, 402, 599};
  BoundsOptions warm, cold, threaded;
  cold.warm_start = false;
  threaded.threads = 2;
  const BoundsReport a = ComputeForceBounds(s, some, {}, warm);
  const BoundsReport b = ComputeForceBounds(s, some, {}, cold);
  const BoundsReport c = ComputeForceBounds(s, some, {}, threaded);
  for (std::size_t k = 0; k < some.size(); ++k) {
    for (const auto& [x, y, z] :
         {std::tuple{a.bounds[k].min, b.bounds[k].min, c.bounds[k].min},
          std::tuple{a.bounds[k].max, b.bounds[k].max, c.bounds[k].max},
          std::tuple{a.bounds[k].max_without_friction, b.bounds[k].max_without_friction,
                     c.bounds[k].max_without_friction}}) {
      ASSERT_EQ(x.status, y.status);
      ASSERT_EQ(x.status, z.status);
      if (!x.ok()) continue;
      EXPECT_NEAR(x.value, y.value, 1e-8 * s.force_scale);
      EXPECT_NEAR(x.value, z.value, 1e-8 * s.force_scale);
    }
  }
}

// The shortcuts (an LP skipped when an earlier optimal network already answers it: a
// contact seen without force has min 0; a maximum reached without tangential force is
// also the maximum without friction) give the bounds of running every LP.
TEST(ForceBounds, ShortcutsGiveTheBoundsOfEveryLp) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  // The contacts of a band along the bottom: neighbours, whose networks answer each other.
  double low = s.contact_points[0].y(), high = low;
  for (const Vec2& p : s.contact_points) {
    low = std::min(low, p.y());
    high = std::max(high, p.y());
  }
  std::vector<int> some;
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    if (s.contact_points[k].y() < low + 0.12 * (high - low)) some.push_back(static_cast<int>(k));
  }
  ASSERT_GT(some.size(), 50u);
  BoundsOptions with, without;
  without.shortcuts = false;
  for (int threads : {1, 2}) {
    with.threads = without.threads = threads;
    const BoundsReport a = ComputeForceBounds(s, some, {}, with);
    const BoundsReport b = ComputeForceBounds(s, some, {}, without);
    ASSERT_TRUE(a.feasible && b.feasible);
    EXPECT_GE(a.lps_skipped, 3);  // the shortcuts are taken (5 here)
    EXPECT_EQ(b.lps_skipped, 0);
    for (std::size_t k = 0; k < some.size(); ++k) {
      for (const auto& [x, y] :
           {std::pair{a.bounds[k].min, b.bounds[k].min},
            std::pair{a.bounds[k].max, b.bounds[k].max},
            std::pair{a.bounds[k].max_without_friction, b.bounds[k].max_without_friction}}) {
        ASSERT_EQ(x.status, y.status) << "contact " << some[k];
        if (x.ok()) {
          EXPECT_NEAR(x.value, y.value, 1e-9 * s.force_scale) << "contact " << some[k];
        }
      }
    }
  }
}

// Long runs: every bound is reported as it is obtained, and a run given some of them back
// (an interrupted run's records) solves only the others, to the same bounds; a run whose
// time is up starts no LP and says it is incomplete.
TEST(ForceBounds, ARunResumesFromTheBoundsItReported) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const std::vector<int> some = {0, 17, 101, 230, 402, 599, 600, 601};
  // Time up before the first LP: only the feasibility LP runs, and nothing is reported.
  std::vector<BoundRecord> reported;
  BoundsOptions stopped;
  stopped.start_before = std::chrono::steady_clock::now();
  stopped.on_bound = [&](const BoundRecord& r) { reported.push_back(r); };
  const BoundsReport none = ComputeForceBounds(s, some, {}, stopped);
  ASSERT_TRUE(none.feasible);
  EXPECT_FALSE(none.complete);
  EXPECT_TRUE(reported.empty());

  BoundsOptions first;
  first.on_bound = [&](const BoundRecord& r) { reported.push_back(r); };
  const BoundsReport a = ComputeForceBounds(s, some, {}, first);
  ASSERT_TRUE(a.feasible && a.complete);
  ASSERT_EQ(reported.size(), 3 * some.size());  // max, max without friction and min of each
  long long iterations = 0;
  for (const BoundRecord& r : reported) iterations += r.iterations;
  EXPECT_EQ(iterations,
            a.lp_iterations - none.lp_iterations);  // every LP's but the feasibility LP's

  BoundsOptions second;
  second.known.assign(reported.begin(), reported.begin() + reported.size() / 2);
  int solved = 0;
  second.on_bound = [&](const BoundRecord&) { ++solved; };
  const BoundsReport b = ComputeForceBounds(s, some, {}, second);
  ASSERT_TRUE(b.complete);
  EXPECT_EQ(b.bounds_known, static_cast<long long>(reported.size() / 2));
  EXPECT_EQ(solved + b.bounds_known, static_cast<long long>(reported.size()));
  for (const BoundRecord& r : reported) {
    const std::size_t at = std::find(some.begin(), some.end(), r.contact) - some.begin();
    ASSERT_LT(at, some.size());
    ASSERT_EQ(b.bounds[at].Of(r.kind).status, r.bound.status);
    ASSERT_EQ(a.bounds[at].Of(r.kind).status, r.bound.status);
    if (!r.bound.ok()) continue;
    EXPECT_EQ(a.bounds[at].Of(r.kind).value, r.bound.value);  // what was reported is the answer
    EXPECT_NEAR(b.bounds[at].Of(r.kind).value, r.bound.value, 1e-9 * s.force_scale)
        << ToString(r.kind) << " of " << r.contact;
  }
}

// A failure while a block reports its bounds (e.g. its records cannot be written) reaches
// the caller as the exception it was, from any thread, instead of ending the process.
TEST(ForceBounds, AFailureInABlockReachesTheCaller) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  for (int threads : {1, 2}) {
    BoundsOptions o;
    o.threads = threads;
    o.on_bound = [](const BoundRecord&) { throw OutputError("records: disk full"); };
    EXPECT_THROW(ComputeForceBounds(s, {0, 17, 101, 230}, {}, o), OutputError)
        << threads << " threads";
  }
}

// Rank 0 of an mpirun: the merged records alone remake the report of the run that wrote them.
TEST(ForceBounds, TheRecordsOfARunMakeItsReportWithoutAnLp) {
  for (const char* name : {"pressure-n500-mu0.5", "pressure-n500-mu0"}) {
    const Scene scene = ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/" + name + ".unjam");
    const EquilibriumSystem s = BuildEquilibriumSystem(scene);
    const std::vector<int> some = {3, 40, 222};
    Eigen::VectorXd reference = Eigen::VectorXd::LinSpaced(s.NumUnknowns(), 1.0, 2.0);
    std::vector<BoundRecord> records;
    BoundsOptions o;
    o.on_bound = [&](const BoundRecord& r) { records.push_back(r); };
    const BoundsReport run = ComputeForceBounds(s, some, reference, o);
    ASSERT_TRUE(run.feasible);
    const BoundsReport made = BoundsFromRecords(s, some, reference, records);
    EXPECT_TRUE(made.feasible);
    EXPECT_TRUE(made.complete) << name;
    ASSERT_EQ(made.bounds.size(), some.size());
    for (std::size_t a = 0; a < some.size(); ++a) {
      EXPECT_EQ(made.bounds[a].contact, some[a]);
      EXPECT_EQ(made.bounds[a].reference, run.bounds[a].reference);
      for (BoundKind kind : {BoundKind::kMax, BoundKind::kMaxWithoutFriction, BoundKind::kMin}) {
        EXPECT_EQ(made.bounds[a].Of(kind).status, run.bounds[a].Of(kind).status)
            << name << " " << ToString(kind);
        EXPECT_EQ(made.bounds[a].Of(kind).value, run.bounds[a].Of(kind).value)
            << name << " " << ToString(kind);
      }
    }
    records.pop_back();  // a bound no process obtained
    EXPECT_FALSE(BoundsFromRecords(s, some, reference, records).complete) << name;
  }
}

// Processes sharing the contacts (mpirun): share s of 2 on one thread solves the block of
// thread s of one process on two threads, bit for bit, and only that block.
TEST(ForceBounds, TwoSharesAreTheBlocksOfTwoThreads) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const std::vector<int> some = {0, 17, 101, 230, 402, 599, 600};
  BoundsOptions two_threads;
  two_threads.threads = 2;
  const BoundsReport whole = ComputeForceBounds(s, some, {}, two_threads);
  std::vector<BoundRecord> shared;
  for (int share : {0, 1}) {
    BoundsOptions o;
    o.shares = 2;
    o.share = share;
    o.on_bound = [&](const BoundRecord& r) { shared.push_back(r); };
    const std::size_t before = shared.size();
    EXPECT_TRUE(ComputeForceBounds(s, some, {}, o).complete);
    EXPECT_GT(shared.size(), before);
    EXPECT_LT(shared.size() - before, 3 * some.size());  // one share only
  }
  ASSERT_EQ(shared.size(), 3 * some.size());
  for (const BoundRecord& r : shared) {
    const std::size_t at = std::find(some.begin(), some.end(), r.contact) - some.begin();
    ASSERT_LT(at, some.size());
    const Bound& expected = whole.bounds[at].Of(r.kind);
    EXPECT_EQ(r.bound.status, expected.status);
    EXPECT_EQ(r.bound.value, expected.value) << ToString(r.kind) << " of " << r.contact;
  }
  BoundsOptions bad;
  bad.shares = 2;
  bad.share = 2;
  EXPECT_THROW(ComputeForceBounds(s, some, {}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace unjam

namespace unjam {
namespace {

// The rank against a dense SVD, whose singular values jump from 1e-2 to 1e-15 here: the
// QR of A alone overestimated it by one on this packing.
TEST(ForceIndeterminacy, RankMatchesADenseSvd) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.1.unjam");
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const Eigen::BDCSVD<Eigen::MatrixXd> svd{Eigen::MatrixXd(s.matrix)};
  const Eigen::VectorXd& sv = svd.singularValues();
  int rank = 0;
  for (int k = 0; k < sv.size(); ++k) rank += sv[k] > 1e-10 * sv[0];
  EXPECT_EQ(ForceIndeterminacy(s).rank, rank);
  EXPECT_EQ(ForceIndeterminacy(s).dimension, s.NumUnknowns() - rank);
}

}  // namespace
}  // namespace unjam
