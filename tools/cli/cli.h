// The command-line style every tool in tools/ shares: positional arguments, `--name VALUE` options and
// `--flag` options, processed in order (a later option overrides an earlier one unless it is
// repeatable). `--help` / `-h` anywhere prints the usage text (every option with its description) and
// exits 0; an unknown option, an option without its value, a value that does not convert, or a wrong
// number of positional arguments prints one line naming the problem and exits 2. A value never starts
// with `--`; `--` alone ends the options (everything after it is positional).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace scan_context_loop {
namespace cli {

class Parser {
 public:
  enum class Result { kRun, kHelp, kError };
  /// Takes the value; returns false with a message ("needs a number, got 'x'") when it is not acceptable.
  using Setter = std::function<bool(const std::string& value, std::string* error)>;

  /// `summary` is the paragraph after the synopsis line.
  Parser(std::string program, std::string summary);

  /// A positional argument, in order; required ones must come before optional ones.
  Parser& positional(const std::string& name, const std::string& help, Setter set, bool required = true);
  Parser& positional(const std::string& name, const std::string& help, std::string* value, bool required = true);

  /// Starts a titled group of options in the usage text (options before the first group are under
  /// "options:").
  Parser& section(const std::string& title);

  /// `--name VALUE`; `metavar` names the value in the usage text.
  Parser& option(const std::string& name, const std::string& metavar, const std::string& help, Setter set);
  Parser& option(const std::string& name, const std::string& metavar, const std::string& help, std::string* value);
  Parser& option(const std::string& name, const std::string& metavar, const std::string& help, double* value);
  Parser& option(const std::string& name, const std::string& metavar, const std::string& help, int* value);
  Parser& option(const std::string& name, const std::string& metavar, const std::string& help, std::uint32_t* value);
  /// Repeatable: each occurrence appends its value.
  Parser& option(const std::string& name, const std::string& metavar, const std::string& help,
                 std::vector<std::string>* values);

  /// `--name` without a value.
  Parser& flag(const std::string& name, const std::string& help, std::function<void()> set);
  Parser& flag(const std::string& name, const std::string& help, bool* value);  ///< sets *value = true

  /// Another name for the option registered last, shown beside it.
  Parser& alias(const std::string& name);

  /// Text after the options in the usage text (e.g. options a wrapper script handles).
  Parser& epilogue(const std::string& text);

  /// Parses the arguments (without the program name), calling the setters in order.
  Result parse(const std::vector<std::string>& args, std::string* error) const;

  /// For main(): parses argv; returns -1 to go on, or the exit status after printing the usage text to
  /// stdout (0) or the error to stderr (2).
  int parse(int argc, char** argv) const;

  /// Prints "PROGRAM: error" and the --help hint to stderr; returns 2, the status for bad arguments.
  int fail(const std::string& error) const;

  /// The usage text --help prints.
  std::string usage() const;
  /// The synopsis line: "usage: PROGRAM ARGS [options]".
  std::string synopsis() const;

  const std::string& program() const { return program_; }

 private:
  struct Entry {
    std::vector<std::string> names;  // options: "--x" (first is the main name); positionals: "NAME"
    std::string metavar;             // empty for flags
    std::string help;
    Setter set;
    bool required = true;  // positionals only
    std::string section;
  };
  const Entry* find(const std::string& name) const;
  Parser& add(Entry entry);

  std::string program_, summary_, epilogue_, section_;
  std::vector<Entry> positionals_, options_;
};

/// Converters the typed overloads use: the whole string must convert.
bool toDouble(const std::string& text, double* value);
bool toInt(const std::string& text, int* value);
bool toUnsigned(const std::string& text, std::uint64_t* value);

/// Creates a folder and its parents when missing; false with a message when that fails.
bool makeDirectories(const std::string& path, std::string* error);

}  // namespace cli
}  // namespace scan_context_loop
