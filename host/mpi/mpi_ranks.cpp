#include "host/mpi/mpi_ranks.h"

#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <limits>

#include "host/error.h"

namespace caustica {
namespace {

// inout[i] += in[i] for 128-bit integers (two uint64 words, low first).
void add_sums128(void* in, void* inout, int* count, MPI_Datatype*) {
  const uint64_t* a = static_cast<const uint64_t*>(in);
  uint64_t* b = static_cast<uint64_t*>(inout);
  for (int i = 0; i < *count; ++i) {
    const uint64_t low = b[2 * i] + a[2 * i];
    b[2 * i + 1] += a[2 * i + 1] + (low < a[2 * i] ? 1u : 0u);
    b[2 * i] = low;
  }
}

// Seconds spent in the data-moving collectives (the barrier is a wait).
class CollectiveTimer {
 public:
  explicit CollectiveTimer(double* total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~CollectiveTimer() { *total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  double* total_;
  std::chrono::steady_clock::time_point t0_;
};

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(rc, text, &length);
  throw Error(std::string("MPI: ") + what + " failed: " + std::string(text, size_t(length)));
}

int count_of(size_t n, const char* what) {
  if (n > size_t(std::numeric_limits<int>::max())) throw Error(std::string("MPI: too many values in ") + what);
  return int(n);
}

}  // namespace

std::unique_ptr<MpiRanks> MpiRanks::if_launched(int* argc, char*** argv) {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") && !std::getenv("PMIX_RANK")) return nullptr;
  return std::unique_ptr<MpiRanks>(new MpiRanks(argc, argv));
}

MpiRanks::MpiRanks(int* argc, char*** argv) {
  check(MPI_Init(argc, argv), "MPI_Init");
  // Errors come back as codes (thrown here, then abort()), not as aborts
  // without a message.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local);
  MPI_Comm_rank(local, &local_rank_);
  MPI_Comm_free(&local);
}

MpiRanks::~MpiRanks() { MPI_Finalize(); }

void MpiRanks::barrier() { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

int MpiRanks::broadcast(int value) {
  const CollectiveTimer timer(&collective_seconds_);
  check(MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
  return value;
}

namespace {
// The film's 128-bit sums added over the ranks, to rank 0 or (to_all) to
// every rank.
void sum128(std::vector<uint64_t>& sums, int rank, bool to_all, double* seconds) {
  const CollectiveTimer timer(seconds);
  MPI_Datatype pair;
  MPI_Type_contiguous(2, MPI_UINT64_T, &pair);
  MPI_Type_commit(&pair);
  MPI_Op add;
  MPI_Op_create(&add_sums128, /*commute=*/1, &add);
  const int n = count_of(sums.size() / 2, "the film's sums");
  const int rc = to_all ? MPI_Allreduce(MPI_IN_PLACE, sums.data(), n, pair, add, MPI_COMM_WORLD)
                 : rank == 0 ? MPI_Reduce(MPI_IN_PLACE, sums.data(), n, pair, add, 0, MPI_COMM_WORLD)
                             : MPI_Reduce(sums.data(), nullptr, n, pair, add, 0, MPI_COMM_WORLD);
  MPI_Op_free(&add);
  MPI_Type_free(&pair);
  check(rc, to_all ? "MPI_Allreduce of the film's 128-bit sums" : "MPI_Reduce of the film's 128-bit sums");
}
}  // namespace

void MpiRanks::sum128_to_root(std::vector<uint64_t>& sums) { sum128(sums, rank_, false, &collective_seconds_); }

void MpiRanks::sum128_to_all(std::vector<uint64_t>& sums) { sum128(sums, rank_, true, &collective_seconds_); }

void MpiRanks::sum_to_root(std::vector<uint64_t>& v) {
  const CollectiveTimer timer(&collective_seconds_);
  const int n = count_of(v.size(), "a sum");
  check(rank_ == 0 ? MPI_Reduce(MPI_IN_PLACE, v.data(), n, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD)
                   : MPI_Reduce(v.data(), nullptr, n, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD),
        "MPI_Reduce");
}

void MpiRanks::sum_to_root(std::vector<uint32_t>& v) {
  const CollectiveTimer timer(&collective_seconds_);
  const int n = count_of(v.size(), "a sum");
  check(rank_ == 0 ? MPI_Reduce(MPI_IN_PLACE, v.data(), n, MPI_UINT32_T, MPI_SUM, 0, MPI_COMM_WORLD)
                   : MPI_Reduce(v.data(), nullptr, n, MPI_UINT32_T, MPI_SUM, 0, MPI_COMM_WORLD),
        "MPI_Reduce");
}

std::vector<std::vector<int32_t>> MpiRanks::gather_to_root(const std::vector<int32_t>& values) {
  const CollectiveTimer timer(&collective_seconds_);
  int mine = count_of(values.size(), "a gather");
  std::vector<int> counts(rank_ == 0 ? size_t(size_) : 0u), offsets;
  check(MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  std::vector<int32_t> all;
  if (rank_ == 0) {
    int total = 0;
    for (int c : counts) {
      offsets.push_back(total);
      total += c;
    }
    all.resize(size_t(total));
  }
  check(MPI_Gatherv(values.data(), mine, MPI_INT32_T, all.data(), counts.data(), offsets.data(), MPI_INT32_T, 0,
                    MPI_COMM_WORLD),
        "MPI_Gatherv");
  std::vector<std::vector<int32_t>> out;
  for (int r = 0; rank_ == 0 && r < size_; ++r)
    out.emplace_back(all.begin() + offsets[size_t(r)], all.begin() + offsets[size_t(r)] + counts[size_t(r)]);
  return out;
}

// Byte counts and offsets of every rank's part (MPI's counts are ints).
namespace {
std::vector<int> offsets_of(const std::vector<int>& counts, const char* what) {
  std::vector<int> offsets;
  size_t total = 0;
  for (int c : counts) {
    offsets.push_back(count_of(total, what));
    total += size_t(c);
  }
  count_of(total, what);
  return offsets;
}
}  // namespace

std::string MpiRanks::gather_bytes_to_all(const std::string& mine) {
  const CollectiveTimer timer(&collective_seconds_);
  int n = count_of(mine.size(), "a gather of bytes");
  std::vector<int> counts(size_t(size_), 0);
  check(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  const std::vector<int> offsets = offsets_of(counts, "a gather of bytes");
  std::string all(size_t(offsets.back()) + size_t(counts.back()), '\0');
  check(MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD),
        "MPI_Allgatherv");
  return all;
}

std::vector<std::string> MpiRanks::gather_bytes_to_root(const std::string& mine) {
  const CollectiveTimer timer(&collective_seconds_);
  int n = count_of(mine.size(), "a gather of bytes");
  std::vector<int> counts(rank_ == 0 ? size_t(size_) : 0u), offsets;
  check(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  std::string all;
  if (rank_ == 0) {
    offsets = offsets_of(counts, "a gather of bytes");
    all.resize(size_t(offsets.back()) + size_t(counts.back()));
  }
  check(MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD),
        "MPI_Gatherv");
  std::vector<std::string> out;
  for (int r = 0; rank_ == 0 && r < size_; ++r) out.push_back(all.substr(size_t(offsets[size_t(r)]), size_t(counts[size_t(r)])));
  return out;
}

void MpiRanks::sum_to_all(std::vector<uint64_t>& v) {
  const CollectiveTimer timer(&collective_seconds_);
  check(MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size(), "a sum"), MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD),
        "MPI_Allreduce");
}

namespace {
// MPI_Reduce_scatter of `values` (segments of counts[r] items, each `words`
// 64-bit words) with `type` and `op`: this rank's segment, summed.
std::vector<uint64_t> reduce_scatter(const std::vector<uint64_t>& values, const std::vector<size_t>& counts, int rank,
                                     int size, int words, MPI_Datatype type, MPI_Op op) {
  if (counts.size() != size_t(size)) throw Error("MPI: a scatter of " + std::to_string(counts.size()) + " segments for " +
                                                 std::to_string(size) + " ranks");
  std::vector<int> receive;
  size_t total = 0;
  for (size_t c : counts) {
    receive.push_back(count_of(c, "a scattered sum"));
    total += c;
  }
  if (total * size_t(words) != values.size())
    throw Error("MPI: a scatter of " + std::to_string(values.size()) + " words in segments of " +
                std::to_string(total) + " items");
  std::vector<uint64_t> mine(counts[size_t(rank)] * size_t(words));
  check(MPI_Reduce_scatter(values.data(), mine.data(), receive.data(), type, op, MPI_COMM_WORLD),
        "MPI_Reduce_scatter");
  return mine;
}
}  // namespace

std::vector<uint64_t> MpiRanks::sum_scatter(const std::vector<uint64_t>& values, const std::vector<size_t>& counts) {
  const CollectiveTimer timer(&collective_seconds_);
  return reduce_scatter(values, counts, rank_, size_, 1, MPI_UINT64_T, MPI_SUM);
}

std::vector<uint64_t> MpiRanks::sum128_scatter(const std::vector<uint64_t>& values, const std::vector<size_t>& counts) {
  const CollectiveTimer timer(&collective_seconds_);
  MPI_Datatype pair;
  MPI_Type_contiguous(2, MPI_UINT64_T, &pair);
  MPI_Type_commit(&pair);
  MPI_Op add;
  MPI_Op_create(&add_sums128, /*commute=*/1, &add);
  std::vector<uint64_t> mine;
  try {
    mine = reduce_scatter(values, counts, rank_, size_, 2, pair, add);
  } catch (...) {
    MPI_Op_free(&add);
    MPI_Type_free(&pair);
    throw;
  }
  MPI_Op_free(&add);
  MPI_Type_free(&pair);
  return mine;
}

void MpiRanks::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace caustica
