// Tests for src/io/study_config.cpp: the study's configuration, its size variants and the
// errors that name file, line and key.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "temp_dir_test.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/study_config.hpp"

namespace unjam {
namespace {

class StudyConfigTest : public testing::TempDirTest {
 protected:
  StudyConfigTest() : TempDirTest("unjam_study_config_") {}
  std::filesystem::path Write(const std::string& text) {
    const std::filesystem::path path = dir_ / "study.json";
    std::ofstream(path) << text;
    return path;
  }
  // The message of the InputError reading `text` throws.
  std::string ErrorOf(const std::string& text, const std::string& size = "") {
    try {
      ReadStudyConfig(Write(text), size);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
};

constexpr const char* kStudy = R"({
  "output": "out/s",
  "pressure": [{"n": 500, "mu": [0, 0.5], "seeds": [1, 2], "openings": 20}],
  "gravity": {"n": 200, "width": 8, "mu": [0.1], "seeds": [3], "shifts": ["top"]},
  "sizes": {"tiny": {"output": "out/t", "pressure": {"n": 30, "mu": [0.5], "seeds": [1], "max_steps": 9,
                                                     "openings": 3}}}
})";

TEST_F(StudyConfigTest, ReadsSetsWithTheirDefaults) {
  const StudyConfig c = ReadStudyConfig(Write(kStudy), "");
  EXPECT_EQ(c.output, "out/s");
  ASSERT_EQ(c.pressure.size(), 1u);
  EXPECT_EQ(c.pressure[0].n, 500);
  EXPECT_EQ(c.pressure[0].mu, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(c.pressure[0].seeds, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(c.pressure[0].openings, 20);
  EXPECT_EQ(c.pressure[0].pressure, 1.0);
  EXPECT_EQ(c.pressure[0].modes, (std::vector<std::string>{"fixed-pressure"}));
  EXPECT_TRUE(c.pressure[0].bounds);
  EXPECT_EQ(c.pressure[0].max_steps, 1000000);
  ASSERT_EQ(c.gravity.size(), 1u);
  EXPECT_EQ(c.gravity[0].width, 8.0);
  EXPECT_EQ(c.gravity[0].sides, (std::vector<std::string>{"top"}));
  EXPECT_FALSE(c.resolved.contains("sizes"));
}

TEST_F(StudyConfigTest, ASizeIsAMergePatch) {
  const StudyConfig c = ReadStudyConfig(Write(kStudy), "tiny");
  EXPECT_EQ(c.output, "out/t");
  ASSERT_EQ(c.pressure.size(), 1u);
  EXPECT_EQ(c.pressure[0].n, 30);
  EXPECT_EQ(c.pressure[0].openings, 3);
  EXPECT_EQ(c.pressure[0].max_steps, 9);
  EXPECT_EQ(c.gravity.size(), 1u);  // untouched by the patch
  EXPECT_EQ(c.resolved["output"], "out/t");
}

TEST_F(StudyConfigTest, AnUnknownSizeNamesTheKnownOnes) {
  const std::string e = ErrorOf(kStudy, "huge");
  EXPECT_NE(e.find("no size \"huge\""), std::string::npos) << e;
  EXPECT_NE(e.find("tiny"), std::string::npos) << e;
}

TEST_F(StudyConfigTest, ErrorsNameTheLineAndTheKey) {
  const std::string typo = ErrorOf(
      "{\n  \"output\": \"o\",\n  \"pressure\": {\"mu\": [0.5],\n"
      "    \"seeds\": [1], \"openings\": 4, \"opennings\": 5}\n}");
  EXPECT_NE(typo.find("study.json:4"), std::string::npos) << typo;
  EXPECT_NE(typo.find("pressure.opennings: unknown key"), std::string::npos) << typo;

  const std::string negative =
      ErrorOf("{\"pressure\": {\"mu\": [0.5,\n -1], \"seeds\": [1], \"openings\": 4}}");
  EXPECT_NE(negative.find("pressure.mu[1]: must be a number >= 0"), std::string::npos) << negative;

  const std::string missing = ErrorOf("{\"gravity\": {\"seeds\": [1]}}");
  EXPECT_NE(missing.find("gravity: needs \"mu\""), std::string::npos) << missing;

  const std::string syntax = ErrorOf("{\n\"output\": \"o\",\n\"pressure\": [\n}");
  EXPECT_NE(syntax.find("study.json:4: not valid JSON"), std::string::npos) << syntax;

  const std::string nothing = ErrorOf("{\"output\": \"o\"}");
  EXPECT_NE(nothing.find("names no packings"), std::string::npos) << nothing;

  const std::string mode = ErrorOf(
      "{\"pressure\": {\"mu\": [0.5], \"seeds\": [1], \"openings\": 4, \"modes\": [\"fixed\"]}}");
  EXPECT_NE(mode.find("pressure.modes[0]: must be one of fixed-pressure, fixed-volume"),
            std::string::npos)
      << mode;
}

}  // namespace
}  // namespace unjam
