// The photon hash grid (issue 13): the exclusive scan against a host scan,
// the built grid's structure, the neighbour query against a brute force over
// every photon (random photons, photons on cell borders and corners, radii
// below, at and above the cell size, tables so small that every cell
// collides, no photons, all photons at one point), and the same bits for
// any work-group size or thread count. The grid is built by the device
// stages (kernels/photon_grid.cl); the query is the kernels' own iterator
// (photon_query_begin / photon_query_next of lib/photon_grid.h) run on the
// host over the grid read back, as it rounds alike there (fmas written out,
// -ffp-contract=off).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "host/render/device_scene.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"
#include "host/render/photon_grid.h"
#include "kernels/shared/photon.h"
#include "lib/photon_grid.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

// The kernels' own cell and bucket of a position (kernels/lib/photon_grid.h
// on the host), to recompute buckets; hash_u32 (lib/rng.h) for checksums.
uint32_t host_bucket(const PhotonGridParams& g, const cs_packed3& p) {
  return photon_grid_bucket(g, photon_grid_cell(g, unpack3(p)));
}

struct QueryResult {
  uint32_t found = 0, sum_a = 0, sum_b = 0, sequence = 0;
};

// The brute force: every photon, by the kernels' photon_distance2.
std::vector<QueryResult> brute_force(const std::vector<Photon>& photons, const std::vector<cs_float4>& queries) {
  std::vector<QueryResult> out(queries.size());
  for (size_t q = 0; q < queries.size(); ++q) {
    const cs_float4& c = queries[q];
    const float radius2 = c.w * c.w;
    for (size_t i = 0; i < photons.size(); ++i) {
      if (photon_distance2(unpack3(photons[i].position), c.xyz) > radius2) continue;
      ++out[q].found;
      out[q].sum_a += hash_u32(uint32_t(i));
      out[q].sum_b += hash_u32(uint32_t(i) ^ 0x5bd1e995u);
    }
  }
  return out;
}

struct GridRig {
  Runtime& rt;
  BuiltProgram built;
  PhotonGrid grid;

  explicit GridRig(Runtime& runtime = test::runtime())
      : rt(runtime), built(rt.build_file("photon_grid.cl", "")), grid(rt, built.program) {}

  void build(const std::vector<Photon>& photons, const PhotonGridShape& shape, size_t local = 64,
             RenderStats* stats = nullptr) {
    StageLauncher launcher(rt, local);
    const cl::Buffer buffer = upload_buffer(rt.context(), photons);
    grid.build(launcher, buffer, photons.size(), shape, stats);
    launcher.collect(stats);
    rt.queue().finish();
  }

  // Per query point (xyz, radius in w) the photons found, two lanes of an
  // order-independent checksum of their indices, and an order-dependent
  // hash of the sequence (bucket order): the kernels' query iterator on the
  // host, over the built grid read back.
  std::vector<QueryResult> run_queries(const std::vector<cs_float4>& queries) {
    const PhotonGridParams& g = grid.params();
    const std::vector<uint32_t> start = read<uint32_t>(grid.bucket_start(), size_t(g.table_size) + 1);
    const std::vector<uint32_t> index = read<uint32_t>(grid.photon_index(), g.photon_count);
    const std::vector<Photon> photons = read<Photon>(grid.photons(), g.photon_count);
    std::vector<QueryResult> out(queries.size());
    for (size_t q = 0; q < queries.size(); ++q) {
      PhotonQuery query = photon_query_begin(g, start.data(), photons.data(), queries[q].xyz, queries[q].w);
      QueryResult& r = out[q];
      for (int slot; (slot = photon_query_next(&query, g, start.data(), photons.data())) >= 0;) {
        const uint32_t i = index[size_t(slot)];
        ++r.found;
        r.sum_a += hash_u32(i);
        r.sum_b += hash_u32(i ^ 0x5bd1e995u);
        r.sequence = hash_u32(r.sequence ^ i);
      }
    }
    return out;
  }

  template <typename T>
  std::vector<T> read(const cl::Buffer& buffer, size_t count) {
    std::vector<T> out(count);
    if (count) rt.queue().enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(T), out.data());
    return out;
  }
};

Photon photon_at(float x, float y, float z) {
  Photon p{};
  p.position = cs_packed3{x, y, z};
  p.wi = cs_packed3{0.0f, 0.0f, 1.0f};
  p.power = cs_float4{1.0f, 1.0f, 1.0f, 0.0f};
  return p;
}

// The built grid is a bucket sort of the photons by index within buckets.
void expect_grid_structure(GridRig& rig, const std::vector<Photon>& photons) {
  const PhotonGridParams& g = rig.grid.params();
  ASSERT_EQ(g.photon_count, photons.size());
  const auto start = rig.read<uint32_t>(rig.grid.bucket_start(), size_t(g.table_size) + 1);
  const auto index = rig.read<uint32_t>(rig.grid.photon_index(), photons.size());
  const auto sorted = rig.read<Photon>(rig.grid.photons(), photons.size());
  ASSERT_EQ(start.front(), 0u);
  ASSERT_EQ(start.back(), photons.size());
  std::vector<bool> seen(photons.size(), false);
  for (uint32_t b = 0; b < g.table_size; ++b) {
    ASSERT_LE(start[b], start[b + 1]) << "bucket " << b;
    for (uint32_t s = start[b]; s < start[b + 1]; ++s) {
      ASSERT_LT(index[s], photons.size());
      ASSERT_FALSE(seen[index[s]]) << "photon " << index[s] << " twice";
      seen[index[s]] = true;
      if (s > start[b]) ASSERT_LT(index[s - 1], index[s]) << "bucket " << b << " not in index order";
      ASSERT_EQ(host_bucket(g, photons[index[s]].position), b) << "photon " << index[s];
      ASSERT_EQ(0, std::memcmp(&sorted[s], &photons[index[s]], sizeof(Photon))) << "slot " << s;
    }
  }
}

void expect_queries_match(GridRig& rig, const std::vector<Photon>& photons, const std::vector<cs_float4>& queries,
                          const char* what) {
  const std::vector<QueryResult> want = brute_force(photons, queries);
  const std::vector<QueryResult> got = rig.run_queries(queries);
  size_t failures = 0;
  for (size_t q = 0; q < queries.size() && failures < 10; ++q) {
    const bool same = got[q].found == want[q].found && got[q].sum_a == want[q].sum_a && got[q].sum_b == want[q].sum_b;
    if (!same) ++failures;
    EXPECT_TRUE(same) << what << ": query " << q << " at (" << queries[q].x << ", " << queries[q].y << ", "
                      << queries[q].z << ") radius " << queries[q].w << ": found " << got[q].found << ", want "
                      << want[q].found;
  }
}

std::vector<Photon> random_photons(size_t n, float lo, float hi, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<Photon> photons;
  for (size_t i = 0; i < n; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng);
    photons.push_back(photon_at(x, y, z));
  }
  return photons;
}

std::vector<cs_float4> random_queries(size_t n, float lo, float hi, const std::vector<float>& radii, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<cs_float4> queries;
  for (size_t i = 0; i < n; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng);
    queries.push_back(cs_float4{x, y, z, radii[i % radii.size()]});
  }
  return queries;
}

PhotonGridShape shape(float origin, float cell_size, uint32_t table_size = 0) {
  PhotonGridShape s;
  s.origin = {origin, origin, origin};
  s.cell_size = cell_size;
  s.table_size = table_size;
  return s;
}

// ------------------------------------------------------------------ scan

TEST(ExclusiveScan, MatchesAHostScanForAnyLengthAndWorkGroupSize) {
  Runtime& rt = test::runtime();
  const BuiltProgram built = rt.build_file("photon_grid.cl", "");
  ExclusiveScan scan(built.program);
  std::mt19937 rng(3);
  // On Oclgrind without 2^20 + 3: 65537 already needs three levels at
  // work-group size 256.
  std::vector<size_t> counts = {1, 7, 256, 257, 1000, 65537};
  if (!test::on_simulator()) counts.push_back((size_t(1) << 20) + 3);
  for (size_t count : counts) {
    std::vector<uint32_t> values(count);
    for (uint32_t& v : values) v = rng() % 1000;
    values[0] = 0xFFFFFFF0u;  // sums wrap modulo 2^32 on both sides
    std::vector<uint32_t> want(count);
    uint32_t running = 0;
    for (size_t i = 0; i < count; ++i) want[i] = running, running += values[i];
    for (size_t local : {1, 3, 64, 256}) {
      cl::Buffer buffer(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, count * sizeof(cl_uint),
                        values.data());
      StageLauncher launcher(rt, local);
      scan.run(launcher, buffer, count);
      std::vector<uint32_t> got(count);
      rt.queue().enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(cl_uint), got.data());
      EXPECT_EQ(got, want) << count << " values, local size " << local;
    }
  }
}

// ------------------------------------------------------------------ grid and query

TEST(PhotonGrid, TableSizeIsAPowerOfTwoAtLeastTwicePhotonsWithinBounds) {
  EXPECT_EQ(photon_grid_table_size(0), 64u);
  EXPECT_EQ(photon_grid_table_size(32), 64u);
  EXPECT_EQ(photon_grid_table_size(33), 128u);
  EXPECT_EQ(photon_grid_table_size(1000000), 1u << 21);
  EXPECT_EQ(photon_grid_table_size(100000000), 1u << 22);
}

TEST(PhotonGrid, RandomPhotonsInABox) {
  GridRig rig;
  // A tenth of the photons and queries on Oclgrind: the checks are exact.
  const std::vector<Photon> photons = random_photons(test::sized(20000, 2000), -1.0f, 3.0f, 1);
  rig.build(photons, shape(-1.0f, 0.25f));
  expect_grid_structure(rig, photons);
  // Radii below, at and well above the cell size; points also outside the box.
  const std::vector<cs_float4> queries =
      random_queries(test::sized(3000, 300), -1.5f, 3.5f, {0.0f, 0.05f, 0.17f, 0.25f, 0.4f, 0.9f}, 2);
  expect_queries_match(rig, photons, queries, "random");
}

TEST(PhotonGrid, PhotonsOnCellBordersAndCorners) {
  // Every photon at a multiple of half a cell from the origin: on cell
  // corners, edges and faces, and at cell centres; queries on the same
  // lattice with radii that reach other photons exactly (the test is <=).
  GridRig rig;
  const float origin = -2.0f, cell = 0.5f;
  std::vector<Photon> photons;
  for (int i = 0; i <= 12; ++i)
    for (int j = 0; j <= 12; ++j)
      for (int k = 0; k <= 12; ++k)
        photons.push_back(photon_at(origin + 0.25f * i, origin + 0.25f * j, origin + 0.25f * k));
  rig.build(photons, shape(origin, cell));
  expect_grid_structure(rig, photons);
  std::vector<cs_float4> queries;
  for (int i = -1; i <= 13; i += 2)
    for (int j = 0; j <= 12; j += 3)
      for (int k = 0; k <= 12; k += 4)
        for (float radius : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f, 1.5f, 2.0f})
          queries.push_back(cs_float4{origin + 0.25f * i, origin + 0.25f * j, origin + 0.25f * k, radius});
  expect_queries_match(rig, photons, queries, "lattice");
  // A query at a lattice point with radius 0 finds exactly the photon there.
  const std::vector<QueryResult> got = rig.run_queries({cs_float4{origin + 1.0f, origin, origin + 0.5f, 0.0f}});
  EXPECT_EQ(got[0].found, 1u);
}

TEST(PhotonGrid, TinyTablesWhereEveryCellCollidesCountEachPhotonOnce) {
  // With one to four buckets the cells of one query share buckets; without
  // the own-cell check a photon would be counted once per visited cell
  // hashing to its bucket.
  // A query visits up to 11^3 cells, each a scan of one shared bucket: 100
  // photons and 8 queries (two of each radius) on Oclgrind, where 300 and
  // 50 ran past 120 s while the query was a kernel (the checks are exact,
  // so 1500 photons and 128 queries, 32 of each radius, check what 3000
  // and 500 did in a tenth of the time: every cell of every query collides
  // either way).
  const std::vector<Photon> photons = random_photons(test::sized(1500, 100), 0.0f, 2.0f, 4);
  const std::vector<cs_float4> queries =
      random_queries(test::sized(128, 8), 0.0f, 2.0f, {0.1f, 0.3f, 0.6f, 1.1f}, 5);
  for (uint32_t table : {1u, 2u, 4u}) {
    GridRig rig;
    rig.build(photons, shape(0.0f, 0.2f, table));
    expect_grid_structure(rig, photons);
    expect_queries_match(rig, photons, queries, ("table size " + std::to_string(table)).c_str());
  }
}

TEST(PhotonGrid, NoPhotons) {
  GridRig rig;
  rig.build({}, shape(0.0f, 0.5f));
  EXPECT_EQ(rig.grid.params().photon_count, 0u);
  const std::vector<QueryResult> got =
      rig.run_queries({cs_float4{0.0f, 0.0f, 0.0f, 0.0f}, cs_float4{1.0f, 1.0f, 1.0f, 3.0f}});
  EXPECT_EQ(got[0].found, 0u);
  EXPECT_EQ(got[1].found, 0u);
}

TEST(PhotonGrid, AllPhotonsAtOnePoint) {
  // One bucket holds every photon: the sort's heap path, and a query that
  // finds all of them, or none.
  GridRig rig;
  const std::vector<Photon> photons(5000, photon_at(0.3f, 0.7f, 0.1f));
  rig.build(photons, shape(0.0f, 0.25f));
  expect_grid_structure(rig, photons);
  expect_queries_match(rig, photons,
                       {cs_float4{0.3f, 0.7f, 0.1f, 0.0f}, cs_float4{0.3f, 0.7f, 0.3f, 0.2f},
                        cs_float4{0.3f, 0.7f, 0.3f, 0.19f}, cs_float4{1.0f, 1.0f, 1.0f, 2.0f},
                        cs_float4{1.0f, 1.0f, 1.0f, 0.5f}},
                       "one point");
  EXPECT_EQ(rig.run_queries({cs_float4{0.3f, 0.7f, 0.1f, 0.0f}})[0].found, 5000u);
}

TEST(PhotonGrid, RebuildsWithFewerAndMorePhotonsAndFromADeviceCounter) {
  GridRig rig;
  const std::vector<Photon> many = random_photons(4000, 0.0f, 1.0f, 6);
  const std::vector<cs_float4> queries = random_queries(test::sized(300, 60), 0.0f, 1.0f, {0.05f, 0.12f}, 7);
  for (size_t n : {size_t(1000), size_t(300), size_t(4000)}) {
    const std::vector<Photon> photons(many.begin(), many.begin() + n);
    rig.build(photons, shape(0.0f, 0.1f));
    expect_grid_structure(rig, photons);
    expect_queries_match(rig, photons, queries, ("rebuild " + std::to_string(n)).c_str());
  }
  // A counter that ran past the buffer's capacity: one read, capacity photons.
  const cl::Buffer buffer = upload_buffer(rig.rt.context(), many);
  const std::vector<uint32_t> stored = {5000};
  const cl::Buffer counter = upload_buffer(rig.rt.context(), stored);
  RenderStats stats;
  StageLauncher launcher(rig.rt, 64);
  EXPECT_EQ(rig.grid.build(launcher, buffer, counter, many.size(), shape(0.0f, 0.1f), &stats), 5000u);
  EXPECT_EQ(stats.blocking_transfers, 1u);
  expect_grid_structure(rig, many);
  expect_queries_match(rig, many, queries, "from counter");
}

TEST(PhotonGrid, SortPutsEveryBucketInIndexOrder) {
  // sort_bucket_photons alone, on buckets of 0 to 3000 indices in scrambled
  // order (the build's atomics scramble them only when threads race):
  // insertion sort up to 16, heap sort above.
  Runtime& rt = test::runtime();
  const BuiltProgram built = rt.build_file("photon_grid.cl", "");
  StageKernel sort(built.program, "sort_bucket_photons");
  std::mt19937 rng(12);
  const std::vector<uint32_t> sizes = {0, 1, 2, 3, 15, 16, 17, 18, 100, 1000, 3000, 0, 5};
  std::vector<uint32_t> start = {0}, index;
  for (uint32_t n : sizes) {
    std::vector<uint32_t> bucket(n);
    for (uint32_t& v : bucket) v = rng();
    index.insert(index.end(), bucket.begin(), bucket.end());
    start.push_back(uint32_t(index.size()));
  }
  while (start.size() < 17) start.push_back(start.back());  // table_size 16
  PhotonGridParams grid{};
  grid.table_size = 16;
  grid.photon_count = cl_uint(index.size());
  const cl::Buffer starts = upload_buffer(rt.context(), start);
  cl::Buffer indices(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, index.size() * sizeof(cl_uint),
                     index.data());
  KernelArgs(sort).arg("grid", grid).arg("bucket_start", starts).arg("photon_index", indices).finish();
  StageLauncher(rt, 4).launch(sort, 16, nullptr);
  std::vector<uint32_t> got(index.size());
  rt.queue().enqueueReadBuffer(indices, CL_TRUE, 0, got.size() * sizeof(cl_uint), got.data());
  for (size_t b = 0; b < 16; ++b) std::sort(index.begin() + start[b], index.begin() + start[b + 1]);
  EXPECT_EQ(got, index);
}

// ------------------------------------------------------------------ determinism

// Clustered photons, so that buckets hold many and the atomics' arrival
// order has something to scramble; enough of them that PoCL's threads run
// at the same time (with a few thousand, one thread often takes every
// work-group in order, and a build without the sort would pass by luck).
// Oclgrind runs one work-item at a time: 4000 there, for its memory checks
// (20000 ran past 120 s over the four work-group sizes).
std::vector<Photon> clustered_photons() {
  std::vector<Photon> photons = random_photons(test::sized(400000, 4000), 0.0f, 1.0f, 8);
  std::mt19937 rng(9);
  std::normal_distribution<float> n(0.5f, 0.01f);
  for (size_t i = 0; i < photons.size(); i += 2) photons[i] = photon_at(n(rng), n(rng), n(rng));
  return photons;
}

struct GridBits {
  std::vector<uint32_t> start, index;
  std::vector<Photon> photons;
  std::vector<QueryResult> queries;
};

GridBits grid_bits(size_t local) {
  GridRig rig;
  const std::vector<Photon> photons = clustered_photons();
  rig.build(photons, shape(0.0f, 0.05f, 1u << 16), local);
  GridBits bits;
  bits.start = rig.read<uint32_t>(rig.grid.bucket_start(), (1u << 16) + 1);
  bits.index = rig.read<uint32_t>(rig.grid.photon_index(), photons.size());
  bits.photons = rig.read<Photon>(rig.grid.photons(), photons.size());
  // 512 queries into the cluster: the order of what each finds is compared
  // bit for bit (as 2000 did, in a quarter of the time).
  bits.queries = rig.run_queries(random_queries(test::sized(512, 100), 0.4f, 0.6f, {0.02f, 0.05f, 0.1f}, 10));
  return bits;
}

void expect_same_bits(const GridBits& a, const GridBits& b, const std::string& what) {
  EXPECT_EQ(a.start, b.start) << what;
  EXPECT_EQ(a.index, b.index) << what;
  ASSERT_EQ(a.photons.size(), b.photons.size());
  EXPECT_EQ(0, std::memcmp(a.photons.data(), b.photons.data(), a.photons.size() * sizeof(Photon))) << what;
  ASSERT_EQ(a.queries.size(), b.queries.size());
  EXPECT_EQ(0, std::memcmp(a.queries.data(), b.queries.data(), a.queries.size() * sizeof(QueryResult)))
      << what << ": query order differs";
}

TEST(PhotonGrid, SameBitsForAnyWorkGroupSize) {
  const GridBits first = grid_bits(1);
  for (size_t local : {7, 64, 256}) expect_same_bits(first, grid_bits(local), "local size " + std::to_string(local));
}

// The same test runs itself in child processes with one and two PoCL
// threads (PoCL reads POCL_MAX_PTHREAD_COUNT when it starts); a child, told
// by $CAUSTICA_PHOTON_GRID_DUMP, writes the grid's bits there.
TEST(PhotonGrid, SameBitsForAnyThreadCount) {
  if (const char* path = std::getenv("CAUSTICA_PHOTON_GRID_DUMP")) {
    const GridBits bits = grid_bits(64);
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bits.start.data()), bits.start.size() * sizeof(uint32_t));
    out.write(reinterpret_cast<const char*>(bits.index.data()), bits.index.size() * sizeof(uint32_t));
    out.write(reinterpret_cast<const char*>(bits.photons.data()), bits.photons.size() * sizeof(Photon));
    out.write(reinterpret_cast<const char*>(bits.queries.data()), bits.queries.size() * sizeof(QueryResult));
    return;
  }
  const std::string dir = test::temp_dir();
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::string dumps[2];
  for (int k = 0; k < 2; ++k) {
    const std::string path = dir + "/grid" + std::to_string(k) + ".bin";
    const std::string cmd = "POCL_MAX_PTHREAD_COUNT=" + std::to_string(k + 1) + " CAUSTICA_PHOTON_GRID_DUMP=" + path +
                            " " + self + " --gtest_filter=PhotonGrid.SameBitsForAnyThreadCount > " + dir + "/log" +
                            std::to_string(k) + ".txt 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream f(path, std::ios::binary);
    dumps[k].assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  ASSERT_FALSE(dumps[0].empty());
  EXPECT_TRUE(dumps[0] == dumps[1]) << "grid bits differ between 1 and 2 PoCL threads";
}

// ------------------------------------------------------------------ scale

// A million random photons: the structure holds, and the time of each stage
// (on a profiling runtime) is printed, to see that no stage stands out.
TEST(PhotonGrid, MillionPhotonsBuildTime) {
  Runtime profiling(select_device(test::device_spec()), true);
  GridRig rig(profiling);
  // 20000 on Oclgrind, whose times mean nothing: the structure is checked.
  const std::vector<Photon> photons = random_photons(test::sized(1000000, 20000), 0.0f, 10.0f, 11);
  const cl::Buffer buffer = upload_buffer(profiling.context(), photons);
  StageLauncher launcher(profiling, 64);
  rig.grid.build(launcher, buffer, photons.size(), shape(0.0f, 0.05f));  // warm: allocation, first launches
  launcher.collect(nullptr);
  RenderStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  rig.grid.build(launcher, buffer, photons.size(), shape(0.0f, 0.05f), &stats);
  profiling.queue().finish();
  const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  launcher.collect(&stats);
  double device_ms = 0.0;
  std::string stages;
  for (const auto& [name, ms] : stats.stage_ms) {
    device_ms += ms;
    char line[96];
    std::snprintf(line, sizeof line, " %s %.2f", name.c_str(), ms);
    stages += line;
  }
  std::printf("[measure] photon grid, 1M photons, %u buckets: %.1f ms wall, %.1f ms in kernels:%s\n",
              rig.grid.params().table_size, wall_ms, device_ms, stages.c_str());
  expect_grid_structure(rig, photons);
}

}  // namespace
}  // namespace caustica
