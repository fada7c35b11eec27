// kessler conjunctions RUN: a run's conjunction catalog, filtered and sorted, as a table, CSV or JSON,
// with the objects' names where the run's population has them and each conjunction's collision
// probability; or as one CCSDS CDM per conjunction (--output cdm).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
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
  std::optional<double> kappa_min, kappa_max, from_s, to_s, pc_min;
  std::string sort;
  std::string dir = ".";
  std::string cdm_format = "kvn";
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
  if (o.pc_min) request.set_pc_min(*o.pc_min);
  request.set_sort(o.sort);
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
        .add_raw("v2_m_s", vector_json(c.v2_m_s()))
        .add_raw("pc", c.has_pc() ? json_number(c.pc()) : "null")
        .add("pc_method", c.pc_method())
        .add("covariance_source", c.covariance_source())
        .add_raw("pc_max", c.has_pc_max() ? json_number(c.pc_max()) : "null")
        .add("pc_max_sigma_m", c.pc_max_sigma_m())
        .add("short_encounter", c.short_encounter());
    std::cout << (i ? ",\n " : "") << obj.str();
  }
  std::cout << "]\n";
}

std::string optional_number(bool has, double v) {
  return has ? json_number(v) : "";
}

// The names, then the probabilities come last so the columns before them stay where scripts expect them.
void print_csv(const std::vector<v1::Encounter>& rows, const std::string& epoch) {
  std::cout
      << "seq,kind,id1,id2,tca_s,tca_utc,miss_distance_m,kappa,relative_speed_m_s,name1,name2,pc,pc_method,"
         "covariance_source,pc_max,pc_max_sigma_m\n";
  for (const auto& c : rows)
    std::cout << c.seq() << "," << kind_name(c.kind()) << "," << c.id1() << "," << c.id2() << ","
              << json_number(c.tca_s()) << "," << format_sim_time(epoch, c.tca_s()) << ","
              << json_number(c.miss_distance_m()) << "," << json_number(c.kappa()) << ","
              << json_number(c.relative_speed_m_s()) << "," << csv_field(c.name1()) << ","
              << csv_field(c.name2()) << "," << optional_number(c.has_pc(), c.pc()) << "," << c.pc_method()
              << "," << c.covariance_source() << "," << optional_number(c.has_pc_max(), c.pc_max()) << ","
              << json_number(c.pc_max_sigma_m()) << "\n";
}

void print_table(const std::vector<v1::Encounter>& rows, const std::string& epoch) {
  if (rows.empty()) {
    std::cout << "no conjunctions match\n";
    return;
  }
  std::vector<std::vector<std::string>> table;
  char buf[6][32];
  for (const auto& c : rows) {
    std::snprintf(buf[0], 32, "%.1f", c.miss_distance_m());
    std::snprintf(buf[1], 32, "%.3f", c.kappa());
    std::snprintf(buf[2], 32, "%.3f", c.relative_speed_m_s() / 1000.0);
    std::snprintf(buf[3], 32, "%.3f", c.tca_s());
    std::snprintf(buf[4], 32, c.has_pc() ? "%.2e" : "-", c.pc());
    std::snprintf(buf[5], 32, c.has_pc_max() ? "%.2e" : "-", c.pc_max());
    table.push_back({std::to_string(c.seq()), kind_name(c.kind()), std::to_string(c.id1()),
                     c.name1().empty() ? "-" : c.name1(), std::to_string(c.id2()),
                     c.name2().empty() ? "-" : c.name2(), format_sim_time(epoch, c.tca_s()), buf[3], buf[0],
                     buf[1], buf[2], buf[4], buf[5]});
  }
  std::cout << render_table({"SEQ", "KIND", "ID1", "NAME1", "ID2", "NAME2", "TCA (UTC)", "TCA [s]",
                             "MISS [m]", "KAPPA", "V_REL [km/s]", "PC", "PC_MAX"},
                            table)
            << rows.size() << " conjunctions\n";
}

// One CDM file per conjunction in o.dir, from GetConjunctionCdm.
int write_cdms(RemoteClient& client, const ConjunctionsOptions& o, const std::vector<v1::Encounter>& rows) {
  std::error_code ec;
  std::filesystem::create_directories(o.dir, ec);
  if (ec) {
    std::cerr << "kessler conjunctions: --dir " << o.dir << ": " << ec.message() << "\n";
    return kExitUsage;
  }
  v1::GetConjunctionCdmRequest request;
  request.set_run_id(o.run_id);
  request.set_format(o.cdm_format);
  for (const auto& c : rows) {
    request.set_seq(c.seq());
    v1::ConjunctionCdm cdm;
    const CallResult r = client.conjunction_cdm(request, cdm);
    if (!r.ok) {
      std::cerr << "kessler conjunctions: " << r.describe() << "\n";
      return r.exit_code();
    }
    const std::filesystem::path path = std::filesystem::path(o.dir) / cdm.file_name();
    std::ofstream out(path, std::ios::binary);
    out << cdm.text();
    if (!out) {
      std::cerr << "kessler conjunctions: cannot write " << path.string() << "\n";
      return kExitFailure;
    }
  }
  std::cout << rows.size() << " CDMs written to " << o.dir << "\n";
  return kExitOk;
}

int list_conjunctions(const ConjunctionsOptions& o, const GlobalOptions& global) {
  const bool cdm = global.output == "cdm";
  OutputFormat format = OutputFormat::kTable;
  if (!cdm && !resolve_output("conjunctions", global.output, {"table", "csv", "json"}, format))
    return kExitUsage;
  if (o.cdm_format != "kvn" && o.cdm_format != "xml")
    return usage_error("conjunctions", "--cdm-format: must be kvn or xml, got '" + o.cdm_format + "'");
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
  if (cdm) return write_cdms(client, o, rows);
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
  command.add_option("--pc-min", o->pc_min, "collision probability at least P (0..1)")->option_text("P");
  command.add_option("--sort", o->sort, "seq (default), pc or pc_max (largest first), miss (closest first)")
      ->option_text("KEY");
  command.add_option("--limit", o->limit, "at most N rows (default: all)")->option_text("N");
  command.add_option("--dir", o->dir, "with --output cdm: the folder for the CDM files (default .)")
      ->option_text("D");
  command.add_option("--cdm-format", o->cdm_format, "with --output cdm: kvn (default) or xml")
      ->option_text("F");
  add_global_options(command, global,
                     "table (default), csv (a header row, then one row per encounter) or json (an array of "
                     "objects with the CSV's columns as keys and both objects' states at TCA), or cdm (one "
                     "CCSDS CDM file per conjunction in --dir)");
  command.footer(
      "Lists a run's conjunctions (collisions included) in the order they happened, with the objects' "
      "catalog "
      "ids and names (where the population has names), and each one's collision probability: pc (from "
      "the covariance model, Chan's series or Foster's integral) and pc_max (the maximum over the "
      "covariance's scale with SOCRATES's 100/300/100 m shape), computed by the daemon as it lists them."
      "\n\n"
      "examples:\n"
      "  kessler conjunctions 1 --kappa-max 1 --closest-per-pair\n"
      "  kessler conjunctions 1 --object 25544 --output csv > iss.csv\n"
      "  kessler conjunctions 1 --pc-min 1e-6 --sort pc\n"
      "  kessler conjunctions 1 --sort pc_max --limit 10 --output cdm --dir cdms --cdm-format xml");
  return [o, &global] { return list_conjunctions(*o, global); };
}

}  // namespace kessler::cli
