// The MPI job this process belongs to, if any (`mpirun -n N farfield bake ...`): its rank and
// the number of ranks, and a barrier. Started by start() from main() only when the process was
// launched by mpirun (OpenMPI's OMPI_COMM_WORLD_SIZE or PMIx's PMIX_RANK in the environment),
// so that without mpirun nothing of MPI runs; a build without MPI (FARFIELD_MPI off, or
// libopenmpi-dev absent) is always a world of one and refuses to run under mpirun rather than
// have every rank do all the work.
#pragma once

#include "farfield/core/result.hpp"

namespace farfield {

class MpiWorld {
 public:
  // The process's world: rank 0 of 1 until start() joins a job.
  static const MpiWorld& get();
  // Joins the job that launched this process, if one did (MPI_Init); idempotent.
  static Result<void> start(int* argc, char*** argv);
  // Leaves it (MPI_Finalize), at exit.
  static void stop();
  // Whether this build can join an MPI job.
  static bool available();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }
  // Waits until every rank has come here (nothing in a world of one).
  void barrier() const;

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace farfield
