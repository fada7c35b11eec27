// Every seed and every input a fuzzer once failed on, through its harness: each returns (no crash, no
// exception escapes). The harnesses are the libFuzzer ones (harnesses/), compiled here without libFuzzer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/fuzz/harness_table.hpp"

namespace kessler::fuzz {
namespace {

namespace fs = std::filesystem;

int replay_folder(const Harness& harness, const fs::path& folder) {
  int inputs = 0;
  if (!fs::is_directory(folder)) return 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    SCOPED_TRACE(entry.path().string());
    EXPECT_EQ(harness.one_input(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 0);
    ++inputs;
  }
  return inputs;
}

TEST(FuzzReplay, EveryHarnessHasSeedsAndTakesThemAndItsRegressions) {
  const fs::path root = KESSLER_FUZZ_DIR;
  ASSERT_GE(harnesses().size(), 10u);
  for (const Harness& h : harnesses()) {
    const std::string name = std::string(h.name).substr(5);  // without "fuzz_"
    SCOPED_TRACE(h.name);
    EXPECT_GT(replay_folder(h, root / "corpus" / name), 0) << "no seed corpus for " << h.name;
    replay_folder(h, root / "regressions" / name);
  }
}

TEST(FuzzReplay, EmptyAndTinyInputs) {
  for (const Harness& h : harnesses()) {
    SCOPED_TRACE(h.name);
    EXPECT_EQ(h.one_input(nullptr, 0), 0);
    const std::uint8_t one[] = {'\n'};
    EXPECT_EQ(h.one_input(one, 1), 0);
  }
}

}  // namespace
}  // namespace kessler::fuzz
