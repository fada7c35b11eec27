// kessler-bench cores: what a cache line costs when it changes cores, between threads 0 and 1.
// A step rewrites the whole grid, so 2-thread figures depend on this far more than on the work; on a VM
// the host may place the two virtual cores on one shared cache or far apart, and the figure changes
// with the placement (minutes apart on the development machine: 0.9 vs 3.5 ns per line read). Run it
// beside any 2-thread measurement. It also times the grid's pattern on private data on both cores at
// once against one alone (private_streaming_ratio), which tells memory contention from shared lines,
// and the shared write with streaming stores, which skip taking the line back from the other core.
//   --lines N (default 16384: 1 MiB)  --repeats R (default 10; the streaming ratio takes at least 30)
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

#include "tests/bench/bench.hpp"

#ifdef __AVX512F__
#include <immintrin.h>
#endif

namespace kessler::bench {
namespace {

// One 64-byte line.
struct alignas(64) Line {
  std::uint64_t word[8];
};

// Where the reads' sum goes, so they are not optimised away.
volatile std::uint64_t read_sink = 0;

// 0 .. n - 1 in a random order (fixed by seed).
std::vector<std::uint32_t> random_order(std::size_t n, unsigned seed) {
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  return order;
}

}  // namespace

CrossCoreCost measure_cross_core(std::size_t lines, int repeats) {
  std::vector<Line> data(lines);
  const std::vector<std::uint32_t> order = random_order(lines, 12345);

  // Per repeat: the writer fills every line, then thread 0 reads them in random order (independent
  // loads, as a walk over neighbour cells does) or writes them in sequence after thread 1 has read
  // them (as the next step's sort does), with plain or with streaming stores.
  enum Case { kReadOwn, kReadOther, kWritePrivate, kWriteShared, kWriteSharedStreamed, kCases };
  std::vector<double> seconds[kCases];
  std::uint64_t sink = 0;
  int team = 0;
  for (int rep = 0; rep < repeats; ++rep) {
    for (int c = 0; c < kCases; ++c) {
      double elapsed = 0.0;
#pragma omp parallel num_threads(2) reduction(+ : sink)
      {
        const int t = omp_get_thread_num();
#pragma omp single
        team = omp_get_num_threads();
        const int writer = c == kReadOther ? 1 : 0;
        if (t == writer)
          for (std::size_t i = 0; i < lines; ++i) data[i].word[0] = i + static_cast<std::size_t>(rep);
#pragma omp barrier
        if ((c == kWriteShared || c == kWriteSharedStreamed) && t == 1)
          for (std::size_t i = 0; i < lines; ++i) sink += data[i].word[0];
#pragma omp barrier
        if (t == 0) {
          const double t0 = omp_get_wtime();
          if (c == kReadOwn || c == kReadOther) {
            std::uint64_t sum = 0;
            for (std::size_t i = 0; i < lines; ++i) sum += data[order[i]].word[0];
            sink += sum;
          } else if (c == kWriteSharedStreamed) {
#ifdef __AVX512F__
            for (std::size_t i = 0; i < lines; ++i)
              _mm512_stream_si512(reinterpret_cast<__m512i*>(&data[i]),
                                  _mm512_set_epi64(0, 0, 0, 0, 0, 0, 0, static_cast<long long>(i)));
            _mm_sfence();
#endif
          } else {
            for (std::size_t i = 0; i < lines; ++i) data[i].word[0] = i;
          }
          elapsed = omp_get_wtime() - t0;
        }
      }
      seconds[c].push_back(elapsed);
    }
  }
  CrossCoreCost cost;
  cost.team = team;
  auto ns_per_line = [&](int c) { return 1e9 * median(seconds[c]) / static_cast<double>(lines); };
  cost.read_own_ns = ns_per_line(kReadOwn);
  cost.read_other_ns = ns_per_line(kReadOther);
  cost.write_private_ns = ns_per_line(kWritePrivate);
  cost.write_shared_ns = ns_per_line(kWriteShared);
#ifdef __AVX512F__
  cost.write_shared_streamed_ns = ns_per_line(kWriteSharedStreamed);
#endif
  read_sink = sink;
  return cost;
}

// Both cores at once on private data, with the grid's pattern: 48-byte records copied in sequence, then
// stored field by field into slot arrays in random order, a barrier after each round. Seconds a round
// with both threads at work over thread 0 alone: near 1 when the cores do not slow each other down by
// streaming memory at the same moments (so any 2-thread excess beyond it comes from shared lines).
double private_streaming_ratio(std::size_t records, int rounds, int repeats) {
  struct Record {
    float box[6];
    std::uint64_t key;
    std::uint32_t index, chord, crosses, slot;
  };
  static_assert(sizeof(Record) == 48);
  std::vector<double> seconds[2];
  for (int rep = 0; rep < repeats; ++rep) {
    for (int both = 0; both < 2; ++both) {
      double elapsed = 0.0;
#pragma omp parallel num_threads(2)
      {
        const int t = omp_get_thread_num();
        const bool works = t == 0 || both == 1;
        std::vector<Record> from(records), to(records);
        std::vector<float> slot_box[6];
        for (std::vector<float>& axis : slot_box) axis.resize(records);
        std::vector<std::uint64_t> slot_key(records);
        const std::vector<std::uint32_t> order = random_order(records, static_cast<unsigned>(t + 1));
        for (std::size_t i = 0; i < records; ++i) from[i].slot = order[i];
#pragma omp barrier
        const double t0 = omp_get_wtime();
        for (int round = 0; round < rounds; ++round) {
          if (works) {
            for (std::size_t i = 0; i < records; ++i) {
              Record r = from[i];
              r.key += static_cast<std::uint64_t>(round);
              to[i] = r;
            }
            for (const Record& r : to) {
              for (int a = 0; a < 6; ++a) slot_box[a][r.slot] = r.box[a];
              slot_key[r.slot] = r.key;
            }
          }
#pragma omp barrier
        }
        if (t == 0) elapsed = omp_get_wtime() - t0;
        read_sink = slot_key[records / 2];
      }
      seconds[both].push_back(elapsed);
    }
  }
  return median(seconds[1]) / median(seconds[0]);
}

void add_cross_core(JsonLine& line) {
  const CrossCoreCost cost = measure_cross_core(16384, 5);
  if (cost.team < 2) return;
  line.add("cross_core_read_ratio", cost.read_ratio()).add("cross_core_write_ratio", cost.write_ratio());
}

namespace {

int bench_cores(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--lines", "--repeats"});
  const auto lines = static_cast<std::size_t>(args.get_int("--lines", 16384));
  const int repeats = static_cast<int>(args.get_int("--repeats", 10));
  if (lines < 64 || repeats < 1) {
    std::fprintf(stderr, "kessler-bench cores: --lines must be >= 64 and --repeats >= 1\n");
    return 2;
  }
  const CrossCoreCost cost = measure_cross_core(lines, repeats);
  if (cost.team < 2) {
    std::fprintf(stderr, "kessler-bench cores: needs 2 threads, OpenMP gave %d\n", cost.team);
    return 1;
  }
  // 10,000 records a thread: one thread's share of leo-19647's grid on 2 threads (~1.2 MB).
  // Single ratios swing by +-15 % on a shared host: the median takes at least 30 repeats.
  const double streaming = private_streaming_ratio(10000, 200, std::max(repeats, 30));
  std::printf(
      "cores: %zu lines, medians of %d: random read %.2f ns/line (own) vs %.2f (written by the other "
      "core): %.1fx; sequential write %.2f (private) vs %.2f (read by the other core): %.1fx; private "
      "streaming, both cores at once over one alone: %.2fx; the shared write with streaming stores "
      "%.2f\n",
      lines, repeats, cost.read_own_ns, cost.read_other_ns, cost.read_ratio(), cost.write_private_ns,
      cost.write_shared_ns, cost.write_ratio(), streaming, cost.write_shared_streamed_ns);
  JsonLine()
      .add("benchmark", std::string("cores"))
      .add("lines", static_cast<std::int64_t>(lines))
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("read_own_ns_per_line", cost.read_own_ns)
      .add("read_other_ns_per_line", cost.read_other_ns)
      .add("read_other_ratio", cost.read_ratio())
      .add("write_private_ns_per_line", cost.write_private_ns)
      .add("write_shared_ns_per_line", cost.write_shared_ns)
      .add("write_shared_ratio", cost.write_ratio())
      .add("private_streaming_together_ratio", streaming)
      .add("write_shared_streamed_ns_per_line", cost.write_shared_streamed_ns)
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("cores", "cost of a cache line that changes cores (2 threads): read to judge 2-thread figures",
              bench_cores);

}  // namespace kessler::bench
