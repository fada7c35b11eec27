// SGP4 for many objects at once: near-Earth element sets (periods < 225 min) in structure-of-arrays
// form, propagated in blocks of vector lanes with branch-free sine/cosine; deep-space sets go through
// the scalar sgp4_propagate. Each object's result depends on its own record and time only.
//
// Differences to sgp4_propagate are rounding-level (own sine/cosine, atan2 replaced by an exact
// rotation identity, fmod by a rounding reduction): well inside the verification tolerances.
#pragma once

#include <cstddef>
#include <vector>

#include "core/sgp4/sgp4.hpp"

namespace kessler {

struct Sgp4BatchOutput {
  double *x = nullptr, *y = nullptr, *z = nullptr;     // position, scaled by position_scale (1 = km)
  double *vx = nullptr, *vy = nullptr, *vz = nullptr;  // velocity, scaled by velocity_scale (1 = km/s)
  double position_scale = 1.0;
  double velocity_scale = 1.0;
  Sgp4Error* error = nullptr;  // per object
};

class Sgp4Batch {
 public:
  static constexpr std::size_t kLanes = 8;

  Sgp4Batch() = default;
  explicit Sgp4Batch(const std::vector<Sgp4Record>& records) { assign(records); }
  void assign(const std::vector<Sgp4Record>& records);
  std::size_t size() const { return records_.size(); }
  std::size_t near_earth_count() const { return near_count_; }

  // States of objects [begin, end) at minutes_since_epoch[i] (indexed like the records). Call from
  // one thread per range; ranges may run in parallel.
  void propagate(const double* minutes_since_epoch, const Sgp4BatchOutput& out, std::size_t begin,
                 std::size_t end) const;
  // All objects, in parallel over blocks (OpenMP).
  void propagate_all(const double* minutes_since_epoch, const Sgp4BatchOutput& out) const;

 private:
  void propagate_block(std::size_t first, std::size_t count, const double* minutes,
                       const Sgp4BatchOutput& out) const;

  std::vector<Sgp4Record> records_;
  std::size_t near_count_ = 0;
  std::vector<unsigned char> near_;  // 1: near-Earth, vector path
  // Near-Earth coefficients by object index.
  std::vector<double> mo_, mdot_, argpo_, argpdot_, nodeo_, nodedot_, nodecf_, cc1_, bcc4_, t2cof_;
  std::vector<double> omgcof_, eta_, xmcof_, delmo_, d2_, d3_, d4_, bcc5_, sinmao_, t3cof_, t4cof_, t5cof_;
  std::vector<double> ecco_, no_, a0_, aycof_, xlcof_, con41_, x1mth2_, x7thm1_, cosio_, sinio_;
};

}  // namespace kessler
