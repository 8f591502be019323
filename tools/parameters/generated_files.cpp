#include "generated_files.h"

#include <fstream>

#include "defaults_yaml.h"
#include "parameters_page.h"
#include "reconfigure_cfg.h"
#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/graph/pose_graph_settings.h"

namespace scan_context_loop {

const char* const kRegenerateCommand = "build/ws/devel/lib/scan_context_loop/scan_context_parameters --write .";

namespace {

/// The last lines of each file's header.
std::vector<std::string> generatedFrom(const std::string& table_file) {
  return {"Written from the settings tables by `scan_context_parameters --write` (doc/parameters.md): change",
          "a row of " + table_file + ", not this file."};
}

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

std::string loopClosureYaml() {
  const std::vector<std::string> header = {
      "scan_context_loop: parameters of the loop-closure nodelet / node, with their defaults.",
      "The evaluator (scripts/evaluate --config FILE) reads the same file: it applies every key but",
      "the node's own (\"the node only\" below), and refuses a key that is not listed here.",
      "Keys marked Live may change while the node runs (rqt_reconfigure, dynparam: cfg/LoopClosure.cfg)."};
  return defaultsYaml(concat(header, generatedFrom("src/core/settings.cpp")),
                      {settingRows(configSettings()), settingRows(nodeSettings())});
}

std::string poseGraphYaml() {
  const std::vector<std::string> header = {
      "scan_context_loop: parameters of the reference pose-graph backend (pose_graph nodelet / node),",
      "with their defaults. A private parameter that is not listed here stops the node. Load it with",
      "<rosparam command=\"load\" file=\"$(find scan_context_loop)/config/pose_graph.yaml\"/>."};
  return defaultsYaml(
      concat(header, generatedFrom("src/graph/pose_graph_settings.cpp")),
      {settingRows(poseGraphSettings()), settingRows(keyframeMapSettings()), settingRows(poseGraphNodeSettings())});
}

std::string loopClosureCfg() {
  const std::vector<std::string> header = {
      "The settings the node takes while running (rqt_reconfigure, dynparam): the keys marked live in",
      "src/core/settings.cpp, with the same names, types, defaults and ranges (test/ros/test_live_settings.cpp",
      "checks them): a bound of the table's range is the slider's bound, and a side the table leaves open is",
      "left out here (dynamic_reconfigure's widest: infinity for a double). They apply from the next keyframe",
      "on; the database is kept. Keys that shape stored data (grid, ranges, voxels, exclusion windows) are read",
      "once at start."};
  return reconfigureCfg(concat(header, generatedFrom("src/core/settings.cpp")),
                        {settingRows(configSettings()), settingRows(nodeSettings())},
                        {"scan_context_loop", "loop_closure", "LoopClosure"});
}

const std::vector<GeneratedFile>& generatedFiles() {
  static const std::vector<GeneratedFile> files = {
      {"doc/parameters.md", "--markdown", parametersPage},
      {"config/default.yaml", "--yaml", loopClosureYaml},
      {"config/pose_graph.yaml", "--pose-graph-yaml", poseGraphYaml},
      {"cfg/LoopClosure.cfg", "--cfg", loopClosureCfg},
  };
  return files;
}

bool writeGeneratedFiles(const std::string& package_dir, std::string* error) {
  for (const auto& file : generatedFiles()) {
    const std::string path = package_dir + "/" + file.path;
    // Truncating keeps the file's mode: the cfg stays executable.
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << file.text();
    out.close();
    if (!out) {
      *error = "cannot write " + path;
      return false;
    }
  }
  return true;
}

}  // namespace scan_context_loop
