// Replays the fuzz seed corpus (fuzz/corpus/<target>/) and every input the fuzzers ever crashed on
// (tests/fuzz_regressions/<target>/) through the fuzz entry points: each must return normally.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fuzz/fuzz_entries.h"

namespace semvox {
namespace {
namespace fs = std::filesystem;

TEST(FuzzRegression, EveryKeptInputIsHandled) {
  size_t replayed = 0;
  for (const auto& target : fuzz::Targets()) {
    for (const char* root : {"/fuzz/corpus/", "/tests/fuzz_regressions/"}) {
      const fs::path dir = fs::path(SEMVOX_SOURCE_DIR + std::string(root)) / target.name;
      if (!fs::exists(dir)) continue;
      for (const auto& e : fs::directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        std::ifstream in(e.path(), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        SCOPED_TRACE(e.path().string());
        target.fn(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
        ++replayed;
      }
    }
  }
  EXPECT_GE(replayed, 6u);  // At least the seed corpus.
}

}  // namespace
}  // namespace semvox
