// The JSON Lines files that long runs append to and resume from (perturb's and bounds'
// records): a torn last line is ignored, any other bad line is named, a header of other
// parameters is refused naming the keys, the files of MPI ranks merge into one, and a file
// without its header line holds nothing yet.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "temp_dir_test.hpp"
#include "unjam/io/json_lines.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

class JsonLinesTest : public testing::TempDirTest {
 protected:
  JsonLinesTest() : TempDirTest("unjam-json-lines-") {}
  std::filesystem::path Write(const std::string& name, const std::string& text) const {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
};

TEST_F(JsonLinesTest, ATornLastLineIsIgnoredAndNotCounted) {
  const std::string whole = "{\"run\":1}\n{\"a\":1}\n{\"a\":2}\n";
  const auto path = Write("r.jsonl", whole + "{\"a\":3, \"tor");
  const JsonLines file = ReadJsonLines(path);
  EXPECT_EQ(file.header, nlohmann::json({{"run", 1}}));
  ASSERT_EQ(file.lines.size(), 2u);
  EXPECT_EQ(file.lines[1].first, 3);  // line numbers count the header
  EXPECT_EQ(file.lines[1].second["a"], 2);
  EXPECT_EQ(file.valid_bytes, whole.size());
}

TEST_F(JsonLinesTest, ABadLineIsNamedByFileAndLine) {
  for (const char* bad : {"not json", "[1, 2]"}) {
    const auto path =
        Write("r.jsonl", std::string("{\"run\":1}\n{\"a\":1}\n") + bad + "\n{\"a\":2}\n");
    try {
      ReadJsonLines(path);
      FAIL() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("r.jsonl:3"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(ReadJsonLines(Write("empty.jsonl", "")), InputError);
  EXPECT_THROW(ReadJsonLines(dir_ / "missing.jsonl"), InputError);
}

TEST_F(JsonLinesTest, AHeaderOfOtherParametersIsRefusedNamingTheKeys) {
  const nlohmann::json expected = {{"run", 1}, {"gap", 1e-9}, {"mode", "a"}};
  EXPECT_NO_THROW(RequireHeader(dir_, expected, expected, "remedy"));
  const nlohmann::json found = {{"run", 1}, {"gap", 1e-8}, {"extra", true}};
  try {
    RequireHeader(dir_ / "r.jsonl", found, expected, "remove it");
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("(gap, mode, extra)"), std::string::npos)
        << what;  // not the equal key "run"
    EXPECT_NE(what.find("r.jsonl"), std::string::npos) << what;
    EXPECT_NE(what.find("remove it"), std::string::npos) << what;
  }
}

TEST_F(JsonLinesTest, TheRanksFilesMergeIntoTheFirstAsTheyWereWritten) {
  const std::string header = "{\"run\":1}\n";
  const auto first = Write("out.csv.records.jsonl", header + "{\"a\":0}\n");
  EXPECT_EQ(RankPath(first, 0), first);
  EXPECT_EQ(RankPath(first, 2), dir_ / "out.csv.records.rank2.jsonl");
  Write("out.csv.records.rank2.jsonl", header + "{\"a\":2}\n{\"a\":3, \"torn");
  Write("out.csv.records.rank1.jsonl", header + "{\"a\":1}\n");
  Write("other.jsonl", header + "{\"a\":9}\n");  // not a rank file of this run
  const auto files = RankFiles(first);
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0], first);
  EXPECT_EQ(files[1].filename(), "out.csv.records.rank1.jsonl");

  MergeRankFiles(first, {{"run", 1}}, "remedy");
  EXPECT_EQ(RankFiles(first), std::vector<std::filesystem::path>{first});
  const JsonLines merged = ReadJsonLines(first);
  ASSERT_EQ(merged.lines.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(merged.lines[k].second["a"], k);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "other.jsonl"));

  Write("out.csv.records.rank1.jsonl", "{\"run\":2}\n");
  EXPECT_THROW(MergeRankFiles(first, {{"run", 1}}, "remedy"), std::invalid_argument);
}

// Under mpirun a rank may look at another's file between its creation and its header line:
// such a file holds nothing yet. It is passed over by the readers, removed by the merge, and
// started afresh by its own rank (as is one a crash left without its header).
TEST_F(JsonLinesTest, AFileWithoutItsHeaderLineHoldsNothingYet) {
  const auto first = Write("r.jsonl", "{\"run\":1}\n");
  const auto creating = Write("r.rank1.jsonl", "");
  const auto torn = Write("r.rank2.jsonl", "{\"ru");
  EXPECT_TRUE(HasHeaderLine(first));
  EXPECT_FALSE(HasHeaderLine(creating));
  EXPECT_FALSE(HasHeaderLine(torn));
  EXPECT_FALSE(HasHeaderLine(dir_ / "missing.jsonl"));
  EXPECT_EQ(RankFiles(first), std::vector<std::filesystem::path>{first});

  {
    std::ofstream own = AppendTo(torn, {{"run", 1}});
    own << "{\"a\":1}\n";
  }
  const JsonLines restarted = ReadJsonLines(torn);
  EXPECT_EQ(restarted.header, nlohmann::json({{"run", 1}}));
  ASSERT_EQ(restarted.lines.size(), 1u);
  {
    std::ofstream own = AppendTo(torn, {{"run", 1}});
    own << "{\"a\":2}\n";
  }  // appends
  EXPECT_EQ(ReadJsonLines(torn).lines.size(), 2u);

  MergeRankFiles(first, {{"run", 1}}, "remedy");
  EXPECT_FALSE(std::filesystem::exists(creating));
  EXPECT_FALSE(std::filesystem::exists(torn));
  EXPECT_EQ(ReadJsonLines(first).lines.size(), 2u);
}

}  // namespace
}  // namespace unjam
