// libFuzzer entry for the msh reader (scripts/fuzz.sh).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  c2d::fuzz::msh(data, size);
  return 0;
}
