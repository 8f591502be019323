// The tools' shared command-line parser (tools/cli/cli.h).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "cli.h"

namespace cli = scan_context_loop::cli;
using Result = cli::Parser::Result;

namespace {

struct Values {
  std::string in, out, name = "default", extra;
  double number = 1.5;
  int count = 3;
  std::uint32_t seed = 1;
  std::vector<std::string> sets;
  bool flag = false;
  int procedural = 0;
};

/// A parser shaped like the tools': two required positionals, one optional, values, a repeatable
/// option, flags and an alias.
cli::Parser makeParser(Values* v) {
  cli::Parser p("tool", "Does things.");
  p.positional("IN_DIR", "input folder", &v->in)
      .positional("OUT_DIR", "output folder", &v->out)
      .positional("EXTRA", "an optional third", &v->extra, false)
      .option("--name", "TEXT", "a string", &v->name)
      .option("--number", "M", "a number", &v->number)
      .alias("--number-alias")
      .section("more")
      .option("--count", "N", "an integer", &v->count)
      .option("--seed", "N", "an unsigned seed", &v->seed)
      .option("--set", "KEY=VALUE", "an override", &v->sets)
      .flag("--flag", "a flag", &v->flag)
      .flag("--procedural", "a flag with its own action", [v] { ++v->procedural; });
  return p;
}

Result parse(const cli::Parser& p, const std::vector<std::string>& args, std::string* error) {
  return p.parse(args, error);
}

}  // namespace

TEST(Cli, PositionalsOptionsAndFlagsInAnyOrder) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  ASSERT_EQ(parse(p,
                  {"--name", "x", "a", "--number", "-2.5", "--flag", "b", "--count", "-7", "--seed", "42", "--set",
                   "k=1", "--set", "j=-1", "--procedural"},
                  &error),
            Result::kRun)
      << error;
  EXPECT_EQ(v.in, "a");
  EXPECT_EQ(v.out, "b");
  EXPECT_EQ(v.extra, "");
  EXPECT_EQ(v.name, "x");
  EXPECT_DOUBLE_EQ(v.number, -2.5);
  EXPECT_EQ(v.count, -7);
  EXPECT_EQ(v.seed, 42u);
  EXPECT_EQ(v.sets, (std::vector<std::string>{"k=1", "j=-1"}));
  EXPECT_TRUE(v.flag);
  EXPECT_EQ(v.procedural, 1);
  EXPECT_TRUE(error.empty());
}

TEST(Cli, DefaultsStayWhenOptionsAreAbsentAndAliasesWork) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  ASSERT_EQ(parse(p, {"a", "b", "c", "--number-alias", "7"}, &error), Result::kRun) << error;
  EXPECT_EQ(v.extra, "c");
  EXPECT_EQ(v.name, "default");
  EXPECT_DOUBLE_EQ(v.number, 7.0);
  EXPECT_EQ(v.count, 3);
  EXPECT_FALSE(v.flag);
}

TEST(Cli, UnknownOptionIsAnErrorNamingIt) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  EXPECT_EQ(parse(p, {"a", "b", "--colour", "red"}, &error), Result::kError);
  EXPECT_NE(error.find("unknown option --colour"), std::string::npos) << error;
  EXPECT_EQ(parse(p, {"a", "b", "-x"}, &error), Result::kError);
  EXPECT_NE(error.find("-x"), std::string::npos) << error;
}

TEST(Cli, MissingValueIsAnErrorNamingTheOption) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  EXPECT_EQ(parse(p, {"a", "b", "--name"}, &error), Result::kError);
  EXPECT_NE(error.find("--name needs a value"), std::string::npos) << error;
  // The next option is not taken as the value.
  EXPECT_EQ(parse(p, {"a", "b", "--count", "--flag"}, &error), Result::kError);
  EXPECT_NE(error.find("--count needs a value"), std::string::npos) << error;
}

TEST(Cli, BadNumbersAreErrorsNamingTheOption) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  for (const auto& bad : std::vector<std::vector<std::string>>{{"--number", "abc"},
                                                               {"--number", "2m"},
                                                               {"--count", "1.5"},
                                                               {"--count", "99999999999"},
                                                               {"--seed", "-1"},
                                                               {"--seed", "4294967296"}}) {
    std::vector<std::string> args = {"a", "b"};
    args.insert(args.end(), bad.begin(), bad.end());
    EXPECT_EQ(parse(p, args, &error), Result::kError) << bad[0] << " " << bad[1];
    EXPECT_NE(error.find(bad[0]), std::string::npos) << error;
    EXPECT_NE(error.find(bad[1]), std::string::npos) << error;
  }
}

TEST(Cli, PositionalCountIsChecked) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  EXPECT_EQ(parse(p, {}, &error), Result::kError);
  EXPECT_NE(error.find("missing argument IN_DIR"), std::string::npos) << error;
  EXPECT_EQ(parse(p, {"a", "--flag"}, &error), Result::kError);
  EXPECT_NE(error.find("missing argument OUT_DIR"), std::string::npos) << error;
  EXPECT_EQ(parse(p, {"a", "b", "c", "d"}, &error), Result::kError);
  EXPECT_NE(error.find("unexpected argument 'd'"), std::string::npos) << error;

  cli::Parser none("none", "");
  EXPECT_EQ(none.parse({}, &error), Result::kRun) << error;
  EXPECT_EQ(none.parse({"x"}, &error), Result::kError);
  EXPECT_NE(error.find("unexpected argument 'x'"), std::string::npos) << error;
}

TEST(Cli, DoubleDashEndsTheOptions) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  ASSERT_EQ(parse(p, {"--flag", "--", "--odd-name", "-h"}, &error), Result::kRun) << error;
  EXPECT_EQ(v.in, "--odd-name");
  EXPECT_EQ(v.out, "-h");
}

TEST(Cli, HelpAnywhereWinsOverErrors) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::string error;
  EXPECT_EQ(parse(p, {"--help"}, &error), Result::kHelp);
  EXPECT_EQ(parse(p, {"a", "--unknown", "-h"}, &error), Result::kHelp);
  EXPECT_EQ(parse(p, {"--count", "x", "--help"}, &error), Result::kHelp);
}

TEST(Cli, HelpTextListsEveryOptionAndArgument) {
  Values v;
  const cli::Parser p = makeParser(&v);
  const std::string usage = p.usage();
  EXPECT_EQ(usage.rfind("usage: tool IN_DIR OUT_DIR [EXTRA] [options]\n", 0), 0u) << usage;
  for (const char* s : {"Does things.", "IN_DIR",     "OUT_DIR",          "EXTRA",           "--name TEXT",
                        "a string",     "--number M", "--number-alias M", "a number",        "more:",
                        "--count N",    "an integer", "--seed N",         "--set KEY=VALUE", "an override (repeatable)",
                        "--flag",       "a flag",     "--procedural",     "--help",          "-h"}) {
    EXPECT_NE(usage.find(s), std::string::npos) << s << " missing from\n" << usage;
  }
  // Every line fits the width the tools print at.
  std::size_t start = 0;
  while (start < usage.size()) {
    const std::size_t end = usage.find('\n', start);
    EXPECT_LE(end - start, 108u) << usage.substr(start, end - start);
    start = end + 1;
  }
}

TEST(Cli, MainStyleParseReturnsTheExitStatus) {
  Values v;
  const cli::Parser p = makeParser(&v);
  std::vector<std::string> storage = {"tool", "a", "b"};
  std::vector<char*> argv;
  for (auto& s : storage) argv.push_back(&s[0]);
  EXPECT_EQ(p.parse(static_cast<int>(argv.size()), argv.data()), -1);

  storage = {"tool", "--bogus"};
  argv.clear();
  for (auto& s : storage) argv.push_back(&s[0]);
  testing::internal::CaptureStderr();
  EXPECT_EQ(p.parse(static_cast<int>(argv.size()), argv.data()), 2);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("tool: unknown option --bogus"), std::string::npos) << err;

  storage = {"tool", "--help"};
  argv.clear();
  for (auto& s : storage) argv.push_back(&s[0]);
  testing::internal::CaptureStdout();
  EXPECT_EQ(p.parse(static_cast<int>(argv.size()), argv.data()), 0);
  EXPECT_EQ(testing::internal::GetCapturedStdout(), p.usage());
}

TEST(Cli, MakeDirectoriesCreatesParents) {
  namespace fs = std::filesystem;
  const fs::path base = fs::path(testing::TempDir()) / ("scl_cli_test_" + std::to_string(::getpid()));
  std::string error;
  ASSERT_TRUE(cli::makeDirectories((base / "a/b/c").string(), &error)) << error;
  EXPECT_TRUE(fs::is_directory(base / "a/b/c"));
  EXPECT_TRUE(cli::makeDirectories((base / "a/b/c").string(), &error)) << error;  // already there
  std::ofstream(base / "plain") << "x";
  EXPECT_FALSE(cli::makeDirectories((base / "plain/sub").string(), &error));
  EXPECT_NE(error.find("plain/sub"), std::string::npos) << error;
  fs::remove_all(base);
}
