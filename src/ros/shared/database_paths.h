// Where the nodes write on request: the map directory that ~save_database names files in (and the one
// the pose_graph node's ~save_map names directories in), the checks a requested path must pass, and the
// file beside a map that a shutdown save must not replace. ROS-free (paths and the file system only),
// so that it is tested without a master.
#pragma once

#include <ctime>
#include <string>

#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

/// The map directory: `database_directory` when set, else the directory of `database_save`, else
/// that of `database_load`, else $ROS_HOME/scan_context_loop ($ROS_HOME defaults to ~/.ros).
std::string mapDirectory(const NodeOptions& options);

/// $ROS_HOME, else ~/.ros.
std::string rosHome();

/// The file a ~save_database call may write for `requested`: a name relative to `directory`, or an
/// absolute path inside it. Refused, with the reason in *error: an empty path, a `..` component, a
/// path whose directory (resolved with realpath, so through symbolic links) is not `directory` or
/// below it, a missing directory, a final component that is a symbolic link. `directory` itself is
/// created when missing. *path is the resolved path. The same checks serve a directory to write in
/// (the last component then names it). `setting` is the parameter that names `directory`, for the
/// messages.
bool servicePath(const std::string& directory, const std::string& requested, std::string* path, std::string* error,
                 const std::string& setting = "database_directory");

/// A path beside `path`, in its directory, that no file has: `<stem>.<now>.<extension>` (`.scdb` when
/// `path` has no extension), with `-1`, `-2`, ... after the time if that name is taken.
std::string besidePath(const std::string& path, std::time_t now);

/// Whether `a` and `b` both exist and are the same file (device and inode).
bool sameFile(const std::string& a, const std::string& b);

/// Whether a file (of any kind) exists at `path`.
bool fileExists(const std::string& path);

/// How a save's log line ends when it replaced a file at `path` (`replacing`): where that file is kept.
std::string backupNote(const std::string& path, bool replacing);

}  // namespace scan_context_loop
