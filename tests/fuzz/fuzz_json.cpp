// libFuzzer entry for the JSON files a user can edit (study.json, summary.json) (scripts/fuzz.sh).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  c2d::fuzz::json(data, size);
  return 0;
}
