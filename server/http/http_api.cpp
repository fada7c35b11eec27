// The dashboard's JSON API (/api/...) and its CSV download, each a thin translation of a RunManager
// call, as the gRPC API's handlers are.
#include <google/protobuf/util/json_util.h>

#include <sstream>

#include "kessler/v1/names.hpp"
#include "server/figures/figures.hpp"
#include "server/run_manager.hpp"
// (after run_manager.hpp: see http_server.cpp)
#include "server/http/http_internal.hpp"
#include "web/assets.hpp"
#include "web/figure_page.hpp"

namespace kessler::server::http {
namespace {

using nlohmann::json;

json to_json(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string text;
  if (!google::protobuf::util::MessageToJsonString(message, &text, options).ok())
    throw std::runtime_error("cannot print a message as JSON");
  return json::parse(text);
}

std::vector<v1::RunState> parse_states(const std::string& list) {
  std::vector<v1::RunState> states;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    bool found = false;
    for (int s = v1::RUN_STATE_QUEUED; s <= v1::RUN_STATE_CANCELLED; ++s)
      if (name == v1::run_state_name(static_cast<v1::RunState>(s))) {
        states.push_back(static_cast<v1::RunState>(s));
        found = true;
      }
    if (!found)
      throw BadParameter("state",
                         "must be queued, running, succeeded, failed or cancelled, got '" + name + "'");
  }
  return states;
}

void list_runs(RunManager& manager, const httplib::Request& req, httplib::Response& res) {
  Params p(req, {"state", "page_size", "page_token"});
  v1::ListRunsRequest request;
  if (auto s = p.text("state"))
    for (v1::RunState st : parse_states(*s)) request.add_states(st);
  request.set_page_size(static_cast<int>(p.integer("page_size", 1, kMaxPageSize).value_or(50)));
  request.set_page_token(p.text("page_token").value_or(""));
  send_json(res, to_json(manager.list(request)));
}

void get_run(RunManager& manager, const httplib::Request& req, httplib::Response& res) {
  Params p(req, {});
  v1::Run run = manager.get(path_id(req, "run_id"));
  // An inline catalog can be megabytes: its size, not its text.
  if (run.scenario().population().has_catalog()) {
    auto* catalog = run.mutable_scenario()->mutable_population()->mutable_catalog();
    catalog->set_text("<" + std::to_string(catalog->text().size()) + " bytes inline>");
  }
  send_json(res, to_json(run));
}

v1::ListConjunctionsRequest conjunctions_request(const Params& p, std::int64_t run_id, bool csv) {
  v1::ListConjunctionsRequest r;
  r.set_run_id(run_id);
  if (auto v = p.number("kappa_min")) r.set_kappa_min(*v);
  if (auto v = p.number("kappa_max")) r.set_kappa_max(*v);
  if (auto v = p.integer("object_id", 0, INT64_MAX)) r.set_object_id(static_cast<std::uint64_t>(*v));
  if (auto v = p.number("time_min_s")) r.set_time_min_s(*v);
  if (auto v = p.number("time_max_s")) r.set_time_max_s(*v);
  r.set_collisions_only(p.flag("collisions_only"));
  r.set_include_evasions(p.flag("include_evasions"));
  r.set_closest_per_pair(p.flag("closest_per_pair"));
  if (auto v = p.text("order_by")) r.set_order_by(*v);
  r.set_descending(p.flag("descending"));
  const std::int64_t max = csv ? kMaxCsvRows : kMaxPageSize;
  r.set_page_size(
      static_cast<int>(p.integer("page_size", 1, max).value_or(csv ? kMaxCsvRows : kDefaultPageSize)));
  r.set_page_token(p.text("page_token").value_or(""));
  return r;
}

const char* kind_name(v1::EncounterKind kind) {
  return kind == v1::ENCOUNTER_KIND_COLLISION ? "collision"
         : kind == v1::ENCOUNTER_KIND_EVASION ? "evasion"
                                              : "conjunction";
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string conjunctions_csv(const v1::ListConjunctionsResponse& page) {
  std::ostringstream out;
  out.precision(17);
  out << "seq,tca_s,id1,name1,id2,name2,miss_distance_m,relative_speed_m_s,kappa,kind\n";
  for (const v1::Encounter& e : page.conjunctions())
    out << e.seq() << ',' << e.tca_s() << ',' << e.id1() << ',' << csv_field(e.name1()) << ',' << e.id2()
        << ',' << csv_field(e.name2()) << ',' << e.miss_distance_m() << ',' << e.relative_speed_m_s() << ','
        << e.kappa() << ',' << kind_name(e.kind()) << '\n';
  return out.str();
}

void list_conjunctions(RunManager& manager, const httplib::Request& req, httplib::Response& res) {
  Params p(req, {"kappa_min", "kappa_max", "object_id", "time_min_s", "time_max_s", "collisions_only",
                 "include_evasions", "closest_per_pair", "order_by", "descending", "page_size", "page_token",
                 "format"});
  const std::string format = p.text("format").value_or("json");
  if (format != "json" && format != "csv")
    throw BadParameter("format", "must be json or csv, got '" + format + "'");
  const std::int64_t run_id = path_id(req, "run_id");
  v1::ListConjunctionsResponse page = manager.conjunctions(conjunctions_request(p, run_id, format == "csv"));
  if (format == "csv") {
    res.set_header("Content-Disposition",
                   "attachment; filename=\"run-" + std::to_string(run_id) + "-conjunctions.csv\"");
    res.set_header("X-Total-Count", std::to_string(page.total()));
    if (!page.next_page_token().empty()) res.set_header("X-Next-Page-Token", page.next_page_token());
    res.set_content(conjunctions_csv(page), "text/csv");
    return;
  }
  json rows = json::array();
  for (const v1::Encounter& e : page.conjunctions())
    rows.push_back({{"seq", e.seq()},
                    {"tca_s", e.tca_s()},
                    {"id1", e.id1()},
                    {"name1", e.name1()},
                    {"id2", e.id2()},
                    {"name2", e.name2()},
                    {"miss_distance_m", e.miss_distance_m()},
                    {"relative_speed_m_s", e.relative_speed_m_s()},
                    {"kappa", e.kappa()},
                    {"kind", kind_name(e.kind())}});
  send_json(res,
            {{"conjunctions", rows}, {"next_page_token", page.next_page_token()}, {"total", page.total()}});
}

std::vector<std::int64_t> parse_ids(const std::optional<std::string>& list, const std::string& name) {
  std::vector<std::int64_t> ids;
  if (!list) return ids;
  std::stringstream in(*list);
  for (std::string word; std::getline(in, word, ',');) {
    char* end = nullptr;
    const long long v = std::strtoll(word.c_str(), &end, 10);
    if (word.empty() || *end != '\0' || v <= 0)
      throw BadParameter(name, "must list run ids, got '" + word + "'");
    ids.push_back(v);
  }
  if (ids.size() > figures::kMaxCompared)
    throw BadParameter(name, "at most " + std::to_string(figures::kMaxCompared) + " runs");
  return ids;
}

json figures_json(const std::vector<figures::Figure>& list) {
  json out = json::array();
  for (const auto& f : list)
    out.push_back({{"id", f.id}, {"title", f.title}, {"partial", f.partial}, {"spec", f.spec}});
  return {{"figures", out}};
}

void list_ensembles(RunManager& manager, const httplib::Request& req, httplib::Response& res) {
  Params p(req, {"page_size", "page_token"});
  v1::ListEnsemblesRequest request;
  request.set_page_size(static_cast<int>(p.integer("page_size", 1, kMaxPageSize).value_or(50)));
  request.set_page_token(p.text("page_token").value_or(""));
  send_json(res, to_json(manager.list_ensembles(request)));
}

void get_ensemble(RunManager& manager, const httplib::Request& req, httplib::Response& res) {
  Params p(req, {});
  v1::GetEnsembleRequest request;
  request.set_ensemble_id(path_id(req, "ensemble_id"));
  v1::EnsembleReport report = manager.get_ensemble(request);
  report.clear_scenario();
  send_json(res, to_json(report));
}

}  // namespace

void add_api_routes(httplib::Server& server, RunManager& manager) {
  using Handler = void (*)(RunManager&, const httplib::Request&, httplib::Response&);
  auto route = [&](const char* pattern, Handler handler) {
    server.Get(pattern, [&manager, handler](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] { handler(manager, req, res); });
    });
  };
  route("/api/runs", list_runs);
  route(R"(/api/runs/(\d+))", get_run);
  route(R"(/api/runs/(\d+)/conjunctions)", list_conjunctions);
  route(R"(/api/runs/(\d+)/figures)", [](RunManager& m, const httplib::Request& req, httplib::Response& res) {
    Params p(req, {"compare"});
    send_json(res, figures_json(figures::figures_for_run(m, path_id(req, "run_id"),
                                                         parse_ids(p.text("compare"), "compare"))));
  });
  route("/api/ensembles", list_ensembles);
  route(R"(/api/ensembles/(\d+))", get_ensemble);
  route(R"(/api/ensembles/(\d+)/figures)",
        [](RunManager& m, const httplib::Request& req, httplib::Response& res) {
          Params p(req, {});
          send_json(res, figures_json(figures::figures_for_ensemble(m, path_id(req, "ensemble_id"))));
        });
  server.Get("/assets/charts.js", [](const httplib::Request&, httplib::Response& res) {
    static const std::string script = web::charting_scripts() + "\n" + web::render_script();
    res.set_header("Cache-Control", "max-age=3600");
    res.set_content(script, "application/javascript");
  });
}

}  // namespace kessler::server::http
