#include "framework/parallel/mpi_env.hpp"

#include <cstdlib>

#include <mpi.h>

namespace rockdem {

namespace {
// Started by mpirun/mpiexec (Open MPI, or a PMI/PMIx launcher such as srun)? A plain start is one
// process: MPI is then not initialised at all, which saves Open MPI's singleton start-up (about
// 0.4 s, most of the time of a short `rockdem element` or `rockdem compare`).
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}
}  // namespace

MpiEnvironment::MpiEnvironment(int& argc, char**& argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized && !launched_by_mpi()) {
    active_ = false;
    return;
  }
  if (!initialized) MPI_Init(&argc, &argv);
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
  int global = code;
  MPI_Allreduce(&code, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  finalized_ = true;
  return global;
}

void MpiEnvironment::barrier() const {
  if (active_) MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace rockdem
