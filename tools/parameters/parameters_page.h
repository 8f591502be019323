// doc/parameters.md, written from the settings tables of both nodes (core/settings.h,
// graph/pose_graph_settings.h): `scan_context_parameters` prints it, a test compares it with the file in
// the source tree (generated_files.h).
#pragma once

#include <string>

namespace scan_context_loop {

/// The whole page as Markdown: a section per node, a table row per key (key, type, default, range or
/// choices, live, doc).
std::string parametersPage();

}  // namespace scan_context_loop
