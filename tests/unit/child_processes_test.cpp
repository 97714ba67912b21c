// Forked jobs: results in job order from other processes, and failures as a loop in order
// would report them.
#include <csignal>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "util/child_processes.h"
#include "util/error.h"

namespace rtusim {
namespace {

const std::vector<std::string> kNames = {"job a", "job b", "job c", "job d", "job e"};

TEST(ChildProcesses, ResultsComeBackInJobOrderFromChildren) {
  const pid_t parent = ::getpid();
  for (int at_once : {1, 2, 5}) {
    const std::vector<std::string> results =
        run_in_child_processes(5, at_once, kNames, [&](size_t i) {
          // A large result crosses the pipe in several reads.
          std::string r(100000 + i, char('a' + i));
          r += ::getpid() == parent ? ":parent" : ":child";
          return r;
        });
    ASSERT_EQ(results.size(), 5u);
    for (size_t i = 0; i < 5; ++i) {
      EXPECT_EQ(results[i].size(), 100000 + i + 6) << at_once;
      EXPECT_EQ(results[i].front(), char('a' + i));
      EXPECT_EQ(results[i].substr(results[i].size() - 6), ":child");
    }
  }
}

TEST(ChildProcesses, LowestFailingJobWinsAndKeepsItsKind) {
  // Job b fails after job c has failed already: b's error is the one a loop would meet first.
  try {
    run_in_child_processes(4, 4, kNames, [](size_t i) -> std::string {
      if (i == 1) {
        ::usleep(200000);
        throw InputError("b is bad input");
      }
      if (i == 2) throw std::runtime_error("c broke");
      return "fine";
    });
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "b is bad input");
  }
  try {
    run_in_child_processes(3, 2, kNames, [](size_t i) -> std::string {
      if (i == 2) throw std::runtime_error("c broke");
      return "fine";
    });
    FAIL() << "no exception";
  } catch (const InputError&) {
    FAIL() << "an internal error came back as bad input";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "c broke");
  }
}

TEST(ChildProcesses, ChildKilledBySignalIsNamed) {
  try {
    run_in_child_processes(2, 2, kNames, [](size_t i) -> std::string {
      if (i == 1) ::raise(SIGKILL);
      return "fine";
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("job b"), std::string::npos) << m;
    EXPECT_NE(m.find("signal 9"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace rtusim
