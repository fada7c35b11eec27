#include "client/commands/report_html.hpp"

#include <nlohmann/json.hpp>

#include <sstream>

#include "client/remote/cli_support.hpp"
#include "kessler/v1/names.hpp"
#include "web/assets.hpp"
#include "web/figure_page.hpp"

namespace kessler::cli {
namespace {

using web::html_escape;

std::string row(const std::string& key, const std::string& value) {
  return "<tr><th>" + html_escape(key) + "</th><td>" + html_escape(value) + "</td></tr>";
}

std::string run_section(const v1::Run& run) {
  std::ostringstream out;
  out << "<h2 id=\"run-" << run.id() << "\">Run " << run.id()
      << (run.name().empty() ? "" : " (" + html_escape(run.name()) + ")") << "</h2><table>"
      << row("state", v1::run_state_name(run.state()));
  if (!run.error().empty()) out << row("error", run.error());
  if (run.has_progress())
    out << row("progress", "step " + std::to_string(run.progress().step()) + " of " +
                               std::to_string(run.progress().total_steps()));
  if (run.has_summary()) {
    const v1::RunSummary& s = run.summary();
    out << row("events digest", s.events_digest()) << row("state digest", s.state_digest())
        << row("conjunctions", std::to_string(s.conjunctions()))
        << row("collisions", std::to_string(s.collisions())) << row("evasions", std::to_string(s.evasions()))
        << row("burn-ups", std::to_string(s.burn_ups()))
        << row("objects", std::to_string(s.objects_initial()) + " at the start, " +
                              std::to_string(s.objects_final()) + " at the end");
  } else {
    out << row("fingerprint", "not yet: the run has not ended");
  }
  out << "</table>";
  if (run.has_ingest()) {
    const v1::IngestReport& ingest = run.ingest();
    out << "<h3>Ingest report</h3><table>" << row("records", std::to_string(ingest.records()))
        << row("kept", std::to_string(ingest.kept()));
    for (const auto& d : ingest.dropped()) out << row("dropped: " + d.reason(), std::to_string(d.count()));
    out << "</table>";
  }
  v1::Scenario scenario = run.scenario();
  if (scenario.population().has_catalog()) {
    auto* catalog = scenario.mutable_population()->mutable_catalog();
    catalog->set_text("<" + std::to_string(catalog->text().size()) + " bytes inline>");
  }
  out << "<h3>Scenario</h3><pre>" << html_escape(nlohmann::json::parse(to_json(scenario)).dump(2))
      << "</pre>";
  return out.str();
}

std::string ensemble_section(const v1::EnsembleReport& e) {
  std::ostringstream out;
  out << "<h2>Ensemble " << e.id() << "</h2><table>" << row("state", v1::run_state_name(e.state()))
      << row("members", std::to_string(e.members()) + " (" + std::to_string(e.finished()) + " ended, " +
                            std::to_string(e.aggregated()) + " aggregated)")
      << row("base seed", std::to_string(e.base_seed())) << "</table>";
  out << "<h3>Members</h3><table><tr><th>index</th><th>run</th><th>seed</th><th>state</th><th>events "
         "digest</th></tr>";
  for (const auto& m : e.member())
    out << "<tr><td>" << m.member_index() << "</td><td>" << m.run_id() << "</td><td>" << m.seed()
        << "</td><td>" << v1::run_state_name(m.state()) << "</td><td>" << html_escape(m.events_digest())
        << "</td></tr>";
  out << "</table><h3>Scenario</h3><pre>" << html_escape(nlohmann::json::parse(to_json(e.scenario())).dump(2))
      << "</pre>";
  return out.str();
}

std::string figures_json(const std::vector<v1::Figure>& figures) {
  nlohmann::json list = nlohmann::json::array();
  for (const v1::Figure& f : figures)
    list.push_back({{"id", f.id()},
                    {"title", f.title()},
                    {"partial", f.partial()},
                    {"spec", nlohmann::json::parse(f.vega_lite_json())}});
  return web::script_safe(list.dump());
}

}  // namespace

std::string report_html(const ReportContent& content) {
  std::ostringstream out;
  out << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>"
      << html_escape(content.title) << "</title><style>" << web::page_style() << "</style>\n<script>"
      << web::charting_scripts() << "</script>\n<script>" << web::render_script()
      << "</script></head><body>\n<h1>Kessler report: " << html_escape(content.title) << "</h1>\n";
  if (content.partial)
    out << "<p class=\"partial\" id=\"partial\">Partial: drawn from a run that has not ended; the figures "
           "show "
           "what existed when the report was made.</p>\n";
  out << "<h2>Figures</h2><div id=\"figures\"></div>\n";
  if (content.ensemble) out << ensemble_section(*content.ensemble);
  for (const v1::Run& run : content.runs) out << run_section(run) << "\n";
  out << "<script>kesslerRenderFigures(document.getElementById('figures'), " << figures_json(content.figures)
      << ");</script>\n</body></html>\n";
  return out.str();
}

}  // namespace kessler::cli
