#include "child_process.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

extern char** environ;

namespace scan_context_loop {
namespace test {
namespace {

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Child::Child(const std::vector<std::string>& args, const std::vector<std::string>& environment) {
  std::vector<char*> argv, envp;
  argv.push_back(const_cast<char*>("rosrun"));
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  for (char** e = environ; *e; ++e) envp.push_back(*e);
  for (const auto& e : environment) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  if (posix_spawnp(&pid_, "rosrun", nullptr, nullptr, argv.data(), envp.data()) != 0) pid_ = -1;
}

Child::~Child() {
  if (pid_ > 0 && !exited_) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

bool Child::running() {
  poll();
  return pid_ > 0 && !exited_;
}

bool Child::stop(int signal, double seconds, double* took) {
  const double start = wallSeconds();
  kill(pid_, signal);
  while (wallSeconds() - start < seconds) {
    if (poll()) {
      *took = wallSeconds() - start;
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  *took = wallSeconds() - start;
  return false;
}

std::string Child::how() const {
  if (!exited_) return "still running";
  if (WIFEXITED(status_)) return "exit status " + std::to_string(WEXITSTATUS(status_));
  return "killed by signal " + std::to_string(WTERMSIG(status_));
}

bool Child::exitedCleanly() const { return exited_ && WIFEXITED(status_) && WEXITSTATUS(status_) == 0; }

bool Child::poll() {
  if (exited_) return true;
  if (pid_ <= 0) return false;
  if (waitpid(pid_, &status_, WNOHANG) == pid_) exited_ = true;
  return exited_;
}

}  // namespace test
}  // namespace scan_context_loop
