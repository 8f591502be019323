// Builders for the rows of a settings table (settings.h): one call per key, naming its member, range, doc
// and (optionally) details; group() gives a run of rows its group. Private to the package's sources; the
// loop_closure tables (settings.cpp) and the pose_graph tables (graph/pose_graph_settings.cpp) use them.
#pragma once

#include <initializer_list>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {
namespace rows {

constexpr double kInf = std::numeric_limits<double>::infinity();

inline bool parseBool(const std::string& text, bool* out) {
  if (text == "true" || text == "1") {
    *out = true;
    return true;
  }
  if (text == "false" || text == "0") {
    *out = false;
    return true;
  }
  return false;
}

inline bool parseInt(const std::string& text, int* out) {
  std::istringstream in(text);
  long long v;
  char extra;
  if (!(in >> v) || (in >> extra) || v < -2147483647LL || v > 2147483647LL) return false;
  *out = static_cast<int>(v);
  return true;
}

inline bool parseDouble(const std::string& text, double* out) {
  std::istringstream in(text);
  double v;
  char extra;
  if (!(in >> v) || (in >> extra)) return false;
  *out = v;
  return true;
}

/// A number as the tables print it: 15 significant digits, the shortest form.
inline std::string numberText(double v) {
  std::ostringstream out;
  out.precision(15);
  out << v;
  return out.str();
}

inline std::string intText(int v) { return std::to_string(v); }

inline SettingRange closed(double low, double high, const char* note = "") { return {low, high, false, false, note}; }
inline SettingRange atLeast(double low, const char* note = "") { return {low, kInf, false, false, note}; }
inline SettingRange positive(const char* note = "") { return {0.0, kInf, true, false, note}; }
inline SettingRange openLow(double low, double high, const char* note = "") { return {low, high, true, false, note}; }

/// The member a row sets, as a function of the table's struct.
template <typename T, typename V>
using Ref = V& (*)(T&);

/// A number member of type V (int or double), parsed with `parse` and printed with `print`.
template <typename T, typename V>
Setting<T> numberSetting(const char* key, SettingType type, Ref<T, V> ref, SettingRange range, const char* doc,
                         const char* details, bool (*parse)(const std::string&, V*), std::string (*print)(V)) {
  Setting<T> s;
  s.key = key;
  s.type = type;
  s.doc = doc;
  s.details = details;
  s.get = [ref, print](const T& t) { return print(ref(const_cast<T&>(t))); };
  s.set = [ref, parse](T* t, const std::string& text) { return parse(text, &ref(*t)); };
  s.number = [ref](const T& t) { return static_cast<double>(ref(const_cast<T&>(t))); };
  s.range = std::move(range);
  return s;
}

template <typename T>
Setting<T> intSetting(const char* key, Ref<T, int> ref, SettingRange range, const char* doc, const char* details = "") {
  return numberSetting<T, int>(key, SettingType::kInt, ref, std::move(range), doc, details, parseInt, intText);
}

template <typename T>
Setting<T> doubleSetting(const char* key, Ref<T, double> ref, SettingRange range, const char* doc,
                         const char* details = "") {
  return numberSetting<T, double>(key, SettingType::kDouble, ref, std::move(range), doc, details, parseDouble,
                                  numberText);
}

template <typename T>
Setting<T> boolSetting(const char* key, Ref<T, bool> ref, const char* doc, const char* details = "") {
  Setting<T> s;
  s.key = key;
  s.type = SettingType::kBool;
  s.doc = doc;
  s.details = details;
  s.get = [ref](const T& t) { return std::string(ref(const_cast<T&>(t)) ? "true" : "false"); };
  s.set = [ref](T* t, const std::string& text) { return parseBool(text, &ref(*t)); };
  return s;
}

/// A string member; `allowed` (empty: any) lists the accepted values.
template <typename T>
Setting<T> stringSetting(const char* key, Ref<T, std::string> ref, std::vector<std::string> allowed, const char* doc,
                         const char* details = "") {
  Setting<T> s;
  s.key = key;
  s.type = allowed.empty() ? SettingType::kString : SettingType::kChoice;
  s.doc = doc;
  s.details = details;
  s.choices = allowed;
  s.get = [ref](const T& t) { return ref(const_cast<T&>(t)); };
  s.set = [ref, allowed](T* t, const std::string& text) {
    for (const auto& a : allowed) {
      if (a == text) {
        ref(*t) = text;
        return true;
      }
    }
    if (!allowed.empty()) return false;
    ref(*t) = text;
    return true;
  };
  return s;
}

/// An enum member with its parse and name functions.
template <typename T, typename E>
Setting<T> enumSetting(const char* key, Ref<T, E> ref, bool (*parse)(const std::string&, E*), const char* (*name)(E),
                       std::vector<E> values, const char* doc, const char* details = "") {
  Setting<T> s;
  s.key = key;
  s.type = SettingType::kChoice;
  s.doc = doc;
  s.details = details;
  for (E v : values) s.choices.push_back(name(v));
  s.get = [ref, name](const T& t) { return std::string(name(ref(const_cast<T&>(t)))); };
  s.set = [ref, parse](T* t, const std::string& text) { return parse(text, &ref(*t)); };
  return s;
}

/// The rows, each in `group` (Setting::group).
template <typename T>
std::vector<Setting<T>> group(const SettingGroup& group, std::vector<Setting<T>> rows) {
  for (auto& row : rows) row.group = group;
  return rows;
}

/// The groups' rows in order: a whole table.
template <typename T>
std::vector<Setting<T>> joined(std::initializer_list<std::vector<Setting<T>>> groups) {
  std::vector<Setting<T>> table;
  for (const auto& rows : groups) table.insert(table.end(), rows.begin(), rows.end());
  return table;
}

/// Marks a row Setting::live.
template <typename T>
Setting<T> live(Setting<T> s) {
  s.live = true;
  return s;
}

/// Adds the earlier names a row is still read by (Setting::deprecated_keys).
template <typename T>
Setting<T> formerly(std::vector<std::string> old_keys, Setting<T> s) {
  s.deprecated_keys = std::move(old_keys);
  return s;
}

/// Adds a rule that is not a range (Setting::extra_check), described in `text` (Setting::extra_rule).
template <typename T>
Setting<T> alsoCheck(std::function<std::string(const T&)> rule, const char* text, Setting<T> s) {
  s.extra_check = std::move(rule);
  s.extra_rule = text;
  return s;
}

}  // namespace rows
}  // namespace scan_context_loop

/// A function from the table's struct T to one of its members, for the row builders.
#define SCL_MEMBER(T, expr) +[](T& c) -> decltype((c.expr)) { return c.expr; }
