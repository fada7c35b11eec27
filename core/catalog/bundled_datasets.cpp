#include "core/catalog/bundled_datasets.hpp"

#include <cstdlib>

#include "core/catalog/satcat.hpp"

namespace kessler {

std::string default_datasets_dir() {
  if (const char* env = std::getenv("KESSLER_DATASETS_DIR"); env && *env) return env;
#ifdef KESSLER_DATASETS_DIR
  return KESSLER_DATASETS_DIR;
#else
  return "deploy/datasets";
#endif
}

std::optional<CatalogInput> load_bundled_catalog(const std::string& name, const std::string& dir,
                                                 std::string* error) {
  if (name != "catalog-2022") {
    if (error) *error = "unknown bundled catalog '" + name + "' (known: catalog-2022)";
    return std::nullopt;
  }
  CatalogInput input;
  input.format = CatalogFormat::kTle;
  input.source = "spacetrack_3le_2022-01-22_ODAP.txt";
  input.satcat_source = "spacetrack_satcat_2021-01-19.csv.gz";
  input.active_list_source = "2026-03-10_celestrak_active_gp.csv";
  auto text = read_catalog_file(dir + "/catalog/" + input.source, error);
  if (!text) return std::nullopt;
  input.text = std::move(*text);
  auto satcat = read_catalog_file(dir + "/catalog/" + input.satcat_source, error);
  if (!satcat) return std::nullopt;
  input.satcat_csv = std::move(*satcat);
  auto active = read_catalog_file(dir + "/catalog/" + input.active_list_source, error);
  if (!active) return std::nullopt;
  input.active_list = std::move(*active);
  return input;
}

}  // namespace kessler
