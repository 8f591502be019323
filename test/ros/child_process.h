// A process a rostest starts itself (a standalone node, a second manager) with rosrun, and stops with a
// signal, waiting for its exit.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace scan_context_loop {
namespace test {

/// A child process (rosrun PACKAGE EXECUTABLE ARGS...) with the environment of this test plus
/// `environment` ("NAME=value" each, e.g. LD_PRELOAD); killed when destroyed still running.
class Child {
 public:
  explicit Child(const std::vector<std::string>& args, const std::vector<std::string>& environment = {});
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  /// Sends `signal`, then waits up to `seconds` for the exit; false when it did not exit in time. *took
  /// is how long it waited [s].
  bool stop(int signal, double seconds, double* took);
  /// The exit status (0 when it exited normally with 0), or a description of how it ended.
  std::string how() const;
  bool exitedCleanly() const;

 private:
  bool poll();
  pid_t pid_ = -1;
  int status_ = 0;
  bool exited_ = false;
};

}  // namespace test
}  // namespace scan_context_loop
