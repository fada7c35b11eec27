// kessler: the command table and the parsing every command shares (CLI11). Global options (--server,
// --output) go before or after the command's name, as git and kubectl take them.
#include <iostream>
#include <map>
#include <string>

#include "client/command.hpp"
#ifdef KESSLER_CLI_REMOTE
#include "client/remote/remote_client.hpp"
#endif

namespace kessler::cli {

CommandRun setup_run(CLI::App& command, GlobalOptions& global);
CommandRun setup_assess(CLI::App& command, GlobalOptions& global);
#ifdef KESSLER_CLI_REMOTE
CommandRun setup_submit(CLI::App& command, GlobalOptions& global);
CommandRun setup_watch(CLI::App& command, GlobalOptions& global);
CommandRun setup_runs(CLI::App& command, GlobalOptions& global);
CommandRun setup_show(CLI::App& command, GlobalOptions& global);
CommandRun setup_conjunctions(CLI::App& command, GlobalOptions& global);
CommandRun setup_fragments(CLI::App& command, GlobalOptions& global);
CommandRun setup_snapshot(CLI::App& command, GlobalOptions& global);
CommandRun setup_cancel(CLI::App& command, GlobalOptions& global);
CommandRun setup_resume(CLI::App& command, GlobalOptions& global);
CommandRun setup_delete(CLI::App& command, GlobalOptions& global);
CommandRun setup_health(CLI::App& command, GlobalOptions& global);
CommandRun setup_ensemble(CLI::App& command, GlobalOptions& global);
CommandRun setup_report(CLI::App& command, GlobalOptions& global);
#endif

namespace {

// Every command, in the order of the help listing.
const CommandSpec kCommands[] = {
    {"run", "run a scenario in this process (--local) and print its events and fingerprint", setup_run},
    {"assess", "a CDM's collision probability recomputed from its states and covariances", setup_assess},
#ifdef KESSLER_CLI_REMOTE
    {"submit", "queue a run of a scenario on kesslerd (and follow it with --watch)", setup_submit},
    {"watch", "follow a run live: progress, events, summary", setup_watch},
    {"runs", "list runs", setup_runs},
    {"show", "a run's scenario, ingest report, state, timers and conjunction counts by kappa", setup_show},
    {"conjunctions",
     "a run's conjunctions, filtered (kappa, object, time, collisions, closest per pair, Pc), or CDMs",
     setup_conjunctions},
    {"fragments", "the fragments a run's breakups made (parent, Lc, A/m, mass, dv)", setup_fragments},
    {"snapshot", "a run's population at a snapshot: kinds, sizes, osculating elements (csv, json)",
     setup_snapshot},
    {"cancel", "cancel a queued or running run", setup_cancel},
    {"resume", "queue a failed or cancelled run again, from its last checkpoint", setup_resume},
    {"delete", "delete an ended run and everything stored for it", setup_delete},
    {"ensemble", "Monte Carlo ensembles (submit --members N): show (aggregates), list, cancel",
     setup_ensemble},
    {"report", "one self-contained HTML file: a run's (or an ensemble's) figures, scenario, fingerprint",
     setup_report},
    {"health", "the daemon's health check: exit 0 when SERVING", setup_health},
#endif
};

const char* const kFooter =
    "Run 'kessler COMMAND --help' for a command's options.\n"
    "Remote commands talk to kesslerd at --server ADDRESS, else $KESSLER_SERVER, else 127.0.0.1:50051;\n"
    "with --token (else $KESSLER_TOKEN) when it takes tokens, over TLS with --tls-ca FILE (else\n"
    "$KESSLER_TLS_CA), with a client certificate for mutual TLS from --tls-cert/--tls-key.\n"
    "Exit codes: 0 success, 1 failure, 2 bad usage or input.";

// The subcommand the user named, or nullptr when parsing stopped before one.
CLI::App* named_command(CLI::App& app) {
  auto parsed = app.get_subcommands();
  return parsed.empty() ? nullptr : parsed.front();
}

// The first argument that is neither an option nor a global option's value: the command's name.
std::string first_word(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--server" || arg == "--output" || arg == "--token" || arg == "--tls-ca" ||
        arg == "--tls-cert" || arg == "--tls-key") {
      ++i;
      continue;
    }
    if (!arg.empty() && arg[0] != '-') return arg;
  }
  return "";
}

}  // namespace

namespace {

void add_connection_options(CLI::App& command, GlobalOptions& global) {
  command
      .add_option("--server", global.server,
                  "kesslerd to talk to (default $KESSLER_SERVER, else 127.0.0.1:50051)")
      ->option_text("HOST:PORT");
  command
      .add_option("--token", global.token, "bearer token for a daemon with tokens (default $KESSLER_TOKEN)")
      ->option_text("TOKEN");
  command
      .add_option("--tls-ca", global.tls_ca,
                  "connect over TLS, trusting this PEM CA (default $KESSLER_TLS_CA)")
      ->option_text("FILE");
  command
      .add_option("--tls-cert", global.tls_cert,
                  "client certificate for mutual TLS (default $KESSLER_TLS_CERT)")
      ->option_text("FILE");
  command.add_option("--tls-key", global.tls_key, "its private key (default $KESSLER_TLS_KEY)")
      ->option_text("FILE");
}

}  // namespace

void add_global_options(CLI::App& command, GlobalOptions& global, const std::string& output_help,
                        bool server) {
  command.add_option("--output", global.output, output_help)->option_text("FORMAT");
  if (server) add_connection_options(command, global);
}

CLI::Option* add_run_id(CLI::App& command, std::int64_t& run_id) {
  return command.add_option("RUN", run_id, "the run's id (kessler runs lists them)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& text) {
            return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos &&
                           text.find_first_not_of('0') != std::string::npos
                       ? std::string()
                       : "must be a run id (a positive integer), got '" + text + "'";
          },
          "RUN", "run id"));
}

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) {
        double v = 0;
        return CLI::detail::lexical_cast(text, v) && v > 0 ? std::string()
                                                           : "must be a positive number, got '" + text + "'";
      },
      "POSITIVE", "positive");
}

int usage_error(const std::string& command, const std::string& message) {
  const std::string who = command.empty() ? "kessler" : "kessler " + command;
  std::cerr << who << ": " << message << " (see " << who << " --help)\n";
  return kExitUsage;
}

bool resolve_output(const std::string& command, const std::string& text,
                    std::initializer_list<const char*> accepted, OutputFormat& out) {
  const std::string name = text.empty() ? "table" : (text == "text" ? "table" : text);
  std::string list;
  for (const char* a : accepted) {
    if (name == a) {
      out = name == "json" ? OutputFormat::kJson : name == "csv" ? OutputFormat::kCsv : OutputFormat::kTable;
      return true;
    }
    list += list.empty() ? a : std::string(", ") + a;
  }
  usage_error(command, "--output must be one of " + list + ", got '" + text + "'");
  return false;
}

}  // namespace kessler::cli

int main(int argc, char** argv) {
  using namespace kessler::cli;
  CLI::App app("kessler - submit, watch and query deterministic space-debris simulations", "kessler");
  app.footer(kFooter);
  GlobalOptions global;
  // Before the command's name; each command declares them again for after it.
  add_connection_options(app, global);
  app.add_option("--output", global.output, "table, csv or json, as the command takes them")
      ->option_text("FORMAT");
  std::map<std::string, CommandRun> runs;
  for (const CommandSpec& spec : kCommands) {
    CLI::App* command = app.add_subcommand(spec.name, spec.summary);
    runs[spec.name] = spec.setup(*command, global);
  }
  if (argc < 2) {
    std::cerr << app.help();
    return kExitUsage;
  }
  if (std::string(argv[1]) == "help") {
    std::cout << app.help();
    return kExitOk;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (CLI::App* command = named_command(app)) return usage_error(command->get_name(), e.what());
    if (auto word = first_word(argc, argv); !word.empty() && !runs.count(word))
      return usage_error("", "unknown command '" + word + "'");
    return usage_error("", e.what());
  }
  CLI::App* command = named_command(app);
  if (!command) return usage_error("", "a command is required");
#ifdef KESSLER_CLI_REMOTE
  std::string error;
  if (!set_connection_options({global.token, global.tls_ca, global.tls_cert, global.tls_key}, error))
    return usage_error(command->get_name(), error);
#endif
  return runs.at(command->get_name())();
}
