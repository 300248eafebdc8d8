// libFuzzer entry for the VTU reader (scripts/fuzz.sh).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  c2d::fuzz::vtu(data, size);
  return 0;
}
