// The files of the source tree written from the settings tables: doc/parameters.md, config/default.yaml,
// config/pose_graph.yaml and cfg/LoopClosure.cfg. They are committed (dynamic_reconfigure runs the cfg at
// build time, launch files load the YAML); test_parameter_files fails while one differs from what the
// tables give, printing kRegenerateCommand.
#pragma once

#include <string>
#include <vector>

namespace scan_context_loop {

struct GeneratedFile {
  std::string path;    ///< relative to the package's root
  std::string option;  ///< scan_context_parameters' flag that prints it ("--yaml")
  std::string (*text)();
};

const std::vector<GeneratedFile>& generatedFiles();

/// Run from the repository's root after a build: writes every generated file.
extern const char* const kRegenerateCommand;

/// Writes every generated file under `package_dir`; false with `error` naming the file that failed.
bool writeGeneratedFiles(const std::string& package_dir, std::string* error);

/// config/default.yaml: the loop_closure node's keys.
std::string loopClosureYaml();
/// config/pose_graph.yaml: the pose_graph node's keys.
std::string poseGraphYaml();
/// cfg/LoopClosure.cfg: the loop_closure node's live keys.
std::string loopClosureCfg();

}  // namespace scan_context_loop
