// The broad phase against an all-pairs test of the same swept boxes and straight-line motions: the grid
// (with its exact pruning of neighbour cells a box does not reach into, and its chord filter) must yield
// every pair whose boxes overlap and whose motions come within the threshold during the step, each once,
// and nothing whose boxes are apart (beyond their rounding to floats) or whose motions stay further apart
// than the chord filter's slack, in dense populations, with tiny cells that clamp at the edge of the
// cell range, and for any thread count (1, 2, 3, 4, 7).
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "core/conjunctions/broad_phase_grid.hpp"

namespace kessler {

// The grid's work balancing fed costs of the test's own (the friend hook BroadPhaseGrid grants).
struct GridBalanceProbe {
  // The passes' seconds and objects per thread of a team, as if the grid's last build had measured them.
  static void record_pass_costs(BroadPhaseGrid& grid, const double* seconds, const std::size_t* objects,
                                std::size_t team) {
    grid.pass_balance_.record(seconds, objects, team);
  }
};

namespace {

struct Box {
  double lo[3], hi[3];
};

// The straight-line motion's box: p0 and p0 + dt v0, grown by `grow` (written here, not taken from the
// grid).
Box line_box(const StateArrays& s, std::size_t i, double dt, double grow) {
  const double p[3] = {s.x[i], s.y[i], s.z[i]}, v[3] = {s.vx[i], s.vy[i], s.vz[i]};
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = std::min(p[k], p[k] + dt * v[k]) - grow;
    b.hi[k] = std::max(p[k], p[k] + dt * v[k]) + grow;
  }
  return b;
}

bool overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

// The closest distance of two straight-line motions within [0, dt], by ternary search on the convex
// squared distance (written here, not taken from the detector).
double closest_distance(const StateArrays& s, std::size_t i, std::size_t j, double dt) {
  auto distance2 = [&](double t) {
    const double d[3] = {(s.x[i] + t * s.vx[i]) - (s.x[j] + t * s.vx[j]),
                         (s.y[i] + t * s.vy[i]) - (s.y[j] + t * s.vy[j]),
                         (s.z[i] + t * s.vz[i]) - (s.z[j] + t * s.vz[j])};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  };
  double a = 0.0, b = dt;
  for (int it = 0; it < 200; ++it) {
    const double m1 = a + (b - a) / 3.0, m2 = b - (b - a) / 3.0;
    (distance2(m1) < distance2(m2)) ? b = m2 : a = m1;
  }
  return std::sqrt(distance2(0.5 * (a + b)));
}

// Objects around (centre_x_m, 0, 0) in a cube of `extent_m` (or a box `x_extent_m` long in x), at LEO
// speeds in random directions.
StateArrays dense_population(std::size_t n, double extent_m, unsigned seed, double x_extent_m = 0.0,
                             double centre_x_m = 7.0e6) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  StateArrays s;
  s.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.x[i] = centre_x_m + (x_extent_m > 0.0 ? x_extent_m : extent_m) * u(rng);
    s.y[i] = extent_m * u(rng);
    s.z[i] = extent_m * u(rng);
    s.vx[i] = 15000.0 * u(rng);
    s.vy[i] = 15000.0 * u(rng);
    s.vz[i] = 15000.0 * u(rng);
  }
  return s;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> grid_pairs(BroadPhaseGrid& grid, const StateArrays& s,
                                                             double dt, double share, std::size_t& listed) {
  ThresholdShare shares;
  shares.fixed_m = share;
  grid.build(StepEnds{0.0, dt, &s, &s}, NarrowPhase::kLinear, shares,
             BroadPhaseGrid::cutoff_bound_m(dt, 0.0));
  std::vector<CandidatePair> out;
  grid.collect_pairs(0, grid.slot_count(), out);
  listed = out.size();
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (const CandidatePair& p : out) pairs.insert({std::min(p.i, p.j), std::max(p.i, p.j)});
  return pairs;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> grid_pairs(const StateArrays& s, double dt, double share,
                                                             std::size_t& listed) {
  BroadPhaseGrid grid;
  return grid_pairs(grid, s, dt, share, listed);
}

// A grid that has served other steps before (its cell size carried over) may be passed in.
// expect_drops: whether the population is spread enough for the chord filter to drop most pairs whose
// boxes overlap (not in a cloud a few metres wide, where the float rounding is larger than the cloud).
void expect_grid_matches_all_pairs(const StateArrays& s, double dt, double share,
                                   BroadPhaseGrid* reused = nullptr, bool expect_drops = true) {
  std::size_t listed = 0;
  BroadPhaseGrid fresh;
  const auto found = grid_pairs(reused ? *reused : fresh, s, dt, share, listed);
  EXPECT_EQ(listed, found.size()) << "a pair listed twice";
  // The grid's boxes are rounded outwards to floats, by up to 2^-22 of the coordinate: 2 m here. The
  // chord filter takes box corners for the motion's ends, each up to err = sqrt(3) (share + rounding)
  // off: it keeps pairs whose corner lines come within 2 share + err_a + err_b, whose motions are then
  // within 2 share + 2 (err_a + err_b).
  const double rounding = 2.0;
  const double chord_slack = 4.0 * std::sqrt(3.0) * (share + 2e-3 + rounding) + 1e-2;
  std::size_t close = 0, overlapping_apart = 0;
  for (std::uint32_t i = 0; i < s.size(); ++i) {
    const Box a = line_box(s, i, dt, share), a_wide = line_box(s, i, dt, share + 2e-3 + rounding);
    for (std::uint32_t j = i + 1; j < s.size(); ++j) {
      const bool in_grid = found.count({i, j}) > 0;
      const bool boxes_overlap = overlap(a, line_box(s, j, dt, share));
      const double distance = boxes_overlap || in_grid ? closest_distance(s, i, j, dt) : INFINITY;
      if (boxes_overlap && distance <= 2.0 * share) {
        ++close;
        EXPECT_TRUE(in_grid) << "missed " << i << ", " << j;
      } else if (in_grid) {
        EXPECT_TRUE(overlap(a_wide, line_box(s, j, dt, share + 2e-3 + rounding)))
            << "apart but listed " << i << ", " << j;
        EXPECT_LE(distance, 2.0 * share + chord_slack) << "motions apart but listed " << i << ", " << j;
      } else if (boxes_overlap && distance > 2.0 * share + chord_slack) {
        ++overlapping_apart;
      }
    }
  }
  EXPECT_GT(close, 100u);  // the population is dense enough to exercise neighbour cells
  if (expect_drops) {
    EXPECT_GT(overlapping_apart, 5 * close);  // the chord filter drops most box pairs
  }
}

TEST(BroadPhaseGrid, EveryOverlappingPairOnceInADenseCloud) {
  // 3,000 objects in a 400 km cube, dt 10 s: boxes up to 85 km, cells of that edge, many neighbours.
  expect_grid_matches_all_pairs(dense_population(3000, 4.0e5, 1), 10.0, 5000.0);
}

TEST(BroadPhaseGrid, EveryOverlappingPairOnceWithClampedCells) {
  // dt 1e-4 s: boxes of ~1 m, cells of ~1 m, so 7,000 km lies beyond the cell range and clamps.
  expect_grid_matches_all_pairs(dense_population(1500, 4.0, 2), 1e-4, 0.3, nullptr, false);
}

TEST(BroadPhaseGrid, CellCarriedBetweenStepsWhetherBoxesGrowOrShrink) {
  // The cell edge is guessed from the last step. Steps whose boxes grow past the guess (key again),
  // fit it, and shrink far below it must all give exactly the overlapping pairs.
  const StateArrays slow = dense_population(2000, 2.0e5, 4);
  BroadPhaseGrid grid;
  expect_grid_matches_all_pairs(slow, 2.0, 2000.0, &grid, false);  // first build: no guess
  const double small_cell = grid.cell_size_m();
  expect_grid_matches_all_pairs(slow, 10.0, 2000.0, &grid, false);  // boxes 5x larger than the guess
  EXPECT_GT(grid.cell_size_m(), 4.0 * small_cell);
  EXPECT_EQ(grid.rekeyed_builds(), 2u);
  expect_grid_matches_all_pairs(slow, 10.0, 2000.0, &grid, false);  // the same boxes: the guess fits
  EXPECT_EQ(grid.rekeyed_builds(), 2u);
  expect_grid_matches_all_pairs(slow, 2.0, 2000.0, &grid, false);  // much smaller boxes in a large cell
  expect_grid_matches_all_pairs(slow, 2.0, 2000.0, &grid, false);  // and the cell shrinks back
  EXPECT_NEAR(grid.cell_size_m(), small_cell, 1e-9 * small_cell);
  EXPECT_EQ(grid.builds(), 5u);
}

TEST(BroadPhaseGrid, SparseCloudsGetCoarserCellsWithTheSamePairs) {
  // 3,000 objects in a 1,500 km cube, dt 10 s, a 20 km share: about 1.4 objects per cell of the largest
  // box's edge. Build by build the cell grows until cells hold several objects (a walk with fewer
  // lookups per object), and every build still lists exactly the overlapping pairs, each once.
  const StateArrays sparse = dense_population(3000, 1.5e6, 7);
  BroadPhaseGrid grid;
  expect_grid_matches_all_pairs(sparse, 10.0, 20000.0, &grid, false);
  const double edge_cell = grid.cell_size_m();  // a first build fits the largest box
  for (int build = 0; build < 8; ++build) expect_grid_matches_all_pairs(sparse, 10.0, 20000.0, &grid, false);
  EXPECT_GT(grid.cell_size_m(), 1.4 * edge_cell);
  EXPECT_LT(grid.cell_size_m(), 2.5 * edge_cell);  // ~4-8 objects per occupied cell, no more
}

TEST(BroadPhaseGrid, ManyRegionsKeepNarrowColumnsAndCoarsenOnlyYAndZ) {
  // The sparse cloud above on 16 threads: 16 regions of at least 4 columns over 1,500 km leave columns
  // no wider than the largest box, while y and z still coarsen to several objects per cell. Every
  // build lists exactly the overlapping pairs, each once, and the same pairs as one thread.
  const int saved = omp_get_max_threads();
  const StateArrays sparse = dense_population(3000, 1.5e6, 7);
  std::size_t listed = 0;
  omp_set_num_threads(1);
  const auto one = grid_pairs(sparse, 10.0, 20000.0, listed);
  omp_set_num_threads(16);
  BroadPhaseGrid grid;
  expect_grid_matches_all_pairs(sparse, 10.0, 20000.0, &grid, false);
  const double edge_cell = grid.cell_size_m();  // a first build fits the largest box
  EXPECT_EQ(grid.column_width_m(), edge_cell);
  for (int build = 0; build < 8; ++build) {
    EXPECT_EQ(grid_pairs(grid, sparse, 10.0, 20000.0, listed), one) << "build " << build;
    EXPECT_EQ(listed, one.size()) << "build " << build << ": a pair listed twice";
  }
  expect_grid_matches_all_pairs(sparse, 10.0, 20000.0, &grid, false);
  EXPECT_LT(grid.column_width_m(), 1.06 * edge_cell);  // held at the largest box (within the slack)
  EXPECT_GT(grid.cell_size_m(), 1.8 * edge_cell);      // y and z coarsened
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, CellsInSpatialOrderGiveTheSamePairs) {
  // Clouds around the origin, a few cells across: once a build has measured how far the objects spread,
  // the next lays the cells out in order (x, then y, then z) instead of hashing the rows. The clouds
  // above, 7,000 km out, span too many cells for the table and stay hashed. Every build lists exactly
  // the overlapping pairs, each once, and the same pairs for 1, 2, 4 and 7 threads.
  const int saved = omp_get_max_threads();
  for (const StateArrays& s :
       {dense_population(3000, 4.0e5, 8, 0.0, 0.0), dense_population(4000, 3.0e5, 9, 8.0e5, 0.0)}) {
    omp_set_num_threads(1);
    BroadPhaseGrid grid;
    expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);
    EXPECT_FALSE(grid.cells_in_order());  // the default extent, the Earth's orbits, is too large
    expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);
    EXPECT_TRUE(grid.cells_in_order());
    std::size_t listed = 0;
    const auto one = grid_pairs(grid, s, 10.0, 5000.0, listed);
    for (int threads : {2, 4, 7}) {
      omp_set_num_threads(threads);
      BroadPhaseGrid team_grid;
      grid_pairs(team_grid, s, 10.0, 5000.0, listed);  // the first build measures the extent
      EXPECT_EQ(grid_pairs(team_grid, s, 10.0, 5000.0, listed), one)
          << s.size() << " objects, " << threads << " threads";
      EXPECT_EQ(listed, one.size()) << threads << " threads: a pair listed twice";
      EXPECT_TRUE(team_grid.cells_in_order()) << threads << " threads";
    }
  }
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, SamePairsOnceForAnyThreadCount) {
  // Each thread sorts the partitions of its region of space (slabs of x). In a first build the regions'
  // borders come from that build's own objects; 7 regions over the ~5 cell columns of these clouds
  // leave some regions empty.
  const int saved = omp_get_max_threads();
  for (const StateArrays& s : {dense_population(3000, 4.0e5, 3), dense_population(1200, 3.0e5, 5)}) {
    std::size_t listed = 0;
    omp_set_num_threads(1);
    const auto one = grid_pairs(s, 10.0, 5000.0, listed);
    EXPECT_EQ(listed, one.size());
    EXPECT_GT(one.size(), 100u);
    for (int threads : {2, 3, 4, 7}) {
      omp_set_num_threads(threads);
      EXPECT_EQ(grid_pairs(s, 10.0, 5000.0, listed), one)
          << s.size() << " objects, " << threads << " threads";
      EXPECT_EQ(listed, one.size()) << threads << " threads: a pair listed twice";
    }
  }
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, MoreRegionsThanThreadsGiveTheSamePairs) {
  // GridSettings::regions: 2 and 3 regions of space on one thread (what benchmarks time), 5 on 2 threads.
  // Each region's borders, ghosts and sort then run on threads that also hold other regions.
  const int saved = omp_get_max_threads();
  const StateArrays s = dense_population(3000, 3.0e5, 8, 1.2e6);
  std::size_t listed = 0;
  omp_set_num_threads(1);
  const auto one = grid_pairs(s, 10.0, 5000.0, listed);
  EXPECT_GT(one.size(), 100u);
  for (const auto [threads, regions] : {std::pair{1, 2}, std::pair{1, 3}, std::pair{2, 5}}) {
    omp_set_num_threads(threads);
    BroadPhaseGrid grid(GridSettings{static_cast<std::size_t>(regions)});
    for (int build = 0; build < 2; ++build) {  // borders from this build's histogram, then the last's
      EXPECT_EQ(grid_pairs(grid, s, 10.0, 5000.0, listed), one)
          << threads << " threads, " << regions << " regions, build " << build;
      EXPECT_EQ(listed, one.size()) << threads << " threads, " << regions << " regions: a pair listed twice";
    }
    EXPECT_EQ(grid.regions(), static_cast<std::size_t>(regions));
    expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);  // and against the all-pairs reference
    std::size_t regions_with_slots = 0;
    for (std::size_t r = 0; r < static_cast<std::size_t>(regions); ++r) {
      const auto [first, last] = grid.sorted_slots(r, static_cast<std::size_t>(regions));
      regions_with_slots += last > first ? 1 : 0;
    }
    EXPECT_EQ(regions_with_slots, static_cast<std::size_t>(regions)) << "a region left empty";
  }
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, RegionsBalanceTheThreadsAndKeepEveryPairAcrossTheirBorders) {
  // 4,000 objects in a box 1,600 km long in x (~19 cell columns), on 4 threads: after a first build,
  // the borders come from the last build's histogram. Pairs across the borders (rows of the next
  // column in the next region) must all be found, each once, and each thread must sort about a quarter
  // of the slots.
  const int saved = omp_get_max_threads();
  omp_set_num_threads(4);
  const StateArrays s = dense_population(4000, 3.0e5, 6, 1.6e6);
  BroadPhaseGrid grid;
  expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);  // borders from this build's histogram
  expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);  // borders from the last build's
  EXPECT_GT(1.6e6 / grid.column_width_m(), 12.0);         // several columns per region
  std::size_t covered = 0;
  for (std::size_t t = 0; t < 4; ++t) {
    const auto [first, last] = grid.sorted_slots(t, 4);
    EXPECT_EQ(first, covered) << "thread " << t;
    covered = last;
    const double share = static_cast<double>(last - first) / static_cast<double>(grid.slot_count());
    EXPECT_GT(share, 0.15) << "thread " << t;
    EXPECT_LT(share, 0.35) << "thread " << t;
  }
  EXPECT_EQ(covered, grid.slot_count());
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, RegionsWhoseSlotsCostMoreGetFewerAndTheSamePairs) {
  // The same 4,000 objects on 2 threads, with region 1's slots reported to cost twice region 0's (a
  // slower core, denser cells): after a few scans region 1 holds clearly fewer slots, and every pair
  // is still found once.
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  const StateArrays s = dense_population(4000, 3.0e5, 6, 1.6e6);
  BroadPhaseGrid grid;
  expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);
  auto share_of_region_1 = [&] {
    const auto [first, last] = grid.sorted_slots(1, 2);
    return static_cast<double>(last - first) / static_cast<double>(grid.slot_count());
  };
  EXPECT_NEAR(share_of_region_1(), 0.5, 0.1);
  for (int scan = 0; scan < 40; ++scan) {
    double cost_s[2];
    for (std::size_t r = 0; r < 2; ++r) {
      const auto [first, last] = grid.sorted_slots(r, 2);
      cost_s[r] = (r == 1 ? 2e-8 : 1e-8) * static_cast<double>(last - first);
    }
    grid.record_region_costs(cost_s, 2);
    std::size_t listed = 0;
    grid_pairs(grid, s, 10.0, 5000.0, listed);
  }
  EXPECT_LT(share_of_region_1(), 0.42);  // a third, within a cell column
  EXPECT_GT(share_of_region_1(), 0.2);
  expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);
  // Costs from a team that is not one thread per region say nothing of the regions.
  const double share = share_of_region_1();
  const double skewed[3] = {1.0, 100.0, 1.0};
  for (int scan = 0; scan < 10; ++scan) {
    grid.record_region_costs(skewed, 3);
    std::size_t listed = 0;
    grid_pairs(grid, s, 10.0, 5000.0, listed);
  }
  EXPECT_NEAR(share_of_region_1(), share, 0.05);
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, AThreadSlowerAtThePassesOverObjectsGetsAShorterChunkAndTheSamePairs) {
  // The same 4,000 objects on 2 threads, with thread 1 reported to spend twice as long per object in
  // the passes over its chunk (a busier core): after a few builds its chunk holds about a third of the
  // objects, the chunks still tile the population in order, and every pair is still found once.
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  const StateArrays s = dense_population(4000, 3.0e5, 6, 1.6e6);
  const std::size_t n = s.size();
  BroadPhaseGrid grid;
  expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);
  auto chunks_tile_in_order = [&] {
    const ThreadChunk first = grid.pass_chunk(nullptr, n, 0, 2), second = grid.pass_chunk(nullptr, n, 1, 2);
    EXPECT_EQ(first.begin, 0u);
    EXPECT_EQ(first.end, second.begin);
    EXPECT_EQ(second.end, n);
    EXPECT_EQ(second.begin % kChunkAlign, 0u);
    return static_cast<double>(second.end - second.begin) / static_cast<double>(n);
  };
  EXPECT_NEAR(chunks_tile_in_order(), 0.5, 0.01);  // none recorded: the propagator's (here equal) chunks
  for (int build = 0; build < 40; ++build) {
    double seconds[2];
    std::size_t objects[2];
    for (std::size_t t = 0; t < 2; ++t) {
      const ThreadChunk c = grid.pass_chunk(nullptr, n, t, 2);
      objects[t] = c.end - c.begin;
      seconds[t] = (t == 1 ? 2e-8 : 1e-8) * static_cast<double>(objects[t]);
    }
    GridBalanceProbe::record_pass_costs(grid, seconds, objects, 2);
  }
  EXPECT_NEAR(chunks_tile_in_order(), 1.0 / 3.0, 0.01);
  expect_grid_matches_all_pairs(s, 10.0, 5000.0, &grid);
  // A team of another size starts afresh: its chunks are the propagator's until measured.
  const double seconds[3] = {1.0, 1.0, 1.0};
  const std::size_t objects[3] = {1000, 1000, 2000};
  GridBalanceProbe::record_pass_costs(grid, seconds, objects, 3);
  EXPECT_NEAR(chunks_tile_in_order(), 0.5, 0.01);
  // An empty chunk's report is ignored.
  const std::size_t none[2] = {4000, 0};
  GridBalanceProbe::record_pass_costs(grid, seconds, none, 2);
  EXPECT_NEAR(chunks_tile_in_order(), 0.5, 0.01);
  omp_set_num_threads(saved);
}

TEST(BroadPhaseGrid, FarOutObjectsStayOutOfTheGridAndMeetOnlyWhatTheirBoxesReach) {
  // Real catalogs hold a few objects far out (the paper's, some at ~10^12 m). There rounding to floats
  // widens a box by ~240 km a side: still under the motion bound at dt 30 s, so kept in the grid they
  // would set the cell edge for every other object. Beyond 10^9 m they are oversized instead. Two of
  // them 10 m apart must still meet (each other only, once); one at 9 x 10^8 m stays in the grid; an
  // object too fast for any orbit, in the middle of the cloud, meets every object its box overlaps.
  const double dt = 30.0, share = 5000.0;
  StateArrays s = dense_population(2000, 4.0e5, 8);
  const StateArrays cloud_states = s;
  const std::size_t cloud = s.size();
  auto add = [&](double x, double y, double z, double vx, double vy, double vz) {
    s.resize(s.size() + 1);
    const std::size_t i = s.size() - 1;
    s.x[i] = x, s.y[i] = y, s.z[i] = z, s.vx[i] = vx, s.vy[i] = vy, s.vz[i] = vz;
  };
  add(1.0e12, 2.0e11, 0.0, 0.0, 100.0, 0.0);          // far A
  add(1.0e12 + 10.0, 2.0e11, 0.0, 0.0, -100.0, 0.0);  // far B, beside A
  add(-1.0e12, 0.0, 3.0e11, 50.0, 0.0, 0.0);          // far C, alone
  add(9.0e8, 0.0, 0.0, 0.0, 1000.0, 0.0);             // out at 9 x 10^8 m: in the grid
  add(7.0e6, 0.0, 0.0, 3.0e4, 0.0, 0.0);              // 30 km/s through the cloud: oversized
  const std::uint32_t far_a = static_cast<std::uint32_t>(cloud), fast = far_a + 4;

  const int saved = omp_get_max_threads();
  ThresholdShare shares;
  shares.fixed_m = share;
  std::set<std::pair<std::uint32_t, std::uint32_t>> first;
  BroadPhaseGrid cloud_only;
  omp_set_num_threads(1);
  cloud_only.build(StepEnds{0.0, dt, &cloud_states, &cloud_states}, NarrowPhase::kLinear, shares,
                   BroadPhaseGrid::cutoff_bound_m(dt, share));
  for (int threads : {1, 4}) {
    omp_set_num_threads(threads);
    BroadPhaseGrid grid;
    grid.build(StepEnds{0.0, dt, &s, &s}, NarrowPhase::kLinear, shares,
               BroadPhaseGrid::cutoff_bound_m(dt, share));
    ASSERT_EQ(grid.oversized_count(), 4u) << threads << " threads";
    // The cell fits the cloud's boxes, as without the far objects (theirs would be ~480 km).
    EXPECT_EQ(grid.cell_size_m(), cloud_only.cell_size_m()) << threads << " threads";
    EXPECT_LT(grid.cell_size_m(), 3.0e5);
    std::vector<CandidatePair> out;
    grid.collect_oversized_pairs(0, grid.oversized_count(), out);
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    std::size_t with_fast = 0;
    for (const CandidatePair& p : out) {
      pairs.insert({std::min(p.i, p.j), std::max(p.i, p.j)});
      with_fast += p.i == fast || p.j == fast;
    }
    EXPECT_EQ(pairs.size(), out.size()) << "a pair listed twice";
    EXPECT_EQ(pairs.count({far_a, far_a + 1}), 1u) << "the far pair";
    EXPECT_EQ(out.size(), with_fast + 1) << "a far object met something out of its reach";
    // The fast object meets exactly the cloud's objects whose boxes overlap its own.
    const Box fast_box = line_box(s, fast, dt, share);
    std::size_t expected = 0;
    for (std::uint32_t j = 0; j < cloud; ++j) {
      const bool listed = pairs.count({j, fast}) > 0;
      if (overlap(fast_box, line_box(s, j, dt, share))) {
        ++expected;
        EXPECT_TRUE(listed) << "missed " << j;
      } else if (listed) {
        EXPECT_TRUE(overlap(line_box(s, fast, dt, share + 3.0), line_box(s, j, dt, share + 3.0)))
            << "apart but listed " << j;
      }
    }
    EXPECT_GT(expected, 20u);
    EXPECT_LE(with_fast, expected + 2);
    if (threads == 1)
      first = pairs;
    else
      EXPECT_EQ(pairs, first);
  }
  omp_set_num_threads(saved);
}

}  // namespace
}  // namespace kessler
