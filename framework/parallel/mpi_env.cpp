#include "framework/parallel/mpi_env.hpp"

#include <mpi.h>

namespace rockdem {

MpiEnvironment::MpiEnvironment(int& argc, char**& argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiEnvironment::~MpiEnvironment() {
  if (!finalized_) {
    int fin = 0;
    MPI_Finalized(&fin);
    if (!fin) MPI_Finalize();
  }
}

int MpiEnvironment::finish(int code) {
  int global = code;
  MPI_Allreduce(&code, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  finalized_ = true;
  return global;
}

void MpiEnvironment::barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

}  // namespace rockdem
