#include "cli.h"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace scan_context_loop {
namespace cli {

namespace {

constexpr std::size_t kWidth = 108;  // usage text lines stay within this many columns
constexpr std::size_t kColumn = 29;  // descriptions start here

/// Appends `text` word-wrapped, its first line continuing `line` and later lines indented by `indent`.
void wrap(const std::string& text, std::string line, std::size_t indent, std::string* out) {
  std::istringstream words(text);
  std::string word;
  bool first = true;
  while (words >> word) {
    if (!first && line.size() + 1 + word.size() > kWidth) {
      *out += line + "\n";
      line = std::string(indent, ' ');
      first = true;
    }
    if (!first) line += " ";
    line += word;
    first = false;
  }
  *out += line + "\n";
}

void describe(const std::string& left, const std::string& help, std::string* out) {
  std::string line = "  " + left;
  if (line.size() + 1 > kColumn) {
    *out += line + "\n";
    line.clear();
  }
  line.resize(kColumn, ' ');
  wrap(help, line, kColumn, out);
}

bool isNegativeNumber(const std::string& arg) {
  return arg.size() > 1 && arg[0] == '-' && (std::isdigit(static_cast<unsigned char>(arg[1])) || arg[1] == '.');
}

}  // namespace

bool toDouble(const std::string& text, double* value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (*end != '\0' || errno == ERANGE || std::isnan(v)) return false;
  *value = v;
  return true;
}

bool toInt(const std::string& text, int* value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (*end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX) return false;
  *value = static_cast<int>(v);
  return true;
}

bool toUnsigned(const std::string& text, std::uint64_t* value) {
  if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (*end != '\0' || errno == ERANGE) return false;
  *value = v;
  return true;
}

bool makeDirectories(const std::string& path, std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path)) {
    *error = "cannot create the folder " + path + (ec ? ": " + ec.message() : std::string());
    return false;
  }
  return true;
}

Parser::Parser(std::string program, std::string summary) : program_(std::move(program)), summary_(std::move(summary)) {
  Entry help;
  help.names = {"--help", "-h"};
  help.help = "print this help and exit";
  help.section = "\x01";  // listed last, on its own
  options_.push_back(help);
}

Parser& Parser::positional(const std::string& name, const std::string& help, Setter set, bool required) {
  if (required && !positionals_.empty() && !positionals_.back().required) {
    throw std::logic_error("cli: required positional " + name + " after an optional one");
  }
  Entry e;
  e.names = {name};
  e.help = help;
  e.set = std::move(set);
  e.required = required;
  positionals_.push_back(std::move(e));
  return *this;
}

Parser& Parser::positional(const std::string& name, const std::string& help, std::string* value, bool required) {
  return positional(
      name, help,
      [value](const std::string& v, std::string*) {
        *value = v;
        return true;
      },
      required);
}

Parser& Parser::section(const std::string& title) {
  section_ = title;
  return *this;
}

Parser& Parser::add(Entry entry) {
  for (const auto& name : entry.names) {
    if (name.rfind("--", 0) != 0 || find(name)) throw std::logic_error("cli: bad or repeated option name " + name);
  }
  entry.section = section_;
  options_.push_back(std::move(entry));
  return *this;
}

Parser& Parser::option(const std::string& name, const std::string& metavar, const std::string& help, Setter set) {
  Entry e;
  e.names = {name};
  e.metavar = metavar.empty() ? "VALUE" : metavar;
  e.help = help;
  e.set = std::move(set);
  return add(std::move(e));
}

Parser& Parser::option(const std::string& name, const std::string& metavar, const std::string& help,
                       std::string* value) {
  return option(name, metavar, help, [value](const std::string& v, std::string*) {
    *value = v;
    return true;
  });
}

Parser& Parser::option(const std::string& name, const std::string& metavar, const std::string& help, double* value) {
  return option(name, metavar, help, [value](const std::string& v, std::string* error) {
    if (toDouble(v, value)) return true;
    *error = "needs a number, got '" + v + "'";
    return false;
  });
}

Parser& Parser::option(const std::string& name, const std::string& metavar, const std::string& help, int* value) {
  return option(name, metavar, help, [value](const std::string& v, std::string* error) {
    if (toInt(v, value)) return true;
    *error = "needs an integer, got '" + v + "'";
    return false;
  });
}

Parser& Parser::option(const std::string& name, const std::string& metavar, const std::string& help,
                       std::uint32_t* value) {
  return option(name, metavar, help, [value](const std::string& v, std::string* error) {
    std::uint64_t u = 0;
    if (toUnsigned(v, &u) && u <= UINT32_MAX) {
      *value = static_cast<std::uint32_t>(u);
      return true;
    }
    *error = "needs an integer from 0 to 4294967295, got '" + v + "'";
    return false;
  });
}

Parser& Parser::option(const std::string& name, const std::string& metavar, const std::string& help,
                       std::vector<std::string>* values) {
  return option(name, metavar, help + " (repeatable)", [values](const std::string& v, std::string*) {
    values->push_back(v);
    return true;
  });
}

Parser& Parser::flag(const std::string& name, const std::string& help, std::function<void()> set) {
  Entry e;
  e.names = {name};
  e.help = help;
  e.set = [set](const std::string&, std::string*) {
    set();
    return true;
  };
  return add(std::move(e));
}

Parser& Parser::flag(const std::string& name, const std::string& help, bool* value) {
  return flag(name, help, [value] { *value = true; });
}

Parser& Parser::alias(const std::string& name) {
  if (options_.size() < 2 || name.rfind("--", 0) != 0 || find(name)) {
    throw std::logic_error("cli: bad alias " + name);
  }
  options_.back().names.push_back(name);
  return *this;
}

Parser& Parser::epilogue(const std::string& text) {
  epilogue_ = text;
  return *this;
}

const Parser::Entry* Parser::find(const std::string& name) const {
  for (const auto& e : options_) {
    for (const auto& n : e.names) {
      if (n == name) return &e;
    }
  }
  return nullptr;
}

Parser::Result Parser::parse(const std::vector<std::string>& args, std::string* error) const {
  error->clear();
  for (const auto& arg : args) {
    if (arg == "--") break;
    if (arg == "--help" || arg == "-h") return Result::kHelp;
  }
  std::size_t positional = 0;
  bool options_ended = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    std::string message;
    if (!options_ended && arg == "--") {
      options_ended = true;
      continue;
    }
    if (!options_ended && arg.size() > 1 && arg[0] == '-' && !isNegativeNumber(arg)) {
      const Entry* e = find(arg);
      if (!e) {
        *error = "unknown option " + arg;
        return Result::kError;
      }
      std::string value;
      if (!e->metavar.empty()) {
        if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) {
          *error = "option " + arg + " needs a value (" + e->metavar + ")";
          return Result::kError;
        }
        value = args[++i];
      }
      if (!e->set(value, &message)) {
        *error = arg + " " + (message.empty() ? "does not take '" + value + "'" : message);
        return Result::kError;
      }
      continue;
    }
    if (positional >= positionals_.size()) {
      *error = "unexpected argument '" + arg + "' (" +
               (positionals_.empty() ? std::string("takes none") : "at most " + std::to_string(positionals_.size())) +
               ")";
      return Result::kError;
    }
    const Entry& p = positionals_[positional++];
    if (!p.set(arg, &message)) {
      *error = p.names[0] + " " + (message.empty() ? "does not take '" + arg + "'" : message);
      return Result::kError;
    }
  }
  if (positional < positionals_.size() && positionals_[positional].required) {
    *error = "missing argument " + positionals_[positional].names[0];
    return Result::kError;
  }
  return Result::kRun;
}

int Parser::parse(int argc, char** argv) const {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string error;
  switch (parse(args, &error)) {
    case Result::kHelp:
      std::fputs(usage().c_str(), stdout);
      return 0;
    case Result::kError:
      return fail(error);
    case Result::kRun:
      break;
  }
  return -1;
}

int Parser::fail(const std::string& error) const {
  std::fprintf(stderr, "%s: %s\n%s\n'%s --help' lists every option\n", program_.c_str(), error.c_str(),
               synopsis().c_str(), program_.c_str());
  return 2;
}

std::string Parser::synopsis() const {
  std::string s = "usage: " + program_;
  std::size_t optional = 0;
  for (const auto& p : positionals_) {
    if (p.required) {
      s += " " + p.names[0];
    } else {
      s += " [" + p.names[0];
      ++optional;
    }
  }
  s += std::string(optional, ']');
  return s + " [options]";
}

std::string Parser::usage() const {
  std::string out = synopsis() + "\n\n";
  if (!summary_.empty()) {
    std::istringstream paragraphs(summary_);
    std::string paragraph, line;
    while (std::getline(paragraphs, line)) {
      if (line.empty()) {
        if (!paragraph.empty()) wrap(paragraph, "", 0, &out);
        out += "\n";
        paragraph.clear();
      } else {
        paragraph += (paragraph.empty() ? "" : " ") + line;
      }
    }
    if (!paragraph.empty()) wrap(paragraph, "", 0, &out);
    out += "\n";
  }
  if (!positionals_.empty()) {
    out += "arguments:\n";
    for (const auto& p : positionals_) describe(p.names[0], p.help + (p.required ? "" : " (optional)"), &out);
    out += "\n";
  }
  std::string current = "\x02";
  for (std::size_t pass = 0; pass < 2; ++pass) {
    for (const auto& e : options_) {
      const bool help_entry = e.section == "\x01";
      if (help_entry != (pass == 1)) continue;
      if (e.section != current) {
        if (current != "\x02") out += "\n";
        current = e.section;
        if (!help_entry) out += (e.section.empty() ? std::string("options") : e.section) + ":\n";
      }
      std::string left;
      for (const auto& n : e.names) {
        if (!left.empty()) left += ", ";
        left += n + (e.metavar.empty() ? "" : " " + e.metavar);
      }
      describe(left, e.help, &out);
    }
  }
  if (!epilogue_.empty()) {
    out += "\n";
    std::istringstream lines(epilogue_);
    std::string line;
    while (std::getline(lines, line)) out += line + "\n";
  }
  return out;
}

}  // namespace cli
}  // namespace scan_context_loop
