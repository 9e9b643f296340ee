#include "farfield/core/mpi_world.hpp"

#include <chrono>
#include <cstdlib>
#include <thread>

#ifdef FARFIELD_HAS_MPI
#include <mpi.h>
#endif

namespace farfield {

namespace {

MpiWorld& world() {
  static MpiWorld w;
  return w;
}

bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

bool started = false;

}  // namespace

const MpiWorld& MpiWorld::get() { return world(); }

bool MpiWorld::available() {
#ifdef FARFIELD_HAS_MPI
  return true;
#else
  return false;
#endif
}

Result<void> MpiWorld::start(int* argc, char*** argv) {
  if (started || !launched_by_mpirun()) return {};
#ifdef FARFIELD_HAS_MPI
  if (MPI_Init(argc, argv) != MPI_SUCCESS) return make_error("MPI_Init failed");
  started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &world().rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &world().size_);
  return {};
#else
  (void)argc, (void)argv;
  return make_error("launched by mpirun, but this build has no MPI (install libopenmpi-dev and "
                    "build again): every rank would do all the work");
#endif
}

void MpiWorld::stop() {
#ifdef FARFIELD_HAS_MPI
  if (started) MPI_Finalize();
#endif
  started = false;
}

void MpiWorld::barrier() const {
#ifdef FARFIELD_HAS_MPI
  if (!started || size_ <= 1) return;
  // Polled with sleeps: OpenMPI's blocking barrier spins, and a rank that waits while rank 0
  // renders for minutes would take a core from it.
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
#endif
}

}  // namespace farfield
