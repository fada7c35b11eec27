// kessler conjunctions: a run's conjunction catalog, filtered, as a table, CSV or JSON.
#include <cstdio>
#include <iostream>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

int conjunctions_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv,
               {{"--kappa-min", true},
                {"--kappa-max", true},
                {"--object", true},
                {"--from-s", true},
                {"--to-s", true},
                {"--collisions", false},
                {"--evasions", false},
                {"--closest-per-pair", false},
                {"--limit", true}},
               error))
    return usage_error("conjunctions", error);
  if (o.has("--help")) {
    std::cout
        << "usage: kessler conjunctions RUN [filters] [--output table|csv|json]\n\n"
           "Lists a run's conjunctions (collisions included) in the order they happened.\n\n"
           "filters:\n"
           "  --kappa-min K, --kappa-max K   miss distance / (r1 + r2) within [K1, K2]\n"
           "  --object ID          encounters of this object\n"
           "  --from-s S, --to-s S time of closest approach within [S1, S2], seconds since the epoch\n"
           "  --collisions         collisions only (d <= r1 + r2)\n"
           "  --evasions           also list evasions (two active objects, presumed to manoeuvre)\n"
           "  --closest-per-pair   only the closest encounter of each pair of objects\n"
           "  --limit N            at most N rows (default: all)\n\n"
           "options:\n"
           "  --output FORMAT      table (default), csv (a header row, then one row per encounter) or\n"
           "                       json (an array of objects with the CSV's columns as keys)\n"
           "  --server HOST:PORT   kesslerd to talk to (default $KESSLER_SERVER, else 127.0.0.1:50051)\n\n"
           "examples:\n"
           "  kessler conjunctions 1 --kappa-max 1 --closest-per-pair\n"
           "  kessler conjunctions 1 --object 25544 --output csv > iss.csv\n";
    return kExitOk;
  }
  std::int64_t run_id = 0;
  if (o.positional.size() != 1 || !parse_run_id(o.positional[0], run_id))
    return usage_error("conjunctions", "expects one RUN id");
  auto format = parse_output(o.get("--output", "table"));
  if (!format) return usage_error("conjunctions", "--output must be table, csv or json");
  v1::ListConjunctionsRequest request;
  request.set_run_id(run_id);
  double v = 0;
  std::uint64_t id = 0;
  struct DoubleFlag {
    const char* name;
    void (v1::ListConjunctionsRequest::*set)(double);
  };
  for (auto [name, set] : {DoubleFlag{"--kappa-min", &v1::ListConjunctionsRequest::set_kappa_min},
                           DoubleFlag{"--kappa-max", &v1::ListConjunctionsRequest::set_kappa_max},
                           DoubleFlag{"--from-s", &v1::ListConjunctionsRequest::set_time_min_s},
                           DoubleFlag{"--to-s", &v1::ListConjunctionsRequest::set_time_max_s}}) {
    if (!o.has(name)) continue;
    if (!parse_double(o.get(name), v))
      return usage_error("conjunctions", std::string(name) + " needs a number");
    (request.*set)(v);
  }
  if (o.has("--object")) {
    if (!parse_uint(o.get("--object"), id)) return usage_error("conjunctions", "--object needs an object id");
    request.set_object_id(id);
  }
  request.set_collisions_only(o.has("--collisions"));
  request.set_include_evasions(o.has("--evasions"));
  request.set_closest_per_pair(o.has("--closest-per-pair"));
  std::uint64_t limit = UINT64_MAX;
  if (o.has("--limit") && !parse_uint(o.get("--limit"), limit))
    return usage_error("conjunctions", "--limit needs a non-negative integer");

  RemoteClient client(server_address(o.get("--server")));
  v1::Run run;
  CallResult r = client.get(run_id, run);
  std::vector<v1::Encounter> rows;
  while (r.ok && rows.size() < limit) {
    request.set_page_size(static_cast<int>(std::min<std::uint64_t>(limit - rows.size(), 50000)));
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
  const std::vector<std::string> columns = {
      "seq", "kind", "id1", "id2", "tca_s", "tca_utc", "miss_distance_m", "kappa", "relative_speed_m_s"};
  if (*format == OutputFormat::kJson) {
    std::cout << "[";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& c = rows[i];
      JsonObject obj;
      obj.add("seq", static_cast<std::uint64_t>(c.seq()))
          .add("kind", kind_name(c.kind()))
          .add("id1", static_cast<std::uint64_t>(c.id1()))
          .add("id2", static_cast<std::uint64_t>(c.id2()))
          .add("tca_s", c.tca_s())
          .add("tca_utc", format_sim_time(epoch, c.tca_s()))
          .add("miss_distance_m", c.miss_distance_m())
          .add("kappa", c.kappa())
          .add("relative_speed_m_s", c.relative_speed_m_s());
      std::cout << (i ? ",\n " : "") << obj.str();
    }
    std::cout << "]\n";
  } else if (*format == OutputFormat::kCsv) {
    for (std::size_t i = 0; i < columns.size(); ++i) std::cout << (i ? "," : "") << columns[i];
    std::cout << "\n";
    for (const auto& c : rows)
      std::cout << c.seq() << "," << kind_name(c.kind()) << "," << c.id1() << "," << c.id2() << ","
                << json_number(c.tca_s()) << "," << format_sim_time(epoch, c.tca_s()) << ","
                << json_number(c.miss_distance_m()) << "," << json_number(c.kappa()) << ","
                << json_number(c.relative_speed_m_s()) << "\n";
  } else {
    std::vector<std::vector<std::string>> table;
    char buf[4][32];
    for (const auto& c : rows) {
      std::snprintf(buf[0], 32, "%.1f", c.miss_distance_m());
      std::snprintf(buf[1], 32, "%.3f", c.kappa());
      std::snprintf(buf[2], 32, "%.3f", c.relative_speed_m_s() / 1000.0);
      std::snprintf(buf[3], 32, "%.3f", c.tca_s());
      table.push_back({std::to_string(c.seq()), kind_name(c.kind()), std::to_string(c.id1()),
                       std::to_string(c.id2()), format_sim_time(epoch, c.tca_s()), buf[3], buf[0], buf[1],
                       buf[2]});
    }
    if (table.empty())
      std::cout << "no conjunctions match\n";
    else
      std::cout << render_table({"SEQ", "KIND", "ID1", "ID2", "TCA (UTC)", "TCA [s]", "MISS [m]", "KAPPA",
                                 "V_REL [km/s]"},
                                table)
                << rows.size() << " conjunctions\n";
  }
  return kExitOk;
}

}  // namespace

KESSLER_COMMAND("conjunctions", 24, "conjunctions RUN [filters]",
                "a run's conjunctions, filtered (kappa, object, time, collisions, closest per pair)",
                conjunctions_main);

}  // namespace kessler::cli
