// The registry of figures: a plain list of (id, title, function), each function under
// server/figures/<name>.cpp turning a FigureSubject into a Vega-Lite v5 spec (null: not applicable).
// figures_for_run / figures_for_ensemble load the subject through the RunManager (the same service
// layer as the gRPC API) and return the figures that apply; RunManager::figures (GetFigures) serves them.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "server/figures/figure.hpp"

namespace kessler::server {
class RunManager;
}

namespace kessler::server::figures {

struct FigureEntry {
  const char* id;
  const char* title;
  std::function<nlohmann::json(const FigureSubject&)> build;
};

// Every figure, in the order reports show them. Add a figure here.
const std::vector<FigureEntry>& registry();

// The figures that apply to the subject (those whose function returns a spec).
std::vector<Figure> figures_for(const FigureSubject& subject);

// Loads through the manager (NOT_FOUND and INVALID_ARGUMENT as ServiceError). compare: other runs'
// ids drawn beside run_id, at most kMaxCompared.
inline constexpr std::size_t kMaxCompared = 16;
FigureSubject load_run_subject(RunManager& manager, std::int64_t run_id,
                               const std::vector<std::int64_t>& compare);
FigureSubject load_ensemble_subject(RunManager& manager, std::int64_t ensemble_id);

std::vector<Figure> figures_for_run(RunManager& manager, std::int64_t run_id,
                                    const std::vector<std::int64_t>& compare = {});
std::vector<Figure> figures_for_ensemble(RunManager& manager, std::int64_t ensemble_id);

}  // namespace kessler::server::figures
