// The ensemble's decay exponents against fields whose answer is known.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/response_ensemble.hpp"

namespace unjam {
namespace {

// A contact-frame grid of 80 × 80 unit boxes centred on the perturbation, profiles from
// r = 1 to 40, fits over [2, 20].
ResponseLayout Layout() {
  ResponseLayout layout;
  layout.gap = 1.0;
  layout.window = 40.0;
  layout.profile_min = 1.0;
  layout.profile_max = 40.0;
  layout.bins_per_decade = 6;
  layout.field.origin = Vec2(-40.0, -40.0);
  layout.field.side = Vec2(1.0, 1.0);
  layout.field.nx = layout.field.ny = 80;
  layout.stress = layout.field;
  layout.stress.nx = layout.stress.ny = 1;
  return layout;
}

// One "ok" record whose field is, in every box at distance r, r^-1.5 along x plus
// sign · r^-0.5 along y: the y parts cancel in the average over records of both signs.
ReducedResponse Record(const ResponseLayout& layout, double sign) {
  ReducedResponse r;
  r.status = PerturbationStatus::kOk;
  const int boxes = layout.field.nx * layout.field.ny;
  r.field.assign(2 * boxes, 0.0);
  r.field_count.assign(boxes, 1);
  std::vector<double> radii, magnitudes;
  for (int b = 0; b < boxes; ++b) {
    const double d = layout.field.BoxCenter(b).norm();
    r.field[2 * b] = std::pow(d, -1.5);
    r.field[2 * b + 1] = sign * std::pow(d, -0.5);
    radii.push_back(d);
    magnitudes.push_back(std::hypot(r.field[2 * b], r.field[2 * b + 1]));
  }
  for (const LogBin& bin : LogBinned(radii, magnitudes, layout.profile_min, layout.profile_max,
                                     layout.bins_per_decade)) {
    r.displacement_profile.push_back(bin.count > 0 ? bin.mean : std::nan(""));
    r.force_profile.push_back(std::nan(""));
  }
  r.stress.assign(3, 0.0);
  return r;
}

// The paper's d(r) is the magnitude of the averaged field: here r^-1.5, so α = 1.5; the
// mean of each perturbation's |d| decays as r^-0.5 far out, another exponent.
TEST(ResponseEnsemble, ThePapersAlphaIsThatOfTheAveragedField) {
  const ResponseLayout layout = Layout();
  std::vector<ReducedResponse> records;
  for (int k = 0; k < 40; ++k) records.push_back(Record(layout, k % 2 == 0 ? 1.0 : -1.0));
  EnsembleOptions options;
  options.fit_max = 20.0;
  const EnsembleSummary s = Summarize(records, layout, options);
  ASSERT_GE(s.decay.points, 3);
  EXPECT_NEAR(s.decay.alpha, 1.5, 0.02);
  EXPECT_NEAR(s.magnitude_decay.alpha, 0.5, 0.1);
  // The jackknife sees that leaving out blocks of records (each block holds both signs but
  // not always as many) barely moves α.
  EXPECT_LT(s.decay.alpha_error, 0.05);
  // Every F_crit is 0 here: the histograms still have bins (they once indexed by NaN).
  ASSERT_EQ(s.fcrit_raw.counts.size(), static_cast<std::size_t>(options.histogram_bins));
  EXPECT_EQ(s.fcrit_raw.counts[0], 40);
}

// The static stress in a contact frame, coarse-grained over a periodic grid that tiles the
// (square) cell, is the virial stress of the packing: its mean pressure is the packing's
// virial pressure, in the frame of either axis (a quarter turn maps the cell onto itself).
TEST(ResponseEnsemble, StaticStressInAFrameAddsUpToTheVirialPressure) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  ASSERT_EQ(scene.cell.size.x(), scene.cell.size.y());
  const PerturbationBase base = PreparePerturbations(scene, PerturbationOptions{});
  ResponseLayout layout = MakeLayout(base, EnsembleOptions{}, 1e-9);
  const double side = scene.cell.size.x();
  layout.stress.nx = layout.stress.ny = 17;
  layout.stress.side = Vec2(side / 17, side / 17);
  layout.stress.origin = Vec2(-0.5 * side, -0.5 * side);
  layout.stress.periodic_x = layout.stress.periodic_y = true;
  for (const Vec2& axis : {Vec2(1.0, 0.0), Vec2(0.0, 1.0)}) {
    const std::vector<Eigen::Matrix2d> s =
        StaticStressInFrame(base, scene.particles[7].position, axis, layout);
    Eigen::Matrix2d mean = Eigen::Matrix2d::Zero();
    for (const Eigen::Matrix2d& box : s) mean += box / static_cast<double>(s.size());
    EXPECT_NEAR(Pressure(mean), base.pressure, 1e-9 * base.pressure);
  }
}

}  // namespace
}  // namespace unjam
