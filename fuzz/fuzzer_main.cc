// One libFuzzer binary per target: compiled with -DSEMVOX_FUZZ_TARGET=<entry function>.
#include "fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  semvox::fuzz::SEMVOX_FUZZ_TARGET(data, size);
  return 0;
}
