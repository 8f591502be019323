#include "parameters_page.h"

#include <sstream>
#include <vector>

#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/graph/pose_graph_settings.h"

namespace scan_context_loop {

namespace {

const char* typeName(SettingType type) {
  switch (type) {
    case SettingType::kInt: return "int";
    case SettingType::kDouble: return "double";
    case SettingType::kBool: return "bool";
    case SettingType::kChoice: return "choice";
    case SettingType::kString: return "string";
  }
  return "";
}

/// Text in a table cell: a '|' would end the cell.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

std::string code(const std::string& text) { return text.empty() ? "\"\"" : "`" + text + "`"; }

template <typename T>
void table(std::ostringstream& out, const std::string& title, const std::vector<Setting<T>>& rows) {
  const T defaults;
  out << "### " << title << "\n\n";
  out << "| key | type | default | range / choices | live | doc |\n";
  out << "| --- | --- | --- | --- | --- | --- |\n";
  for (const auto& s : rows) {
    std::string allowed;
    if (s.number) {
      allowed = s.range.interval() + s.range.note;
    } else {
      for (const auto& c : s.choices) allowed += (allowed.empty() ? "" : ", ") + code(c);
    }
    if (s.extra_check && s.type == SettingType::kString) allowed += (allowed.empty() ? "" : "; ") + std::string("not empty");
    std::string doc = s.doc;
    for (const auto& old_key : s.deprecated_keys) doc += " (formerly " + code(old_key) + ", still read with a warning)";
    out << "| " << code(s.key) << " | " << typeName(s.type) << " | " << code(s.get(defaults)) << " | "
        << cell(allowed) << " | " << (s.live ? "yes" : "") << " | " << cell(doc) << " |\n";
  }
  out << "\n";
}

}  // namespace

std::string parametersPage() {
  std::ostringstream out;
  out << "# Parameters\n\n"
         "Every private parameter of both nodes, written from their settings tables (src/core/settings.cpp,\n"
         "src/graph/pose_graph_settings.cpp) by `rosrun scan_context_loop scan_context_parameters >\n"
         "doc/parameters.md`; a test fails when this page is not the tables'. A parameter that is no key stops\n"
         "the node, naming it. Ranges: `[a, b]` includes both ends, `(a, b]` excludes a; a value must be\n"
         "finite. Live keys may change while running (dynamic_reconfigure, cfg/LoopClosure.cfg).\n\n";
  out << "## loop_closure\n\n"
         "config/default.yaml lists every key with its default and a comment. The evaluator\n"
         "(`scripts/evaluate --config FILE --set KEY=VALUE`) reads the core keys and accepts the node keys.\n\n";
  table(out, "Core keys", configSettings());
  table(out, "Node keys", nodeSettings());
  out << "## pose_graph\n\n"
         "The reference backend (launch/pose_graph.launch); config/pose_graph.yaml lists every key with its\n"
         "default and a comment.\n\n";
  table(out, "Graph keys", poseGraphSettings());
  table(out, "Map keys", keyframeMapSettings());
  table(out, "Node keys", poseGraphNodeSettings());
  std::string text = out.str();
  text.pop_back();  // one newline at the end
  return text;
}

}  // namespace scan_context_loop
