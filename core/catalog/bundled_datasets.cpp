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
  CatalogInput input;
  input.format = CatalogFormat::kTle;
  input.satcat_source = "spacetrack_satcat_2021-01-19.csv.gz";
  std::string folder = "/catalog/";
  bool active_list = true;
  if (name == "catalog-2022") {
    input.source = "spacetrack_3le_2022-01-22_ODAP.txt";
    input.active_list_source = "2026-03-10_celestrak_active_gp.csv";
  } else if (name == "catalog-2019") {
    folder = "/catalog-2019/";
    input.source = "spacetrack_3le_2019-03-19.txt.gz";
    active_list = false;
  } else {
    if (error) *error = "unknown bundled catalog '" + name + "' (known: catalog-2022, catalog-2019)";
    return std::nullopt;
  }
  auto text = read_catalog_file(dir + folder + input.source, error);
  if (!text) return std::nullopt;
  input.text = std::move(*text);
  auto satcat = read_catalog_file(dir + "/catalog/" + input.satcat_source, error);
  if (!satcat) return std::nullopt;
  input.satcat_csv = std::move(*satcat);
  if (!active_list) return input;
  auto active = read_catalog_file(dir + "/catalog/" + input.active_list_source, error);
  if (!active) return std::nullopt;
  input.active_list = std::move(*active);
  return input;
}

}  // namespace kessler
