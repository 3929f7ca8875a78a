// Signals as the tools take them (command.hpp): while deferred, any number of SIGTERM or
// SIGINT only ask the tool to stop, the first deciding the exit code; otherwise, and once
// the deferral ends, a signal ends the process at once with 128 + the first signal.
// Each case runs a whole tool in a child process (gtest's death tests).
#include "cdpile/cli/command.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <csignal>

using namespace cdpile;

namespace {

int run(void (*body)()) {
  char name[] = "signals";
  char* argv[] = {name, nullptr};
  return cli::run_tool(
      1, argv, [](cli::Usage& u) { u.synopsis = "signal test"; },
      [body](const cli::Args&) { body(); });
}

}  // namespace

// A scheduler signals a tool and its make together, and make forwards its SIGTERM: the
// second signal (and a third) must not end the tool while it writes its checkpoint.
TEST(SignalsDeathTest, DeferredSignalsOnlyAskToStop) {
  EXPECT_EXIT(run([] {
                cli::defer_interrupts();
                std::raise(SIGTERM);
                std::raise(SIGTERM);
                std::raise(SIGINT);
                _exit(cli::interrupted() && cli::interrupt_exit_code() == 128 + SIGTERM ? 42 : 1);
              }),
              testing::ExitedWithCode(42), "");
}

TEST(SignalsDeathTest, AfterTheDeferralASignalEndsTheToolAtOnce) {
  EXPECT_EXIT(run([] {
                cli::defer_interrupts();
                std::raise(SIGINT);
                cli::end_deferral();  // the first signal is still the tool's to act on
                if (!cli::interrupted()) _exit(1);
                std::raise(SIGTERM);
                _exit(2);
              }),
              testing::ExitedWithCode(128 + SIGINT), "");
  EXPECT_EXIT(run([] {
                std::raise(SIGTERM);
                _exit(2);
              }),
              testing::ExitedWithCode(128 + SIGTERM), "");
}

// A tool's exit code is its body's return value, through the runner (no std::exit in the
// tools): an interrupted run returns 130 or 143 after its message, a body returning
// nothing succeeds.
TEST(Runner, ReturnsTheBodysExitCode) {
  char name[] = "runner";
  char* argv[] = {name, nullptr};
  auto declare = [](cli::Usage& u) { u.synopsis = "runner test"; };
  EXPECT_EQ(cli::run_tool(1, argv, declare, [](const cli::Args&) { return 130; }), 130);
  EXPECT_EQ(cli::run_tool(1, argv, declare, [](const cli::Args&) {}), 0);
}
