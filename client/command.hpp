// kessler, the command-line client: one command per file, registered with KESSLER_COMMAND.
// Exit codes: 0 success, 1 failure, 2 bad usage or input.
#pragma once

namespace kessler::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// argv[0] is the command's name; the options follow.
using CommandMain = int (*)(int argc, char** argv);

struct CommandRegistration {
  // `order` sorts the help listing; `usage` is one line such as "submit FILE [--watch]".
  CommandRegistration(const char* name, int order, const char* usage, const char* summary, CommandMain main);
};

}  // namespace kessler::cli

#define KESSLER_COMMAND_CONCAT_(a, b) a##b
#define KESSLER_COMMAND_CONCAT(a, b) KESSLER_COMMAND_CONCAT_(a, b)
#define KESSLER_COMMAND(name, order, usage, summary, main_fn)                                             \
  static ::kessler::cli::CommandRegistration KESSLER_COMMAND_CONCAT(kessler_cmd_reg_, __LINE__)(name, order, \
                                                                                              usage, summary, main_fn)
