// kessler-bench: one program, one subcommand per measured capability. Each subcommand lives in its own
// file and registers itself with KESSLER_BENCH; each prints, last, one JSON object on one line.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/population/population.hpp"

namespace kessler::bench {

using BenchMain = int (*)(int argc, char** argv);

struct Registration {
  Registration(const char* name, const char* summary, BenchMain main);
};

// "--key value" and "--flag" options after the subcommand. Unknown options are an error (exit 2).
class Args {
 public:
  Args(int argc, char** argv);
  bool has(const std::string& key) const;
  std::string get(const std::string& key, const std::string& fallback) const;
  double get_double(const std::string& key, double fallback) const;
  std::int64_t get_int(const std::string& key, std::int64_t fallback) const;
  // Exits with code 2 and a message when an option was given that is not in `known`.
  void allow_only(const std::vector<std::string>& known) const;

 private:
  std::map<std::string, std::string> values_;
};

// Accumulates "key": value pairs and prints them as one JSON line.
class JsonLine {
 public:
  JsonLine& add(const std::string& key, double value);
  JsonLine& add(const std::string& key, std::int64_t value);
  JsonLine& add(const std::string& key, const std::string& value);
  std::string str() const;
  void print() const;

 private:
  std::vector<std::string> fields_;
};

// Median of a sample (copies it).
double median(std::vector<double> values);

// Seconds of a steady clock.
double now_s();

// The leo-19647 population repeated to `objects` objects: ids 1..objects, copy k of an object with its
// position scaled by 1 + 1e-6 k, so that no two objects coincide. `dir` holds the dataset's files.
Population leo19647_repeated(const std::string& dir, std::size_t objects);

// What a 64-byte line costs thread 0 of a 2-thread team [ns per line, medians]: read in random order
// after thread 0 (own) or thread 1 (other) wrote it, and written in sequence with or without thread 1
// having read it first. On a VM the host may place the two cores on a shared cache or far apart, and
// 2-thread figures follow the placement (kessler-bench cores). `team` is the team OpenMP gave.
struct CrossCoreCost {
  double read_own_ns = 0.0, read_other_ns = 0.0, write_private_ns = 0.0, write_shared_ns = 0.0;
  // The same shared write with streaming stores (whole lines, past the cache; 0 without AVX-512).
  double write_shared_streamed_ns = 0.0;
  int team = 0;
  double read_ratio() const { return read_other_ns / read_own_ns; }
  double write_ratio() const { return write_shared_ns / write_private_ns; }
};
CrossCoreCost measure_cross_core(std::size_t lines, int repeats);
// Adds that placement to a multi-threaded benchmark's line, measured after its timing (~50 ms):
// "cross_core_read_ratio" and "cross_core_write_ratio" (other core over own; near ~1-2, far ~5-14).
void add_cross_core(JsonLine& line);

// CPU seconds of the whole process (all threads): unlike wall time, it does not count the time other
// programs on a shared machine take the cores away.
double process_cpu_s();

}  // namespace kessler::bench

#define KESSLER_BENCH_CONCAT_(a, b) a##b
#define KESSLER_BENCH_CONCAT(a, b) KESSLER_BENCH_CONCAT_(a, b)
#define KESSLER_BENCH(name, summary, main_fn)                                                             \
  static ::kessler::bench::Registration KESSLER_BENCH_CONCAT(kessler_bench_reg_, __LINE__)(name, summary, \
                                                                                           main_fn)
