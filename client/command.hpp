// kessler, the command-line client: each command lives in its own file under client/commands/ and is
// listed in the table of client/main.cpp. Exit codes: 0 success, 1 failure, 2 bad usage or input.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <string>

namespace kessler::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Options every command takes, before or after the command's name (kessler --server H:P runs).
struct GlobalOptions {
  std::string server;  // empty: $KESSLER_SERVER, else 127.0.0.1:50051
  std::string output;  // empty: the command's default format
  // Security of the connection (client/remote/remote_client.hpp's ConnectionOptions); empty: from the
  // environment, else none.
  std::string token, tls_ca, tls_cert, tls_key;
};

// What runs the command once its options are parsed; returns the exit code.
using CommandRun = std::function<int()>;
// Declares the command's options and arguments on `command` and returns what runs it.
using CommandSetup = CommandRun (*)(CLI::App& command, GlobalOptions& global);

struct CommandSpec {
  const char* name;
  const char* summary;
  CommandSetup setup;
};

// Declares the global options on a command too, so its --help lists them; `output_help` says which
// formats it takes. server: whether it talks to kesslerd.
void add_global_options(CLI::App& command, GlobalOptions& global, const std::string& output_help,
                        bool server = true);

// The RUN argument of the commands about one run: a positive integer.
CLI::Option* add_run_id(CLI::App& command, std::int64_t& run_id);

// A check that a number is > 0, with a message that names the value.
CLI::Validator positive_number();

// Prints "kessler CMD: message (see kessler CMD --help)" and returns kExitUsage: the one style of
// usage errors, whether CLI11 or a command's own checks find them.
int usage_error(const std::string& command, const std::string& message);

// "table" (also "text"), "csv" or "json", checked against what the command accepts.
enum class OutputFormat { kTable, kCsv, kJson };
// False with a usage error printed when `text` is not among `accepted` ("table", "csv", "json").
bool resolve_output(const std::string& command, const std::string& text,
                    std::initializer_list<const char*> accepted, OutputFormat& out);

}  // namespace kessler::cli
