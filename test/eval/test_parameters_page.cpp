// doc/parameters.md is the page the settings tables give now (tools/parameters_page.h).
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "parameters_page.h"

namespace scan_context_loop {
namespace {

TEST(ParametersPage, DocParametersIsWrittenFromTheTables) {
  std::ifstream file(std::string(SCL_PACKAGE_DIR) + "/doc/parameters.md");
  ASSERT_TRUE(file.good()) << "doc/parameters.md is missing; regenerate with: rosrun scan_context_loop "
                              "scan_context_parameters > doc/parameters.md";
  std::ostringstream text;
  text << file.rdbuf();
  EXPECT_TRUE(text.str() == parametersPage())
      << "doc/parameters.md is not the settings tables' page; regenerate with: rosrun scan_context_loop "
         "scan_context_parameters > doc/parameters.md";
}

}  // namespace
}  // namespace scan_context_loop
