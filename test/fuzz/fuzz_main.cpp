// libFuzzer's entry point for one target, chosen at compile time: -DSCL_FUZZ_TARGET=cloudInput,
// odometryInput or databaseFile (fuzz_input.h).
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return scan_context_loop::fuzz::SCL_FUZZ_TARGET(data, size);
}
