#include "setting_row.h"

#include <cctype>
#include <sstream>

namespace scan_context_loop {

const char* typeName(SettingType type) {
  switch (type) {
    case SettingType::kInt:
      return "int";
    case SettingType::kDouble:
      return "double";
    case SettingType::kBool:
      return "bool";
    case SettingType::kChoice:
      return "choice";
    case SettingType::kString:
      return "string";
  }
  return "";
}

std::string allowedText(const SettingRow& row, std::string (*quote)(const std::string&)) {
  std::string allowed;
  if (row.number) {
    allowed = row.range.interval() + row.range.note;
  } else {
    for (const auto& c : row.choices) allowed += (allowed.empty() ? "" : ", ") + quote(c);
  }
  if (!row.extra_rule.empty()) allowed += (allowed.empty() ? "" : "; ") + row.extra_rule;
  return allowed;
}

std::string floatText(double v) {
  std::ostringstream out;
  out.precision(15);
  out << v;
  std::string text = out.str();
  if (text.find_first_of("in") != std::string::npos) return text;  // inf, nan: never a default
  const std::size_t exponent = text.find('e');
  if (text.find('.') == std::string::npos) text.insert(exponent == std::string::npos ? text.size() : exponent, ".0");
  return text;
}

std::vector<std::string> wrapped(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::istringstream words(text);
  std::string line;
  for (std::string word; words >> word;) {
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string sentence(const std::string& text) {
  if (text.empty()) return text;
  std::string out = text;
  // Only a plain word: a doc may begin with a name ("lio_loop:", "odom:", "tf mode:", "x, y, z").
  std::string first = out.substr(0, out.find(' '));
  if (!first.empty() && first.back() == ',') first.pop_back();
  bool plain = first != "tf" && (first.size() > 1 || first == "a");
  for (char c : first) plain = plain && ((c >= 'a' && c <= 'z') || c == '-');
  if (plain) out[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(out[0])));
  if (out.back() != '.') out += '.';
  return out;
}

}  // namespace scan_context_loop
