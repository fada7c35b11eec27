// The catalogs shipped with the project under deploy/datasets/ (KESSLER_DATASETS_DIR):
//   "catalog-2022": catalog/spacetrack_3le_2022-01-22_ODAP.txt (3LE, 23,939 objects),
//                   catalog/spacetrack_satcat_2021-01-19.csv.gz (Space-Track SATCAT),
//                   catalog/2026-03-10_celestrak_active_gp.csv (CelesTrak active list, OMM CSV).
//   "catalog-2019": catalog-2019/spacetrack_3le_2019-03-19.txt.gz (3LE, 17,892 objects) with the same
//                   SATCAT (whose DECAY dates are the decay check's outcome); no active list (the SATCAT of
//                   2021 has no status, and the 2026 list would be anachronistic), so every object is
//                   passive.
// The element data originate from the 18th Space Defense Squadron via Space-Track.org and CelesTrak.
#pragma once

#include <optional>
#include <string>

#include "core/catalog/ingest.hpp"

namespace kessler {

// The datasets folder: the KESSLER_DATASETS_DIR environment variable when set, else the build's.
std::string default_datasets_dir();

// The inputs of a bundled catalog by name ("catalog-2022", "catalog-2019"). nullopt with *error for an
// unknown name or a missing file.
std::optional<CatalogInput> load_bundled_catalog(const std::string& name, const std::string& datasets_dir,
                                                 std::string* error);

}  // namespace kessler
