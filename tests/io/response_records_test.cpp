// Perturbation records survive a round trip through JSON Lines bit for bit (a resumed run
// sums exactly what an uninterrupted one would), and a torn last line is dropped.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "unjam/io/packing_file.hpp"
#include "unjam/io/response_records.hpp"

namespace unjam {
namespace {

ReducedResponse SomeRecord() {
  ReducedResponse r;
  r.target.kind = PerturbationTarget::Kind::kParticleShift;
  r.target.i = 4;
  r.target.direction = Vec2(0.0, 1.0);
  r.origin = Vec2(0.1, 1.0 / 3.0);
  r.f_crit = 2.0 / 3.0;
  r.f_reference = std::sqrt(2.0);
  r.penetration_depth = 1e-300;
  r.status = PerturbationStatus::kOk;
  r.rattler = true;
  r.fcrit_10xi = 2.0 / 3.0 + 1e-9;
  r.displacement_profile = {1.5, std::numeric_limits<double>::quiet_NaN(), 0.1};
  r.force_profile = {0.25};
  r.field = {1.0 / 7.0, -2.0};
  r.field_count = {3};
  r.stress = {1.0, 2.0, 3.0};
  return r;
}

TEST(ResponseRecords, RoundTripIsExact) {
  const ReducedResponse a = SomeRecord();
  const ReducedResponse b =
      ReducedResponseFromJson(nlohmann::json::parse(ToJson(a).dump()), "test");
  EXPECT_EQ(b.target.i, 4);
  EXPECT_EQ(b.target.kind, PerturbationTarget::Kind::kParticleShift);
  EXPECT_EQ(b.origin, a.origin);
  EXPECT_EQ(b.f_crit, a.f_crit);
  EXPECT_EQ(b.f_reference, a.f_reference);
  EXPECT_EQ(b.penetration_depth, a.penetration_depth);
  EXPECT_TRUE(b.rattler);
  EXPECT_EQ(b.fcrit_10xi, a.fcrit_10xi);
  EXPECT_TRUE(std::isnan(b.linearity_misfit));  // not a number: null in JSON, NaN again
  ASSERT_EQ(b.displacement_profile.size(), 3u);
  EXPECT_TRUE(std::isnan(b.displacement_profile[1]));
  EXPECT_EQ(b.field, a.field);
  EXPECT_EQ(b.stress, a.stress);
}

TEST(ResponseRecords, TornLastLineIsDroppedAndBadLinesNamed) {
  const auto path = std::filesystem::temp_directory_path() / "unjam_records_test.jsonl";
  const nlohmann::json header = {{"header", 1}};
  nlohmann::json line = ToJson(SomeRecord());
  line["index"] = 3;
  {
    std::ofstream out(path);
    out << header.dump() << '\n' << line.dump() << '\n' << R"({"index": 4, "f_cr)";
  }
  {
    RunRecords run(path, header, 0, "remedy");
    const std::map<int, ReducedResponse> records = RecordsByIndex(run.Entries());
    ASSERT_EQ(records.size(), 1u);
    EXPECT_EQ(records.begin()->first, 3);
  }
  // The torn line is cut off the run's own file before it appends.
  std::ifstream in(path);
  std::string first, second, third;
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_FALSE(std::getline(in, third));
  {
    std::ofstream out(path);
    out << header.dump() << '\n' << R"({"index": 4})" << '\n';
  }
  try {
    RunRecords run(path, header, 0, "remedy");
    RecordsByIndex(run.Entries());
    FAIL() << "a record without fields was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":2"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// Every status a record can hold comes back as itself; any other word is refused where it
// stands, not read as some status.
TEST(ResponseRecords, StatusesRoundTripAndUnknownOnesAreRefused) {
  for (PerturbationStatus s :
       {PerturbationStatus::kOk, PerturbationStatus::kNotConverged, PerturbationStatus::kDynamic,
        PerturbationStatus::kNonlinear, PerturbationStatus::kBlocked}) {
    ReducedResponse r = SomeRecord();
    r.status = s;
    EXPECT_EQ(ReducedResponseFromJson(nlohmann::json::parse(ToJson(r).dump()), "test").status, s);
  }
  nlohmann::json line = ToJson(SomeRecord());
  line["status"] = "maybe";
  try {
    ReducedResponseFromJson(line, "records.jsonl:7");
    FAIL() << "an unknown status was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("records.jsonl:7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("maybe"), std::string::npos) << e.what();
  }
}

// A records file of other parameters is refused, naming it and the remedy.
TEST(ResponseRecords, ARunOfOtherParametersIsRefused) {
  const auto path = std::filesystem::temp_directory_path() / "unjam_records_other.jsonl";
  { RunRecords run(path, {{"run", 1}}, 0, "remedy"); }
  try {
    RunRecords run(path, {{"run", 2}}, 0, "choose another");
    FAIL() << "records of another run were taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("choose another"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace unjam
