// dynamic_reconfigure's messages and the live settings (Setting::live in settings.h), by key name: the
// generated LoopClosureConfig (cfg/LoopClosure.cfg) carries the same names, so nothing here knows its
// fields.
#pragma once

#include <string>
#include <vector>

#include <dynamic_reconfigure/Config.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

/// Sets every value of `message` on `config` / `options` by its key, then checks the result whole
/// (Config::validate, the node options' rules). False, with `error` naming the keys, when a name is not
/// a live key of either table or a value breaks a rule; `config` and `options` are then unchanged.
bool applyLiveSettings(const dynamic_reconfigure::Config& message, Config* config, NodeOptions* options,
                       std::string* error);

/// The live values of `config` and `options` as a message (what is in force, to report after a refusal).
dynamic_reconfigure::Config liveSettingsMessage(const Config& config, const NodeOptions& options);

/// "key old -> new" for every live setting that differs between `before` and `after`.
std::vector<std::string> liveSettingsChanged(const Config& before, const NodeOptions& before_options,
                                             const Config& after, const NodeOptions& after_options);

}  // namespace scan_context_loop
