// Tests for src/analysis/study_table.cpp: runs grouped by their parameters, quantities
// combined over packings (one packing: its own error; several: their scatter).
#include <gtest/gtest.h>

#include <cmath>

#include "unjam/analysis/study_table.hpp"

namespace unjam {
namespace {

StudyRun RunOf(double mu, std::uint64_t seed, double ratio, double ratio_error, int used) {
  StudyRun r;
  r.key = {"pressure", 500, kNoValue, 1.0, mu, "fixed-pressure"};
  r.seed = seed;
  r.perturbations = 10;
  r.used = used;
  r.dynamic = 10 - used;
  r.ratio = {ratio, ratio_error, used};
  r.packing_fraction = 0.8 + 0.01 * static_cast<double>(seed);
  return r;
}

TEST(AggregateStudy, OnePackingKeepsItsOwnErrorAndSamples) {
  const std::vector<StudyRow> rows = AggregateStudy({RunOf(0.5, 1, 1.2, 0.05, 7)});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].packings, 1);
  EXPECT_DOUBLE_EQ(rows[0].ratio.mean, 1.2);
  EXPECT_DOUBLE_EQ(rows[0].ratio.error, 0.05);
  EXPECT_EQ(rows[0].ratio.count, 7);
  EXPECT_DOUBLE_EQ(rows[0].dynamic_share, 0.3);
}

TEST(AggregateStudy, SeveralPackingsGiveTheirScatter) {
  // Means 1.0 and 1.4: mean 1.2, sample standard deviation 0.2828, error 0.2.
  const std::vector<StudyRow> rows =
      AggregateStudy({RunOf(0.5, 1, 1.0, 0.01, 5), RunOf(0.5, 2, 1.4, 0.01, 3)});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].packings, 2);
  EXPECT_EQ(rows[0].used, 8);
  EXPECT_EQ(rows[0].perturbations, 20);
  EXPECT_DOUBLE_EQ(rows[0].ratio.mean, 1.2);
  EXPECT_NEAR(rows[0].ratio.error, 0.2, 1e-12);
  EXPECT_EQ(rows[0].ratio.count, 2);
  EXPECT_NEAR(rows[0].packing_fraction.mean, 0.815, 1e-12);
}

TEST(AggregateStudy, APackingWithoutAValueIsLeftOutOfThatQuantity) {
  StudyRun none = RunOf(0.5, 2, kNoValue, kNoValue, 0);
  const std::vector<StudyRow> rows = AggregateStudy({RunOf(0.5, 1, 1.3, 0.1, 4), none});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0].ratio.mean, 1.3);
  EXPECT_DOUBLE_EQ(rows[0].ratio.error, 0.1);
  EXPECT_EQ(rows[0].packings, 2);
  EXPECT_TRUE(std::isnan(rows[0].alpha.mean));
  EXPECT_EQ(rows[0].alpha.count, 0);
}

TEST(AggregateStudy, RowsFollowTheKeysInTheOrderTheyAppear) {
  StudyRun shift = RunOf(0.5, 1, 3.0, 0.1, 4);
  shift.key = {"gravity", 200, 8.0, kNoValue, 0.5, "top"};
  const std::vector<StudyRow> rows = AggregateStudy(
      {RunOf(0.5, 1, 1.0, 0.1, 4), RunOf(0.1, 1, 1.5, 0.1, 4), shift, RunOf(0.5, 2, 1.2, 0.1, 4)});
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].key.mu, 0.5);
  EXPECT_EQ(rows[0].packings, 2);
  EXPECT_EQ(rows[1].key.mu, 0.1);
  EXPECT_EQ(rows[2].key.protocol, "gravity");
}

}  // namespace
}  // namespace unjam
