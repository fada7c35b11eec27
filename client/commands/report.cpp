// kessler report RUN|--ensemble ID [--compare RUN...] -o FILE: one self-contained HTML file with the
// figures that apply (GetFigures), the scenario, the fingerprint and the ingest report, that opens
// offline (the charting scripts are inlined). A run still running gives a report of what exists,
// marked partial.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "client/command.hpp"
#include "client/commands/report_html.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

struct ReportOptions {
  std::int64_t run_id = 0;
  std::int64_t ensemble_id = 0;
  std::vector<std::int64_t> compare;
  std::string out_path;
};

// Empty when `path` can be written (created or replaced), else why not.
std::string unwritable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return "is a directory";
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) return "no directory " + dir.string();
  if (fs::exists(path, ec) ? access(path.c_str(), W_OK) != 0 : access(dir.c_str(), W_OK) != 0)
    return std::strerror(errno);
  return "";
}

// A refused call: NOT_FOUND (no such run or ensemble) and INVALID_ARGUMENT are the user's input: exit 2.
int call_failed(const CallResult& r) {
  std::cerr << "kessler report: " << r.describe() << "\n";
  return r.code == 5 ? kExitUsage : r.exit_code();
}

int report(const ReportOptions& o, const GlobalOptions& global) {
  if ((o.run_id > 0) == (o.ensemble_id > 0))
    return usage_error("report", "give a RUN or --ensemble ID (one of them)");
  if (o.ensemble_id > 0 && !o.compare.empty())
    return usage_error("report", "--compare compares runs, not ensembles");
  if (std::string why = unwritable(o.out_path); !why.empty())
    return usage_error("report", "cannot write " + o.out_path + ": " + why);
  RemoteClient client(server_address(global.server));
  ReportContent content;
  v1::GetFiguresRequest request;
  if (o.ensemble_id > 0) {
    request.set_ensemble_id(o.ensemble_id);
    v1::GetEnsembleRequest get;
    get.set_ensemble_id(o.ensemble_id);
    v1::EnsembleReport e;
    if (CallResult r = client.get_ensemble(get, e); !r.ok) return call_failed(r);
    content.title = "ensemble " + std::to_string(e.id()) + (e.name().empty() ? "" : " (" + e.name() + ")");
    e.clear_series();
    content.ensemble = std::move(e);
  } else {
    request.set_run_id(o.run_id);
    std::vector<std::int64_t> ids = {o.run_id};
    ids.insert(ids.end(), o.compare.begin(), o.compare.end());
    for (std::int64_t id : ids) {
      request.add_compare_run_ids(id);
      v1::Run run;
      if (CallResult r = client.get(id, run); !r.ok) return call_failed(r);
      content.runs.push_back(std::move(run));
    }
    request.mutable_compare_run_ids()->erase(request.mutable_compare_run_ids()->begin());
    const v1::Run& first = content.runs.front();
    content.title =
        "run " + std::to_string(first.id()) + (first.name().empty() ? "" : " (" + first.name() + ")");
  }
  v1::GetFiguresResponse figures;
  if (CallResult r = client.figures(request, figures); !r.ok) return call_failed(r);
  content.figures.assign(figures.figures().begin(), figures.figures().end());
  for (const auto& f : content.figures) content.partial = content.partial || f.partial();
  for (const auto& run : content.runs) content.partial = content.partial || !run.has_summary();
  if (content.ensemble && content.ensemble->finished() < content.ensemble->members()) content.partial = true;

  const std::string tmp = o.out_path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << report_html(content);
    if (!out.flush()) {
      std::remove(tmp.c_str());
      return usage_error("report", "cannot write " + o.out_path);
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, o.out_path, ec);
  if (ec) return usage_error("report", "cannot write " + o.out_path + ": " + ec.message());
  std::cout << "kessler report: wrote " << o.out_path << " (" << content.figures.size() << " figures"
            << (content.partial ? ", partial: not every run has ended" : "") << ")\n";
  return kExitOk;
}

}  // namespace

CommandRun setup_report(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<ReportOptions>();
  command.add_option("RUN", o->run_id, "the run's id (kessler runs lists them)")->check(CLI::PositiveNumber);
  command.add_option("--ensemble", o->ensemble_id, "an ensemble's id instead of a run")
      ->option_text("ID")
      ->check(CLI::PositiveNumber);
  command.add_option("--compare", o->compare, "runs drawn beside RUN in the figures that compare")
      ->option_text("RUN...")
      ->check(CLI::PositiveNumber);
  command.add_option("-o,--out", o->out_path, "the HTML file to write")->option_text("FILE")->required();
  add_global_options(command, global, "(not used: the report is HTML)");
  command.footer(
      "Writes one HTML file that opens offline: the figures that apply (conjunctions over time by kappa and "
      "against kappa, runtime by phase, objects on orbit by type, ...), the scenario, the fingerprint and "
      "the "
      "ingest report. A run still running gives what exists so far, marked partial.\n\n"
      "examples:\n  kessler report 1 -o run1.html\n  kessler report 1 --compare 2 3 -o runs.html\n"
      "  kessler report --ensemble 1 -o ensemble1.html");
  return [o, &global] { return report(*o, global); };
}

}  // namespace kessler::cli
