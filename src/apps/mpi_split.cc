#include "apps/mpi_split.h"

#include <mpi.h>

#include <cstddef>
#include <cstdlib>
#include <stdexcept>

namespace partslam::apps {
namespace {

bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

bool started = false;

class MpiSplit : public WorkSplit {
 public:
  MpiSplit() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  // The records travel as an MPI type of record_size bytes, so counts and offsets are in records.
  std::vector<std::byte> all_gather_bytes(std::span<const std::byte> mine, std::size_t record_size) const override {
    const int count = static_cast<int>(mine.size() / record_size);
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_), 0);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    long total = 0;
    for (int r = 0; r < size_; ++r) {
      offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
      total += counts[static_cast<std::size_t>(r)];
    }
    if (total > 1'000'000'000L) throw std::runtime_error("mpi: more than 1e9 records to gather");
    std::vector<std::byte> all(static_cast<std::size_t>(total) * record_size);
    MPI_Datatype record;
    MPI_Type_contiguous(static_cast<int>(record_size), MPI_BYTE, &record);
    MPI_Type_commit(&record);
    MPI_Allgatherv(mine.data(), count, record, all.data(), counts.data(), offsets.data(), record, MPI_COMM_WORLD);
    MPI_Type_free(&record);
    return all;
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  if (!launched_by_mpirun()) return;
  MPI_Init(argc, argv);
  started = true;
}

MpiSession::~MpiSession() {
  if (started) MPI_Finalize();
}

void MpiSession::abort_all(int code) {
  if (started && world_split().size() > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

const WorkSplit& world_split() {
  if (!started) return local_work();
  static const MpiSplit split;
  return split;
}

}  // namespace partslam::apps
