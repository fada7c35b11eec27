// The test programs' main: GoogleTest's, plus one rule. gtest skips every test of a suite whose
// SetUpTestSuite fails (an ASSERT or an exception there), and ctest counts a skipped test as passed, so
// a broken fixture would pass CI. Here a failed suite setup ends the program with an error before its
// first test is reported skipped.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

namespace {

class FailedSuiteSetupFails : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo& test) override {
    const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
    if (suite == nullptr || !suite->ad_hoc_test_result().Failed()) return;
    std::fprintf(stderr, "%s: the suite's SetUpTestSuite failed (above), so %s cannot run\n", suite->name(),
                 test.name());
    std::fflush(nullptr);
    std::_Exit(1);
  }
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // After the default printer, which has reported the setup's failure by then.
  ::testing::UnitTest::GetInstance()->listeners().Append(new FailedSuiteSetupFails);
  return RUN_ALL_TESTS();
}
