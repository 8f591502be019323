// The files written from the settings tables (tools/parameters/generated_files.h) are committed as the
// tables give them now, and the pieces they are written with keep their formats.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "defaults_yaml.h"
#include "generated_files.h"
#include "setting_row.h"

namespace scan_context_loop {
namespace {

TEST(ParameterFiles, EveryCommittedFileIsWhatTheSettingsTablesGive) {
  for (const auto& file : generatedFiles()) {
    std::ifstream in(std::string(SCL_PACKAGE_DIR) + "/" + file.path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    EXPECT_TRUE(in.good() && text.str() == file.text())
        << file.path << " is not what the settings tables give; regenerate the files from the repository's root "
        << "with: " << kRegenerateCommand << "  (rosrun scan_context_loop scan_context_parameters " << file.option
        << " prints this one)";
  }
}

TEST(ParameterFiles, FloatsReadBackAsFloatsInYamlAndPython) {
  EXPECT_EQ(floatText(2.0), "2.0");
  EXPECT_EQ(floatText(0.015), "0.015");
  EXPECT_EQ(floatText(1073741824.0), "1073741824.0");
  EXPECT_EQ(floatText(-0.5), "-0.5");
  // YAML 1.1 reads "1e-06" as a string: the float needs its point.
  EXPECT_EQ(floatText(1e-6), "1.0e-06");
  EXPECT_EQ(floatText(2.5e20), "2.5e+20");
}

TEST(ParameterFiles, StringsThatWouldReadAsAnotherTypeAreQuoted) {
  SettingRow row;
  row.type = SettingType::kString;
  for (const std::string plain : {"odom", "/team", "map_frame", "a.b-c"}) {
    row.default_text = plain;
    EXPECT_EQ(yamlValue(row), plain);
  }
  for (const std::string quoted : {"", "off", "Yes", "null", "1", "two words", "x: y"}) {
    row.default_text = quoted;
    EXPECT_EQ(yamlValue(row), "\"" + quoted + "\"");
  }
  row.type = SettingType::kDouble;
  row.default_number = 80.0;
  EXPECT_EQ(yamlValue(row), "80.0");
}

TEST(ParameterFiles, TheCommentSaysMeaningRuleLiveAndDefault) {
  SettingRow row;
  row.key = "max_gap";
  row.type = SettingType::kDouble;
  row.doc = "largest gap between two keyframes [m]";
  row.details = "Larger gaps split the session.";
  row.number = true;
  row.range.low = 0.0;
  row.range.note = " (0 disables)";
  row.default_number = 5.0;
  row.live = true;
  EXPECT_EQ(yamlComment(row),
            "Largest gap between two keyframes [m]. Larger gaps split the session. Allowed: >= 0 (0 disables). "
            "Live: may change while running. Default: 5.0.");
  row.doc = "tf mode: how long to wait";  // a name keeps its case
  EXPECT_EQ(yamlComment(row).rfind("tf mode: how long to wait. ", 0), 0u);
}

TEST(ParameterFiles, CommentsWrapAtTheGivenWidth) {
  const auto lines = wrapped("one two three four five", 9);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "one two");
  EXPECT_EQ(lines[1], "three");
  EXPECT_EQ(lines[2], "four five");
}

}  // namespace
}  // namespace scan_context_loop
