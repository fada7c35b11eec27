#include <cstring>
#include <iostream>
#include <map>
#include <string>

#include "client/command.hpp"

namespace kessler::cli {
namespace {

struct Entry {
  int order;
  std::string usage;
  std::string summary;
  CommandMain main;
};

std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> entries;
  return entries;
}

void print_help(std::ostream& out) {
  out << "kessler - submit, watch and query deterministic space-debris simulations\n\n"
         "usage: kessler <command> [options]\n\ncommands:\n";
  std::multimap<int, const std::pair<const std::string, Entry>*> ordered;
  for (const auto& entry : registry()) ordered.emplace(entry.second.order, &entry);
  for (const auto& [order, entry] : ordered)
    out << "  " << entry->second.usage << "\n      " << entry->second.summary << "\n";
  out << "\nRun 'kessler <command> --help' for a command's options.\n"
         "Remote commands talk to kesslerd at --server ADDRESS, else $KESSLER_SERVER, else 127.0.0.1:50051.\n"
         "Exit codes: 0 success, 1 failure, 2 bad usage or input.\n";
}

}  // namespace

CommandRegistration::CommandRegistration(const char* name, int order, const char* usage, const char* summary,
                                         CommandMain main) {
  registry()[name] = Entry{order, usage, summary, main};
}

}  // namespace kessler::cli

int main(int argc, char** argv) {
  using namespace kessler::cli;
  if (argc < 2) {
    print_help(std::cerr);
    return kExitUsage;
  }
  std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    print_help(std::cout);
    return kExitOk;
  }
  auto it = registry().find(name);
  if (it == registry().end()) {
    std::cerr << "kessler: unknown command '" << name << "' (see kessler --help)\n";
    return kExitUsage;
  }
  return it->second.main(argc - 1, argv + 1);
}
