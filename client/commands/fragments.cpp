// kessler fragments RUN: the fragments a run's breakups made (optionally of one breakup), by id, with
// their parent, characteristic length, area-to-mass ratio, mass and ejection speed.
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

struct FragmentsOptions {
  std::int64_t run_id = 0;
  std::optional<std::uint32_t> breakup;
  std::uint64_t limit = std::numeric_limits<std::uint64_t>::max();
};

void print_json(const std::vector<v1::Fragment>& rows) {
  std::cout << "[";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& f = rows[i];
    JsonObject obj;
    obj.add("id", static_cast<std::uint64_t>(f.id()))
        .add("breakup_id", static_cast<std::uint64_t>(f.breakup_id()))
        .add("parent_id", static_cast<std::uint64_t>(f.parent_id()))
        .add("characteristic_length_m", f.characteristic_length_m())
        .add("area_to_mass_m2_kg", f.area_to_mass_m2_kg())
        .add("mass_kg", f.mass_kg())
        .add("delta_v_m_s", f.delta_v_m_s());
    std::cout << (i ? ",\n " : "") << obj.str();
  }
  std::cout << "]\n";
}

void print_csv(const std::vector<v1::Fragment>& rows) {
  std::cout << "id,breakup_id,parent_id,characteristic_length_m,area_to_mass_m2_kg,mass_kg,delta_v_m_s\n";
  for (const auto& f : rows)
    std::cout << f.id() << "," << f.breakup_id() << "," << f.parent_id() << ","
              << json_number(f.characteristic_length_m()) << "," << json_number(f.area_to_mass_m2_kg()) << ","
              << json_number(f.mass_kg()) << "," << json_number(f.delta_v_m_s()) << "\n";
}

void print_table(const std::vector<v1::Fragment>& rows, std::uint64_t total) {
  if (rows.empty()) {
    std::cout << "no fragments\n";
    return;
  }
  std::vector<std::vector<std::string>> table;
  char buf[4][32];
  for (const auto& f : rows) {
    std::snprintf(buf[0], 32, "%.4f", f.characteristic_length_m());
    std::snprintf(buf[1], 32, "%.5f", f.area_to_mass_m2_kg());
    std::snprintf(buf[2], 32, "%.6g", f.mass_kg());
    std::snprintf(buf[3], 32, "%.2f", f.delta_v_m_s());
    table.push_back({std::to_string(f.id()), "FRAGMENT " + std::to_string(f.id()),
                     std::to_string(f.breakup_id()), std::to_string(f.parent_id()), buf[0], buf[1], buf[2],
                     buf[3]});
  }
  std::cout << render_table(
                   {"ID", "NAME", "BREAKUP", "PARENT", "LC [m]", "A/M [m2/kg]", "MASS [kg]", "DV [m/s]"},
                   table)
            << rows.size() << " fragments";
  if (total > rows.size()) std::cout << " (of " << total << ")";
  std::cout << "\n";
}

int list_fragments(const FragmentsOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("fragments", global.output, {"table", "csv", "json"}, format)) return kExitUsage;
  v1::ListFragmentsRequest request;
  request.set_run_id(o.run_id);
  if (o.breakup) request.set_breakup_id(*o.breakup);
  RemoteClient client(server_address(global.server));
  std::vector<v1::Fragment> rows;
  std::uint64_t total = 0;
  CallResult r;
  while (rows.size() < o.limit) {
    request.set_page_size(static_cast<int>(std::min<std::uint64_t>(o.limit - rows.size(), 50000)));
    v1::ListFragmentsResponse response;
    r = client.fragments(request, response);
    if (!r.ok) break;
    total = response.total();
    for (const auto& f : response.fragments()) rows.push_back(f);
    if (response.next_page_token().empty()) break;
    request.set_page_token(response.next_page_token());
  }
  if (!r.ok) {
    std::cerr << "kessler fragments: " << r.describe() << "\n";
    return r.exit_code();
  }
  if (format == OutputFormat::kJson)
    print_json(rows);
  else if (format == OutputFormat::kCsv)
    print_csv(rows);
  else
    print_table(rows, total);
  return kExitOk;
}

}  // namespace

CommandRun setup_fragments(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<FragmentsOptions>();
  add_run_id(command, o->run_id);
  command.add_option("--breakup", o->breakup, "only the fragments of breakup N (1, 2, ... in event order)")
      ->option_text("N")
      ->check(CLI::PositiveNumber);
  command.add_option("--limit", o->limit, "at most N rows (default: all)")->option_text("N");
  add_global_options(command, global,
                     "table (default), csv (a header row, then one row per fragment) or json (an array of "
                     "objects with the CSV's columns as keys)");
  command.footer(
      "Lists the fragments a run's breakups made, by id: the breakup, the parent object, characteristic "
      "length Lc, area-to-mass ratio, mass and ejection speed. Fragments have no catalog name; listings "
      "show them as FRAGMENT <id>."
      "\n\n"
      "examples:\n"
      "  kessler fragments 3\n"
      "  kessler fragments 3 --breakup 1 --output csv > breakup1.csv");
  return [o, &global] { return list_fragments(*o, global); };
}

}  // namespace kessler::cli
