#include "parameters_page.h"

#include <sstream>
#include <vector>

#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/graph/pose_graph_settings.h"
#include "setting_row.h"

namespace scan_context_loop {

namespace {

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

void table(std::ostringstream& out, const std::string& title, const std::vector<SettingRow>& rows) {
  out << "### " << title << "\n\n";
  out << "| key | type | default | range / choices | live | doc |\n";
  out << "| --- | --- | --- | --- | --- | --- |\n";
  for (const auto& r : rows) {
    std::string doc = r.doc;
    for (const auto& old_key : r.deprecated_keys) doc += " (formerly " + code(old_key) + ", still read with a warning)";
    out << "| " << code(r.key) << " | " << typeName(r.type) << " | " << code(r.default_text) << " | "
        << cell(allowedText(r, code)) << " | " << (r.live ? "yes" : "") << " | " << cell(doc) << " |\n";
  }
  out << "\n";
}

}  // namespace

std::string parametersPage() {
  std::ostringstream out;
  out << "# Parameters\n\n"
         "Every private parameter of both nodes, written from their settings tables (src/core/settings.cpp,\n"
         "src/graph/pose_graph_settings.cpp). A parameter that is no key stops the node, naming it. Ranges:\n"
         "`[a, b]` includes both ends, `(a, b]` excludes a; a value must be finite. Live keys may change while\n"
         "running (dynamic_reconfigure, cfg/LoopClosure.cfg).\n\n"
         "A new setting is one row of a table (beside its member in the struct): key, member, range, group,\n"
         "doc and details. This page, config/default.yaml, config/pose_graph.yaml and cfg/LoopClosure.cfg are\n"
         "written from the tables; after changing a row, regenerate them from the repository's root with\n"
         "`build/ws/devel/lib/scan_context_loop/scan_context_parameters --write .` (or `rosrun scan_context_loop\n"
         "scan_context_parameters --write $(rospack find scan_context_loop)`). test_parameter_files fails,\n"
         "printing that command, while a committed file differs from what the tables give.\n\n";
  out << "## loop_closure\n\n"
         "config/default.yaml lists every key with its default and a comment. The evaluator\n"
         "(`scripts/evaluate --config FILE --set KEY=VALUE`) reads the core keys and accepts the node keys.\n\n";
  table(out, "Core keys", settingRows(configSettings()));
  table(out, "Node keys", settingRows(nodeSettings()));
  out << "## pose_graph\n\n"
         "The reference backend (launch/pose_graph.launch); config/pose_graph.yaml lists every key with its\n"
         "default and a comment.\n\n";
  table(out, "Graph keys", settingRows(poseGraphSettings()));
  table(out, "Map keys", settingRows(keyframeMapSettings()));
  table(out, "Node keys", settingRows(poseGraphNodeSettings()));
  std::string text = out.str();
  text.pop_back();  // one newline at the end
  return text;
}

}  // namespace scan_context_loop
