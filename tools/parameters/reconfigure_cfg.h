// A dynamic_reconfigure description (cfg/LoopClosure.cfg, the Python script dynamic_reconfigure runs at
// build time) written from settings tables: their live rows, a group per Setting::group.
#pragma once

#include <string>
#include <vector>

#include "setting_row.h"

namespace scan_context_loop {

/// Which description: the package, the node and the name of the generated class (LoopClosureConfig).
struct ReconfigureNames {
  std::string package, node, name;
};

/// The script: `header` (comment lines, without "# "), then every live row of `tables`, with its type,
/// default, doc and range: a bound of the row's range is the slider's bound, a side the range leaves open
/// is left out (dynamic_reconfigure's widest). Groups come in the order they first appear.
std::string reconfigureCfg(const std::vector<std::string>& header, const std::vector<std::vector<SettingRow>>& tables,
                           const ReconfigureNames& names);

}  // namespace scan_context_loop
