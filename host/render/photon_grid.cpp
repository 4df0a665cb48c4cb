#include "host/render/photon_grid.h"

#include <algorithm>
#include <cmath>

#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/render/integrator.h"
#include "host/render/kernel_args.h"

namespace caustica {

namespace {

constexpr uint32_t kMinTableSize = 64;
constexpr uint32_t kMaxTableSize = 1u << 22;

size_t blocks_of(size_t count) { return (count + PHOTON_SCAN_BLOCK - 1) / PHOTON_SCAN_BLOCK; }

}  // namespace

// ------------------------------------------------------------------ scan

ExclusiveScan::ExclusiveScan(const cl::Program& program)
    : sum_blocks_(std::make_unique<StageKernel>(program, "sum_scan_blocks")),
      scan_blocks_(std::make_unique<StageKernel>(program, "scan_blocks_exclusive")) {}

ExclusiveScan::~ExclusiveScan() = default;

void ExclusiveScan::run(StageLauncher& launcher, const cl::Buffer& values, size_t count, RenderStats* stats) {
  if (count == 0) return;
  if (count > 0xFFFFFFFFull) throw Error("exclusive scan: more than 2^32 values");
  scan_level(launcher, values, count, 0, stats);
}

// Scans `count` values given the exclusive scan of their block sums, which
// is the same problem PHOTON_SCAN_BLOCK times smaller: recursion down to a
// single block, whose offset is 0.
void ExclusiveScan::scan_level(StageLauncher& launcher, const cl::Buffer& values, size_t count, size_t level,
                               RenderStats* stats) {
  const size_t blocks = blocks_of(count);
  if (block_sums_.size() <= level) block_sums_.resize(level + 1), block_sums_capacity_.resize(level + 1, 0);
  if (block_sums_capacity_[level] < blocks) {
    block_sums_[level] = cl::Buffer(launcher.runtime().context(), CL_MEM_READ_WRITE, blocks * sizeof(cl_uint));
    block_sums_capacity_[level] = blocks;
  }
  const cl::Buffer offsets = block_sums_[level];  // a handle: the recursion may grow block_sums_
  if (blocks == 1) {
    launcher.runtime().fill(offsets, cl_uint(0), 0, sizeof(cl_uint));
  } else {
    KernelArgs(*sum_blocks_)
        .arg("values", values)
        .arg("value_count", cl_uint(count))
        .arg("block_sums", offsets)
        .finish();
    launcher.launch(*sum_blocks_, blocks, stats);
    scan_level(launcher, offsets, blocks, level + 1, stats);
  }
  KernelArgs(*scan_blocks_)
      .arg("values", values)
      .arg("value_count", cl_uint(count))
      .arg("block_offsets", offsets)
      .finish();
  launcher.launch(*scan_blocks_, blocks, stats);
}

// ------------------------------------------------------------------ grid

uint32_t photon_grid_table_size(size_t photon_count) {
  uint32_t size = kMinTableSize;
  while (size < kMaxTableSize && size_t(size) < 2 * photon_count) size *= 2;
  return size;
}

PhotonGrid::PhotonGrid(Runtime& runtime, const cl::Program& program)
    : runtime_(runtime),
      count_(std::make_unique<StageKernel>(program, "count_bucket_photons")),
      scatter_(std::make_unique<StageKernel>(program, "scatter_photon_indices")),
      sort_(std::make_unique<StageKernel>(program, "sort_bucket_photons")),
      copy_(std::make_unique<StageKernel>(program, "copy_sorted_photons")),
      scan_(program) {}

PhotonGrid::~PhotonGrid() = default;

uint32_t PhotonGrid::build(StageLauncher& launcher, const cl::Buffer& photons, const cl::Buffer& photon_counter,
                           size_t capacity, const PhotonGridShape& shape, RenderStats* stats) {
  const uint32_t stored = launcher.read_count(photon_counter, stats);
  build(launcher, photons, std::min<size_t>(stored, capacity), shape, stats);
  return stored;
}

void PhotonGrid::build(StageLauncher& launcher, const cl::Buffer& photons, size_t photon_count,
                       const PhotonGridShape& shape, RenderStats* stats) {
  if (!(shape.cell_size > 0.0f) || !std::isfinite(shape.cell_size))
    throw Error("photon grid: the cell size must be positive and finite");
  const uint32_t table_size = shape.table_size ? shape.table_size : photon_grid_table_size(photon_count);
  if ((table_size & (table_size - 1)) != 0) throw Error("photon grid: the table size must be a power of two");
  if (photon_count > 0x7FFFFFFFull) throw Error("photon grid: more than 2^31 photons");

  params_ = PhotonGridParams{};
  params_.origin = cs_float4{shape.origin[0], shape.origin[1], shape.origin[2], 0.0f};
  params_.cell_size = shape.cell_size;
  params_.inv_cell_size = 1.0f / shape.cell_size;
  params_.table_size = table_size;
  params_.photon_count = cl_uint(photon_count);

  cl::Context& ctx = runtime_.context();
  if (bucket_capacity_ < size_t(table_size) + 1) {
    bucket_capacity_ = size_t(table_size) + 1;
    bucket_start_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, bucket_capacity_ * sizeof(cl_uint));
  }
  if (photon_capacity_ < photon_count || photon_capacity_ == 0) {
    photon_capacity_ = std::max<size_t>(1, photon_count);  // never a zero-sized buffer
    photon_rank_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, photon_capacity_ * sizeof(cl_uint));
    photon_index_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, photon_capacity_ * sizeof(cl_uint));
    photons_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, photon_capacity_ * sizeof(Photon));
  }

  runtime_.fill(bucket_start_, cl_uint(0), 0, (size_t(table_size) + 1) * sizeof(cl_uint));
  KernelArgs(*count_)
      .arg("grid", params_)
      .arg("photons", photons)
      .arg("bucket_start", bucket_start_)
      .arg("photon_rank", photon_rank_)
      .finish();
  launcher.launch(*count_, photon_count, stats);
  scan_.run(launcher, bucket_start_, size_t(table_size) + 1, stats);
  KernelArgs(*scatter_)
      .arg("grid", params_)
      .arg("photons", photons)
      .arg("bucket_start", bucket_start_)
      .arg("photon_rank", photon_rank_)
      .arg("photon_index", photon_index_)
      .finish();
  launcher.launch(*scatter_, photon_count, stats);
  if (photon_count > 1) {
    KernelArgs(*sort_)
        .arg("grid", params_)
        .arg("bucket_start", bucket_start_)
        .arg("photon_index", photon_index_)
        .finish();
    launcher.launch(*sort_, table_size, stats);
  }
  KernelArgs(*copy_)
      .arg("grid", params_)
      .arg("photons", photons)
      .arg("photon_index", photon_index_)
      .arg("grid_photons", photons_)
      .finish();
  launcher.launch(*copy_, photon_count, stats);
}

KernelArgs& PhotonGrid::bind(KernelArgs& args) const {
  if (bucket_capacity_ == 0) throw Error("photon grid: bound before it was built");
  return args.arg("grid", params_).arg("grid_bucket_start", bucket_start_).arg("grid_photons", photons_);
}

}  // namespace caustica
