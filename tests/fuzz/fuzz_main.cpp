// libFuzzer entry for one target, chosen at compile time (APICLAB_FUZZ_TARGET, CMake option
// APICLAB_FUZZ). A FuzzFinding escapes and aborts, which libFuzzer records as a crash.
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const apiclab::fuzz::Target target = apiclab::fuzz::target_named(APICLAB_FUZZ_TARGET);
  target(data, size);
  return 0;
}
