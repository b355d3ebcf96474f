// Linked into every test program (tests/CMakeLists.txt's vastray_test): when a suite's
// SetUpTestSuite fails, gtest marks each of its tests skipped ("[  SKIPPED ]"), which CTest's
// skip pattern for gtest turns into a skip, not a failure: a GPU suite whose device did not start
// would pass CI unseen. This listener ends the program with exit code 1 before the first such
// test is reported, so CTest reports a failure naming the suite.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

namespace {

class SuiteSetupGuard final : public ::testing::EmptyTestEventListener {
    void OnTestStart(const ::testing::TestInfo& test) override {
        const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
        if (suite == nullptr || !suite->ad_hoc_test_result().Failed()) return;
        std::printf("[  FAILED  ] %s: SetUpTestSuite failed (above), so %s.%s and the rest of the suite did not run\n",
                    test.test_suite_name(), test.test_suite_name(), test.name());
        std::fflush(stdout);
        std::_Exit(1);
    }
};

const bool kRegistered = [] {
    ::testing::UnitTest::GetInstance()->listeners().Append(new SuiteSetupGuard);
    return true;
}();

}  // namespace
