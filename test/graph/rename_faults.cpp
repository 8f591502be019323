#include "rename_faults.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <csignal>
#include <cstdio>

#include <atomic>

namespace scan_context_loop {
namespace test {
namespace {

std::atomic<int> kill_at{0};
std::atomic<int> seen{0};

/// Counts a rename; kills the process if it is the one to die at.
void beforeRename() {
  const int n = ++seen;
  if (kill_at > 0 && n == kill_at) ::raise(SIGKILL);
}

template <typename F>
F real(const char* name) {
  return reinterpret_cast<F>(::dlsym(RTLD_NEXT, name));
}

}  // namespace

void killAtRename(int n) {
  seen = 0;
  kill_at = n;
}

int renamesSeen() { return seen; }

}  // namespace test
}  // namespace scan_context_loop

extern "C" int rename(const char* from, const char* to) noexcept {
  using F = int (*)(const char*, const char*);
  static const F next = scan_context_loop::test::real<F>("rename");
  scan_context_loop::test::beforeRename();
  return next(from, to);
}

extern "C" int renameat2(int from_dir, const char* from, int to_dir, const char* to, unsigned int flags) noexcept {
  using F = int (*)(int, const char*, int, const char*, unsigned int);
  static const F next = scan_context_loop::test::real<F>("renameat2");
  scan_context_loop::test::beforeRename();
  return next(from_dir, from, to_dir, to, flags);
}
