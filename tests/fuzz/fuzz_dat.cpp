// libFuzzer entry for the dat reader (scripts/fuzz.sh).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  c2d::fuzz::dat(data, size);
  return 0;
}
