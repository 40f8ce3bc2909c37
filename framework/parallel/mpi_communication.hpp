#pragma once
// Domain decomposition with MPI (docs/parallel.md): the Communication of a run on several
// processes. Every process holds the whole model's arrays (partition.hpp says why); it steps the
// blocks METIS gave it and receives, every step, the positions and velocities of the blocks of
// other processes within contact reach of its own.
#include <memory>
#include <string>
#include <vector>

#include "framework/model/communication.hpp"
#include "framework/model/model.hpp"

namespace rockdem {

class MpiCommunication final : public Communication {
 public:
  MpiCommunication();  // MPI_COMM_WORLD, started by MpiEnvironment
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  // Shares the blocks among the processes with METIS on the block-contact graph (block pairs
  // whose boxes, grown by `margin`, overlap): a block weighs its zones and gridpoints (rigid
  // blocks their corners) plus its candidate contacts, a pair its candidate contacts. Computed on
  // process 0 and sent to all; the same on every process count and every run.
  DecompositionReport decompose(Model& m, double margin) override;
  OwnerChange plan_owners(Model& m, double margin, double limit, ContactList* local) override;

  void borders(Model& m, double margin) override;
  void forward(Model& m) override;
  void gather_all(const double* values, int n, std::vector<double>& all) const override;
  void sum(double* values, int n) const override;
  void sum_held(double* values, int n) const override;
  double min(double v) const override;
  double max(double v) const override;
  std::string first_message(const std::string& message) const override;
  void collect(Model& m, int root, ContactList* local_contacts, unsigned parts) override;
  std::string time_report() const override;

 private:
  // Wall seconds spent in each verb, waiting for the other processes included.
  struct Seconds {
    double borders = 0.0, forward = 0.0, reduce = 0.0, collect = 0.0;
    double owners = 0.0;  // plan_owners(), its reductions and collect included
  };
  double forward_bytes_ = 0.0;  // sent by forward() since the start
  long forwards_ = 0;           // forward() calls
  mutable Seconds spent_;
  double started_ = 0.0;  // MPI_Wtime at construction
  struct Neighbour {
    int rank = 0;
    std::vector<int> send, recv;  // block positions, ascending
    std::vector<double> send_buf, recv_buf;
  };
  int rank_ = 0, size_ = 1;
  std::vector<Neighbour> neighbours_;
  // Where this process's blocks' boundary gridpoints were when the ghosts were last found, and
  // which blocks it owned then: borders() finds them again only once a point has moved far enough
  // to need it (a Verlet skin, as LAMMPS's neighbour lists have).
  std::vector<Vec2> anchor_;
  std::vector<int> anchor_blocks_;
  double anchor_margin_ = 0.0;
  long borders_skipped_ = 0, borders_done_ = 0;
  double boxes_received_ = 0.0;  // other processes' block boxes received by borders(), in all
  // The imbalance the last partition reached: plan_owners() partitions again only beyond it.
  double settled_imbalance_ = 1.0;
  double last_imbalance_ = 1.0;  // at the last check (after its change, if any), for the report
  long owner_checks_ = 0, owner_changes_ = 0, blocks_moved_ = 0;
};

// The communication of this process: an MpiCommunication when started by mpirun on more than one
// process, else null (a serial run: serial_communication()).
std::unique_ptr<Communication> make_communication();

}  // namespace rockdem
