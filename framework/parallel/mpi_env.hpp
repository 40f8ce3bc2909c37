#pragma once
// MPI lives here (framework/parallel/) and nowhere else. The rest of rockdem asks this object for
// its rank and size. `rockdem run` shares a model among the processes (mpi_communication.hpp);
// the other commands run on process 0 while the others wait without spinning.
namespace rockdem {

// Started by mpirun/mpiexec (Open MPI, or a PMI/PMIx launcher such as srun), from the
// environment the launcher sets; any process count, one included.
bool launched_by_mpi();

class MpiEnvironment {
 public:
  MpiEnvironment(int& argc, char**& argv);
  ~MpiEnvironment();
  MpiEnvironment(const MpiEnvironment&) = delete;
  MpiEnvironment& operator=(const MpiEnvironment&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  // Agree on an exit code across ranks (the largest), finalise, and return it.
  int finish(int code);
  // Block until rank 0 reaches its matching barrier (serial runs on several ranks).
  void barrier() const;

 private:
  int rank_ = 0;
  int size_ = 1;
  bool finalized_ = false;
  bool active_ = true;  // MPI initialised (false: a plain start, one process)
};

}  // namespace rockdem
