// README's short table of the settings to change first gives the settings tables' defaults (the files
// written whole from the tables are checked by test_parameter_files).
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {
namespace {

/// The default of `key` in the loop_closure node's tables as text, or "" when no row has that key.
std::string defaultOf(const std::string& key) {
  if (const auto* s = findSetting(configSettings(), key)) return s->get(Config());
  if (const auto* s = findSetting(nodeSettings(), key)) return s->get(NodeOptions());
  return "";
}

/// Two defaults agree as text, or as numbers ("2.0" and "2").
bool sameValue(const std::string& a, const std::string& b) {
  if (a == b) return true;
  char* end_a = nullptr;
  char* end_b = nullptr;
  const double x = std::strtod(a.c_str(), &end_a), y = std::strtod(b.c_str(), &end_b);
  return !a.empty() && !b.empty() && *end_a == '\0' && *end_b == '\0' && x == y;
}

TEST(ReadmeSettings, ReadmeSettingsTableGivesTheTablesDefaults) {
  std::ifstream file(std::string(SCL_PACKAGE_DIR) + "/README.md");
  ASSERT_TRUE(file.good());
  // Rows of "## Settings to change first": | keys (each in backticks) | defaults, comma-separated | what |
  const std::regex key_pattern("`([a-z_0-9]+)`");
  std::string line;
  bool in_section = false;
  int rows = 0;
  while (std::getline(file, line)) {
    if (line.rfind("## ", 0) == 0) in_section = line == "## Settings to change first";
    if (!in_section || line.rfind("| [`", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 3u) << line;
    std::vector<std::string> keys, defaults;
    for (std::sregex_iterator m(cells[0].begin(), cells[0].end(), key_pattern), done; m != done; ++m) {
      keys.push_back((*m)[1]);
    }
    std::stringstream values(cells[1]);
    for (std::string v; std::getline(values, v, ',');) {
      v.erase(0, v.find_first_not_of(' '));
      v.erase(v.find_last_not_of(' ') + 1);
      defaults.push_back(v);
    }
    ASSERT_EQ(keys.size(), defaults.size()) << "a default for each key: " << line;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const std::string expected = defaultOf(keys[i]);
      EXPECT_FALSE(expected.empty()) << "README names `" << keys[i] << "`, which is no key";
      EXPECT_TRUE(sameValue(defaults[i], expected))
          << "README gives `" << keys[i] << "` the default " << defaults[i] << ", the table " << expected;
    }
    ++rows;
  }
  EXPECT_GE(rows, 5) << "README's settings table was not found";
}

}  // namespace
}  // namespace scan_context_loop
