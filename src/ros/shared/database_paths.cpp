#include "shared/database_paths.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

#include <sys/stat.h>

#include "scan_context_loop/core/file_io.h"

namespace scan_context_loop {

namespace {

std::string nameOf(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// realpath(3) as a string; "" when `path` cannot be resolved (errno says why).
std::string resolved(const std::string& path) {
  char buffer[PATH_MAX];
  return ::realpath(path.c_str(), buffer) ? std::string(buffer) : std::string();
}

/// mkdir -p, mode 0755.
void makeDirectories(const std::string& path) {
  for (std::size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1)) {
    ::mkdir(path.substr(0, slash).c_str(), 0755);
    if (slash == std::string::npos) return;
  }
}

bool refuse(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

}  // namespace

std::string mapDirectory(const NodeOptions& options) {
  if (!options.database_directory.empty()) return options.database_directory;
  if (!options.database_save.empty()) return directoryOf(options.database_save);
  if (!options.database_load.empty()) return directoryOf(options.database_load);
  return rosHome() + "/scan_context_loop";
}

std::string rosHome() {
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  return ros_home && *ros_home ? ros_home : std::string(home ? home : "") + "/.ros";
}

bool servicePath(const std::string& directory, const std::string& requested, std::string* path, std::string* error,
                 const std::string& setting) {
  if (requested.empty()) return refuse(error, "no path given");
  for (std::size_t begin = 0; begin <= requested.size();) {
    const std::size_t end = std::min(requested.find('/', begin), requested.size());
    if (requested.substr(begin, end - begin) == "..") {
      return refuse(error, requested + ": a path with a \"..\" component is refused");
    }
    begin = end + 1;
  }
  if (directory.empty()) return refuse(error, "no map directory (" + setting + ")");
  makeDirectories(directory);
  const std::string root = resolved(directory);
  if (root.empty()) {
    return refuse(error,
                  "the map directory " + directory + " (" + setting + ") cannot be used: " + std::strerror(errno));
  }
  const std::string full = requested.front() == '/' ? requested : root + "/" + requested;
  const std::string name = nameOf(full);
  if (name.empty() || name == ".") return refuse(error, requested + ": no file name");
  const std::string parent = resolved(directoryOf(full));
  if (parent.empty()) {
    return refuse(error, requested + ": its directory cannot be resolved: " + std::string(std::strerror(errno)) +
                             " (saves go inside the map directory " + root + ", " + setting + ")");
  }
  if (parent != root && parent.compare(0, root.size() + 1, root + "/") != 0) {
    return refuse(error, requested + " is outside the map directory " + root + " (" + setting + "): refused");
  }
  const std::string target = (parent == "/" ? "" : parent) + "/" + name;
  struct stat st;
  if (::lstat(target.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    return refuse(error, requested + " is a symbolic link: refused (name the file itself)");
  }
  *path = target;
  return true;
}

std::string besidePath(const std::string& path, std::time_t now) {
  const std::string directory = directoryOf(path);
  std::string stem = nameOf(path), extension = ".scdb";
  const std::size_t dot = stem.rfind('.');
  if (dot != std::string::npos && dot > 0) {
    extension = stem.substr(dot);
    stem = stem.substr(0, dot);
  }
  const std::string base = directory + "/" + stem + "." + std::to_string(static_cast<long long>(now));
  std::string candidate = base + extension;
  for (int n = 1; fileExists(candidate); ++n) candidate = base + "-" + std::to_string(n) + extension;
  return candidate;
}

bool sameFile(const std::string& a, const std::string& b) {
  struct stat sa, sb;
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

bool fileExists(const std::string& path) {
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0;
}

}  // namespace scan_context_loop
