#include "core/catalog/leo19647.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {

Population leo19647_repeated(const std::string& dir, std::size_t objects) {
  const Population base = load_leo19647(dir);
  Population p;
  p.reserve(objects);
  for (std::size_t i = 0; i < objects; ++i) {
    ObjectRecord r = base.record(i % base.size());
    r.id = i + 1;
    r.position_m *= 1.0 + 1.0e-6 * static_cast<double>(i / base.size());
    p.add(r);
  }
  return p;
}

}  // namespace kessler::bench
