// kessler assess FILE: a CDM's collision probability recomputed from its own states and covariances
// (core/assessment), next to the message's own value. Local: no daemon.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "client/command.hpp"
#include "client/render.hpp"
#include "core/assessment/cdm.hpp"
#include "core/assessment/cdm_conjunction.hpp"

namespace kessler::cli {
namespace {

struct AssessOptions {
  std::string file;
  std::optional<double> hbr_m;
  std::string method = "foster";
};

std::string number_or_null(double v) {
  if (!std::isfinite(v)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

// Reads the file, refusing one over the readers' limit before reading it.
bool read_text(const std::string& path, std::string& text, std::string& error) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) {
    error = path + ": " + ec.message();
    return false;
  }
  if (size > assessment::kMaxCdmBytes) {
    error = path + ": " + std::to_string(size) + " bytes, over the limit of " +
            std::to_string(assessment::kMaxCdmBytes) + " for a CDM";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  text = s.str();
  return true;
}

void print_json(const assessment::CdmConjunction& c, const assessment::Assessment& a, double hbr_m,
                const std::vector<assessment::CdmError>& problems) {
  std::cout << "{\"pc\": " << (a.pc_computed ? number_or_null(a.pc) : "null") << ", \"method\": \""
            << assessment::method_name(a.method)
            << "\", \"cdm_pc\": " << (c.cdm_pc ? number_or_null(*c.cdm_pc) : "null")
            << ", \"cdm_pc_method\": \"" << json_escape(c.cdm_pc_method)
            << "\", \"hbr_m\": " << number_or_null(hbr_m) << ", \"pc_max\": " << number_or_null(a.pc_max)
            << ", \"pc_max_sigma_m\": " << number_or_null(a.pc_max_sigma_m)
            << ", \"short_encounter\": " << (a.short_encounter ? "true" : "false")
            << ", \"encounter_duration_s\": " << number_or_null(a.encounter_duration_s) << ", \"tca\": \""
            << json_escape(c.tca) << "\", \"miss_distance_m\": " << number_or_null(c.miss_distance_m)
            << ", \"object1\": \"" << json_escape(c.objects[0].name) << "\", \"object2\": \""
            << json_escape(c.objects[1].name) << "\", \"problems\": [";
  for (std::size_t i = 0; i < problems.size(); ++i)
    std::cout << (i ? ", " : "") << "\"" << json_escape(problems[i].message) << "\"";
  std::cout << "]}\n";
}

void print_text(const assessment::CdmConjunction& c, const assessment::Assessment& a, double hbr_m) {
  std::printf("%s vs %s at %s, miss %.1f m, HBR %.3f m\n", c.objects[0].name.c_str(),
              c.objects[1].name.c_str(), c.tca.c_str(), c.miss_distance_m, hbr_m);
  if (a.pc_computed)
    std::printf("pc      %.6e (%s)\n", a.pc, std::string(assessment::method_name(a.method)).c_str());
  else
    std::printf("pc      not computed\n");
  if (c.cdm_pc)
    std::printf("cdm_pc  %.6e (%s)\n", *c.cdm_pc,
                c.cdm_pc_method.empty() ? "method not given" : c.cdm_pc_method.c_str());
  else
    std::printf("cdm_pc  none in the message\n");
  std::printf("pc_max  %.6e at a radial sigma of %.1f m (SOCRATES shape 100/300/100 m)\n", a.pc_max,
              a.pc_max_sigma_m);
  if (!a.short_encounter)
    std::printf("warning: the encounter lasts %.0f s, too long for the 2-D short-encounter model\n",
                a.encounter_duration_s);
}

int assess_file(const AssessOptions& o, const GlobalOptions& global) {
  if (!global.output.empty() && global.output != "json" && global.output != "table" &&
      global.output != "text")
    return usage_error("assess", "--output: must be table or json, got '" + global.output + "'");
  if (o.method != "foster" && o.method != "chan")
    return usage_error("assess", "--method: must be foster or chan, got '" + o.method + "'");
  std::string text;
  std::string error;
  if (!read_text(o.file, text, error)) {
    std::cerr << "kessler assess: " << error << "\n";
    return kExitUsage;
  }
  assessment::Cdm cdm;
  std::vector<assessment::CdmError> problems;
  if (!assessment::read_cdm(text, cdm, problems)) {
    for (const auto& p : problems) std::cerr << "kessler assess: " << o.file << ": " << p.message << "\n";
    return kExitUsage;
  }
  assessment::CdmConjunction conjunction;
  assessment::read_conjunction(cdm, conjunction, problems);
  for (const auto& p : problems) std::cerr << "kessler assess: " << o.file << ": " << p.message << "\n";
  const double hbr_m = assessment::choose_hard_body_radius(conjunction, o.hbr_m);
  if (!(hbr_m > 0.0)) {
    std::cerr << "kessler assess: " << o.file
              << ": no hard-body radius in the message (no HBR, no AREA_PC): give --hbr\n";
    return kExitUsage;
  }
  const assessment::Assessment a = assessment::assess_cdm(
      conjunction, hbr_m, o.method == "chan" ? assessment::PcMethod::kChan : assessment::PcMethod::kFoster);
  if (global.output == "json")
    print_json(conjunction, a, hbr_m, problems);
  else
    print_text(conjunction, a, hbr_m);
  return problems.empty() && a.pc_computed ? kExitOk : kExitUsage;
}

}  // namespace

CommandRun setup_assess(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<AssessOptions>();
  command.add_option("FILE", o->file, "a CDM, KVN or XML (CCSDS 508.0-B-1)")->required();
  command
      .add_option("--hbr", o->hbr_m,
                  "hard-body radius r1 + r2 in metres (default: the CDM's, else from AREA_PC)")
      ->option_text("METRES")
      ->check(positive_number());
  command.add_option("--method", o->method,
                     "foster (default; the reference integral) or chan (Chan's series)");
  add_global_options(command, global, "table (default) or json (one object: pc, method, cdm_pc, ...)", false);
  command.footer(
      "Reads a Conjunction Data Message and recomputes its 2-D collision probability from the two objects' "
      "states and RTN position covariances, next to the message's own COLLISION_PROBABILITY. Problems "
      "(missing mandatory keywords, bad units or numbers, a covariance that is not positive definite) are "
      "printed with their line and keyword and make the exit code 2; no Pc is computed from a covariance "
      "that is not positive definite."
      "\n\n"
      "examples:\n"
      "  kessler assess conjunction.cdm\n"
      "  kessler assess conjunction.xml --hbr 12 --output json");
  return [o, &global] { return assess_file(*o, global); };
}

}  // namespace kessler::cli
