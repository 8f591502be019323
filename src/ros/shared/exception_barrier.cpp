#include "shared/exception_barrier.h"

#include <exception>

namespace scan_context_loop {

bool runCatching(const std::function<void()>& work, std::string* what) {
  try {
    work();
    return true;
  } catch (const std::exception& e) {
    if (what) *what = e.what();
  } catch (...) {
    if (what) *what = "an exception that is not a std::exception";
  }
  return false;
}

}  // namespace scan_context_loop
