#include "framework/parallel/mpi_env.hpp"

#include <chrono>
#include <cstdlib>
#include <thread>

#include <mpi.h>

namespace rockdem {

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

MpiEnvironment::MpiEnvironment(int& argc, char**& argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  // A plain start is one process: MPI is then not initialised at all, which saves Open MPI's
  // singleton start-up (about 0.4 s, most of the time of a short `rockdem element` or `rockdem
  // compare`).
  if (!initialized && !launched_by_mpi()) {
    active_ = false;
    return;
  }
  // A process may run its loops on threads of its own (--threads, core/threads.hpp); only the
  // thread that started MPI calls it, which MPI_THREAD_FUNNELED declares.
  int provided = 0;
  if (!initialized) MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiEnvironment::~MpiEnvironment() {
  if (active_ && !finalized_) {
    int fin = 0;
    MPI_Finalized(&fin);
    if (!fin) MPI_Finalize();
  }
}

int MpiEnvironment::finish(int code) {
  if (!active_) return code;
  // Open MPI waits by polling at full speed; a process that finished early (a command only
  // process 0 runs) polls this non-blocking reduction gently instead.
  int global = code;
  MPI_Request req;
  MPI_Iallreduce(&code, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD, &req);
  for (int done = 0;;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  MPI_Finalize();
  finalized_ = true;
  return global;
}

void MpiEnvironment::barrier() const {
  if (!active_) return;
  MPI_Request req;
  MPI_Ibarrier(MPI_COMM_WORLD, &req);
  for (int done = 0;;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

}  // namespace rockdem
