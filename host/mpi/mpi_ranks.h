// MPI ranks (Open MPI; built only where CMake finds MPI: CAUSTICA_WITH_MPI)
// for a distributed render (host/app/distributed_render.h).
//
// Rules. MPI starts only in a process that mpirun (or another launcher)
// started, seen by its environment (OMPI_COMM_WORLD_SIZE, PMI_SIZE or
// PMIX_RANK), so `caustica` run by hand never initialises MPI. The film's
// 128-bit sums are reduced with a commutative, associative integer op
// (a 2-word type added with the carry), exact in any order the library
// picks. A rank that fails calls abort(), which ends every rank
// (MPI_Abort): none is left waiting in a collective; a rank that dies
// without a word is ended by mpirun, which aborts the job when a process
// exits with a non-zero status.
#pragma once

#include <memory>

#include "host/app/rank_group.h"

namespace caustica {

class MpiRanks final : public RankGroup {
 public:
  // nullptr unless this process was started by an MPI launcher.
  static std::unique_ptr<MpiRanks> if_launched(int* argc, char*** argv);
  ~MpiRanks() override;  // MPI_Finalize

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int local_rank() const override { return local_rank_; }
  void barrier() override;
  int broadcast(int value) override;
  void sum128_to_root(std::vector<uint64_t>& sums128) override;
  void sum128_to_all(std::vector<uint64_t>& sums128) override;
  void sum_to_root(std::vector<uint64_t>& values) override;
  void sum_to_root(std::vector<uint32_t>& values) override;
  std::vector<std::vector<int32_t>> gather_to_root(const std::vector<int32_t>& values) override;
  std::string gather_bytes_to_all(const std::string& mine) override;
  std::vector<std::string> gather_bytes_to_root(const std::string& mine) override;
  void sum_to_all(std::vector<uint64_t>& values) override;
  std::vector<uint64_t> sum_scatter(const std::vector<uint64_t>& values, const std::vector<size_t>& counts) override;
  std::vector<uint64_t> sum128_scatter(const std::vector<uint64_t>& values, const std::vector<size_t>& counts) override;
  [[noreturn]] void abort(int code) override;
  double collective_seconds() const override { return collective_seconds_; }

 private:
  MpiRanks(int* argc, char*** argv);
  int rank_ = 0, size_ = 1, local_rank_ = 0;
  double collective_seconds_ = 0.0;
};

}  // namespace caustica
