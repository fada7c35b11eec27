#include "core/catalog/leo19647.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace kessler {
namespace {

// One finite number per non-empty line; throws naming file and line otherwise.
std::vector<double> read_numbers(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  std::vector<double> values;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::size_t begin = line.find_first_not_of(" \t\r");
    if (begin == std::string::npos) continue;
    std::size_t end = line.find_last_not_of(" \t\r") + 1;
    std::string text = line.substr(begin, end - begin);
    char* stop = nullptr;
    errno = 0;
    double value = std::strtod(text.c_str(), &stop);
    if (stop != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": not a finite number: '" + text +
                               "'");
    values.push_back(value);
  }
  return values;
}

}  // namespace

UtcEpoch leo19647_epoch() {
  return UtcEpoch::from_calendar(2022, 3, 1, 0, 0, 0.0);
}

double paper_mass_kg(double r) {
  const double volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return r <= 0.01 ? volume * 2698.9 : volume * 92.937 * std::pow(2.0 * r, -0.74);
}

Population load_leo19647(const std::string& dir) {
  const std::string ic_path = dir + "/test_ic_19647.txt";
  const std::string par_path = dir + "/test_par_19647.txt";
  const std::vector<double> ic = read_numbers(ic_path);
  const std::vector<double> par = read_numbers(par_path);
  if (ic.size() % 7 != 0)
    throw std::runtime_error(ic_path + ": " + std::to_string(ic.size()) +
                             " numbers, not a multiple of 7 (x, y, z, vx, vy, vz, radius per object)");
  const std::size_t n = ic.size() / 7;
  if (par.size() != n)
    throw std::runtime_error(par_path + ": " + std::to_string(par.size()) + " values for " +
                             std::to_string(n) + " objects in " + ic_path);
  Population population;
  population.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* v = &ic[7 * i];
    ObjectRecord r;
    r.id = i + 1;
    r.name = "LEO19647-" + std::to_string(r.id);
    r.position_m = {v[0], v[1], v[2]};
    r.velocity_m_s = {v[3], v[4], v[5]};
    r.radius_m = v[6];
    if (!(r.radius_m > 0.0))
      throw std::runtime_error(ic_path + ":" + std::to_string(7 * i + 7) + ": object " +
                               std::to_string(r.id) + ": radius must be positive");
    if (par[i] < 0.0)
      throw std::runtime_error(par_path + ":" + std::to_string(i + 1) + ": object " + std::to_string(r.id) +
                               ": drag parameter must be non-negative");
    r.mass_kg = paper_mass_kg(r.radius_m);
    r.drag_area_to_mass_m2_kg = 2.0 * par[i] / kLeo19647Rho0_kg_m3;
    r.srp_area_to_mass_m2_kg = std::numbers::pi * r.radius_m * r.radius_m / r.mass_kg;
    if (auto problem = validate_record(r))
      throw std::runtime_error(ic_path + ":" + std::to_string(7 * i + 1) + ": " + *problem);
    population.add(r);
  }
  return population;
}

}  // namespace kessler
