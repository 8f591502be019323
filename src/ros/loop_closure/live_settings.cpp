#include "loop_closure/live_settings.h"

#include <sstream>

#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {

namespace {

template <typename T>
std::string text(const T& value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

/// Sets `key` to `value` in whichever table has it as a live key; "" or the problem.
std::string setLive(const std::string& key, const std::string& value, Config* config, NodeOptions* options) {
  if (const auto* s = findSetting(configSettings(), key)) {
    if (!s->live) return key + " cannot change while running";
    return s->set(config, value) ? "" : key + " = " + value + ": not " + settingTypeName(s->type, s->choices);
  }
  if (const auto* s = findSetting(nodeSettings(), key)) {
    if (!s->live) return key + " cannot change while running";
    return s->set(options, value) ? "" : key + " = " + value + ": not " + settingTypeName(s->type, s->choices);
  }
  return key + " is no setting";
}

template <typename T>
void addLive(const std::vector<Setting<T>>& table, const T& target, dynamic_reconfigure::Config* message) {
  for (const auto& s : table) {
    if (!s.live) continue;
    if (s.type == SettingType::kInt) {
      dynamic_reconfigure::IntParameter p;
      p.name = s.key;
      p.value = std::stoi(s.get(target));
      message->ints.push_back(p);
    } else if (s.type == SettingType::kDouble) {
      dynamic_reconfigure::DoubleParameter p;
      p.name = s.key;
      p.value = std::stod(s.get(target));
      message->doubles.push_back(p);
    }
  }
}

template <typename T>
void addChanged(const std::vector<Setting<T>>& table, const T& before, const T& after, std::vector<std::string>* out) {
  for (const auto& s : table) {
    if (s.live && s.get(before) != s.get(after)) out->push_back(s.key + " " + s.get(before) + " -> " + s.get(after));
  }
}

}  // namespace

bool applyLiveSettings(const dynamic_reconfigure::Config& message, Config* config, NodeOptions* options,
                       std::string* error) {
  Config next_config = *config;
  NodeOptions next_options = *options;
  std::vector<std::string> problems;
  auto apply = [&](const std::string& key, const std::string& value) {
    const std::string problem = setLive(key, value, &next_config, &next_options);
    if (!problem.empty()) problems.push_back(problem);
  };
  for (const auto& p : message.ints) apply(p.name, text(p.value));
  for (const auto& p : message.doubles) apply(p.name, text(p.value));
  for (const auto& p : message.bools) apply(p.name, p.value ? "true" : "false");
  for (const auto& p : message.strs) apply(p.name, p.value);
  if (problems.empty()) {
    for (const auto& p : next_config.validate()) problems.push_back(p);
    for (const auto& p : checkSettings(nodeSettings(), next_options)) problems.push_back(p);
  }
  if (!problems.empty()) {
    error->clear();
    for (const auto& p : problems) *error += (error->empty() ? "" : "; ") + p;
    return false;
  }
  *config = next_config;
  *options = next_options;
  return true;
}

dynamic_reconfigure::Config liveSettingsMessage(const Config& config, const NodeOptions& options) {
  dynamic_reconfigure::Config message;
  addLive(configSettings(), config, &message);
  addLive(nodeSettings(), options, &message);
  return message;
}

std::vector<std::string> liveSettingsChanged(const Config& before, const NodeOptions& before_options,
                                             const Config& after, const NodeOptions& after_options) {
  std::vector<std::string> changed;
  addChanged(configSettings(), before, after, &changed);
  addChanged(nodeSettings(), before_options, after_options, &changed);
  return changed;
}

}  // namespace scan_context_loop
