// The HTML of `kessler report`: one self-contained page (charting scripts inlined) with the figures, the
// scenario, the fingerprint and the ingest report. Plain data in, text out: no gRPC here.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "kessler/v1/service.pb.h"

namespace kessler::cli {

struct ReportContent {
  std::string title;          // "run 7 (paper-1day)"
  bool partial = false;       // some run (or member) has not ended
  std::vector<v1::Run> runs;  // the run and those compared (with scenarios), or the members
  std::optional<v1::EnsembleReport> ensemble;
  std::vector<v1::Figure> figures;
};

std::string report_html(const ReportContent& content);

}  // namespace kessler::cli
