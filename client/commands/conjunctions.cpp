// kessler conjunctions RUN: a run's conjunction catalog, filtered, as a table, CSV or JSON, with the
// objects' names where the run's population has them.
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

struct ConjunctionsOptions {
  std::int64_t run_id = 0;
  std::optional<double> kappa_min, kappa_max, from_s, to_s;
  std::optional<std::uint64_t> object;
  bool collisions = false, evasions = false, closest_per_pair = false;
  std::uint64_t limit = std::numeric_limits<std::uint64_t>::max();
};

v1::ListConjunctionsRequest request_of(const ConjunctionsOptions& o) {
  v1::ListConjunctionsRequest request;
  request.set_run_id(o.run_id);
  if (o.kappa_min) request.set_kappa_min(*o.kappa_min);
  if (o.kappa_max) request.set_kappa_max(*o.kappa_max);
  if (o.from_s) request.set_time_min_s(*o.from_s);
  if (o.to_s) request.set_time_max_s(*o.to_s);
  if (o.object) request.set_object_id(*o.object);
  request.set_collisions_only(o.collisions);
  request.set_include_evasions(o.evasions);
  request.set_closest_per_pair(o.closest_per_pair);
  return request;
}

std::string vector_json(const v1::Vector3& v) {
  return "[" + json_number(v.x()) + ", " + json_number(v.y()) + ", " + json_number(v.z()) + "]";
}

void print_json(const std::vector<v1::Encounter>& rows, const std::string& epoch) {
  std::cout << "[";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& c = rows[i];
    JsonObject obj;
    obj.add("seq", static_cast<std::uint64_t>(c.seq()))
        .add("kind", kind_name(c.kind()))
        .add("id1", static_cast<std::uint64_t>(c.id1()))
        .add("id2", static_cast<std::uint64_t>(c.id2()))
        .add("name1", c.name1())
        .add("name2", c.name2())
        .add("tca_s", c.tca_s())
        .add("tca_utc", format_sim_time(epoch, c.tca_s()))
        .add("miss_distance_m", c.miss_distance_m())
        .add("kappa", c.kappa())
        .add("relative_speed_m_s", c.relative_speed_m_s())
        .add_raw("r1_m", vector_json(c.r1_m()))
        .add_raw("v1_m_s", vector_json(c.v1_m_s()))
        .add_raw("r2_m", vector_json(c.r2_m()))
        .add_raw("v2_m_s", vector_json(c.v2_m_s()));
    std::cout << (i ? ",\n " : "") << obj.str();
  }
  std::cout << "]\n";
}

// The names come last so the columns before them stay where scripts expect them.
void print_csv(const std::vector<v1::Encounter>& rows, const std::string& epoch) {
  std::cout << "seq,kind,id1,id2,tca_s,tca_utc,miss_distance_m,kappa,relative_speed_m_s,name1,name2\n";
  for (const auto& c : rows)
    std::cout << c.seq() << "," << kind_name(c.kind()) << "," << c.id1() << "," << c.id2() << ","
              << json_number(c.tca_s()) << "," << format_sim_time(epoch, c.tca_s()) << ","
              << json_number(c.miss_distance_m()) << "," << json_number(c.kappa()) << ","
              << json_number(c.relative_speed_m_s()) << "," << csv_field(c.name1()) << ","
              << csv_field(c.name2()) << "\n";
}

void print_table(const std::vector<v1::Encounter>& rows, const std::string& epoch) {
  if (rows.empty()) {
    std::cout << "no conjunctions match\n";
    return;
  }
  std::vector<std::vector<std::string>> table;
  char buf[4][32];
  for (const auto& c : rows) {
    std::snprintf(buf[0], 32, "%.1f", c.miss_distance_m());
    std::snprintf(buf[1], 32, "%.3f", c.kappa());
    std::snprintf(buf[2], 32, "%.3f", c.relative_speed_m_s() / 1000.0);
    std::snprintf(buf[3], 32, "%.3f", c.tca_s());
    table.push_back({std::to_string(c.seq()), kind_name(c.kind()), std::to_string(c.id1()),
                     c.name1().empty() ? "-" : c.name1(), std::to_string(c.id2()),
                     c.name2().empty() ? "-" : c.name2(), format_sim_time(epoch, c.tca_s()), buf[3], buf[0],
                     buf[1], buf[2]});
  }
  std::cout << render_table({"SEQ", "KIND", "ID1", "NAME1", "ID2", "NAME2", "TCA (UTC)", "TCA [s]",
                             "MISS [m]", "KAPPA", "V_REL [km/s]"},
                            table)
            << rows.size() << " conjunctions\n";
}

int list_conjunctions(const ConjunctionsOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("conjunctions", global.output, {"table", "csv", "json"}, format)) return kExitUsage;
  v1::ListConjunctionsRequest request = request_of(o);
  RemoteClient client(server_address(global.server));
  v1::Run run;
  CallResult r = client.get(o.run_id, run);
  std::vector<v1::Encounter> rows;
  while (r.ok && rows.size() < o.limit) {
    request.set_page_size(static_cast<int>(std::min<std::uint64_t>(o.limit - rows.size(), 50000)));
    v1::ListConjunctionsResponse response;
    r = client.conjunctions(request, response);
    if (!r.ok) break;
    for (const auto& c : response.conjunctions()) rows.push_back(c);
    if (response.next_page_token().empty()) break;
    request.set_page_token(response.next_page_token());
  }
  if (!r.ok) {
    std::cerr << "kessler conjunctions: " << r.describe() << "\n";
    return r.exit_code();
  }
  const std::string epoch = run.scenario().start_epoch();
  if (format == OutputFormat::kJson)
    print_json(rows, epoch);
  else if (format == OutputFormat::kCsv)
    print_csv(rows, epoch);
  else
    print_table(rows, epoch);
  return kExitOk;
}

}  // namespace

CommandRun setup_conjunctions(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<ConjunctionsOptions>();
  add_run_id(command, o->run_id);
  command.add_option("--kappa-min", o->kappa_min, "miss distance / (r1 + r2) at least K")->option_text("K");
  command.add_option("--kappa-max", o->kappa_max, "miss distance / (r1 + r2) at most K")->option_text("K");
  command.add_option("--object", o->object, "encounters of this object")->option_text("ID");
  command.add_option("--from-s", o->from_s, "time of closest approach at least S seconds since the epoch")
      ->option_text("S");
  command.add_option("--to-s", o->to_s, "time of closest approach at most S seconds since the epoch")
      ->option_text("S");
  command.add_flag("--collisions", o->collisions, "collisions only (d <= r1 + r2)");
  command.add_flag("--evasions", o->evasions,
                   "also list evasions (two active objects, presumed to manoeuvre)");
  command.add_flag("--closest-per-pair", o->closest_per_pair,
                   "only the closest encounter of each pair of objects");
  command.add_option("--limit", o->limit, "at most N rows (default: all)")->option_text("N");
  add_global_options(command, global,
                     "table (default), csv (a header row, then one row per encounter) or json (an array of "
                     "objects with the CSV's columns as keys and both objects' states at TCA)");
  command.footer(
      "Lists a run's conjunctions (collisions included) in the order they happened, with the objects' "
      "catalog "
      "ids and names (where the population has names)."
      "\n\n"
      "examples:\n"
      "  kessler conjunctions 1 --kappa-max 1 --closest-per-pair\n"
      "  kessler conjunctions 1 --object 25544 --output csv > iss.csv");
  return [o, &global] { return list_conjunctions(*o, global); };
}

}  // namespace kessler::cli
