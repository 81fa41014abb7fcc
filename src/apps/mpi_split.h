// `mpirun -n P partslam eval ...`: the process's place among MPI ranks as a WorkSplit (core/work_split.h),
// over Debian's OpenMPI. MPI is started only when the process was launched by
// mpirun (its environment says so), so a plain `partslam` run never touches it. Rank 0 prints and writes the
// outputs; the other ranks compute their slices silently.
#pragma once

#include "core/work_split.h"

namespace partslam::apps {

/// Starts MPI when launched by mpirun; the returned guard finalises it. Call once, first thing in main.
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  /// Ends every rank after an error on one (MPI_Abort) when there are several; no-op otherwise.
  static void abort_all(int code);
};

/// This process's split: its MPI rank among the world's, or the one-process split outside mpirun.
const WorkSplit& world_split();

/// True on the process that prints and writes outputs (rank 0, or the only process).
inline bool is_reporting_process() { return world_split().rank() == 0; }

}  // namespace partslam::apps
