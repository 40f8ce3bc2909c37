#pragma once
// The engine's one view of the other processes of a domain-decomposed run (docs/parallel.md).
// This base class is the serial run: one process holds and computes every block, so every verb is
// the identity. framework/parallel/mpi_communication.hpp implements it with MPI; nothing below
// that layer sees a communicator.
//
// The verbs follow LAMMPS's Comm: `borders` finds, after the blocks have moved, which blocks each
// process needs as ghosts (those within contact reach of its own) and `forward` sends the ghosts'
// positions and velocities every step. Contacts between blocks of two processes are computed on
// both (LAMMPS's "newton off"), so no contact force needs to travel back: every owned gridpoint
// sums its forces from the same contacts in the same order as a serial run, and a decomposed run
// gives the serial run's results bit for bit. Blocks change owner only when plan_owners() says so
// (a load grown out of balance, a block that has moved among another process's blocks), and the
// engine then makes the whole state current on every process before the new owners take over
// (Engine::rebalance), so that a change of owner changes no result either.
#include <string>
#include <utility>
#include <vector>

namespace rockdem {

struct Model;
struct Contact;
struct ContactList;

// The parts of the state collect() gathers: the blocks' motion and gridpoints always; zones and
// contacts when asked (a history sample that reads only displacements needs neither).
enum StateParts : unsigned { kZoneState = 1u, kContactState = 2u, kWholeState = 3u };

// How the blocks were shared out, for the run's report.
struct DecompositionReport {
  int processes = 1;
  std::vector<long> blocks, weight;  // per process: blocks owned, their work weight
  long cut_pairs = 0;                // block pairs within contact reach split between processes
  double imbalance = 1.0;            // largest weight over the mean
  double seconds = 0.0;              // wall time of the partitioning
};

// What plan_owners() decided, for the engine that carries it out and the run's report.
struct OwnerChange {
  std::vector<int> owner;        // the new owner of every block position; empty: nothing changes
  bool repartitioned = false;    // a new METIS partition (else: strays only)
  long moved = 0;                // blocks whose owner changes
  std::vector<int> strays;       // positions of blocks that touch only other processes' blocks
  double imbalance_before = 1.0; // largest process weight over the mean, before and after
  double imbalance_after = 1.0;
  bool collected = false;        // the whole model's state was made current on every process
  double seconds = 0.0;          // wall time of the planning (Engine::rebalance: and of the hand-over)
};

class Communication {
 public:
  virtual ~Communication() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  bool root() const { return rank() == 0; }

  // Shares the blocks among the processes (partition.hpp); a serial run keeps them all.
  virtual DecompositionReport decompose(Model&, double /*margin*/) { return {}; }
  // Whether blocks should change owner, the same answer on every process (collective): when the
  // load imbalance (largest process weight over the mean, weights as decompose() gives them)
  // exceeds `limit` (0: never) and has grown since the last partition, a new METIS partition whose
  // parts are matched to the present owners so that as few blocks as possible move; else the
  // blocks all of whose contacts are with another process's blocks (a block that fell among them)
  // go to the process they touch most. A new partition needs the whole contact graph: it collects
  // the model's state on every process first (`collected`), the contact list this process had
  // going to `local` for the caller to put back when nothing changes.
  virtual OwnerChange plan_owners(Model&, double /*margin*/, double /*limit*/, ContactList* /*local*/) { return {}; }
  // After motion, before contact detection: marks as ghosts the blocks of other processes whose
  // boxes, grown by `margin`, reach the boxes of this process's blocks, and sets up what
  // forward() sends and receives.
  virtual void borders(Model&, double /*margin*/) {}
  // Positions and velocities of the ghosts' boundary gridpoints (and of rigid ghosts' centroids).
  virtual void forward(Model&) {}

  // Every process's `n` values, in process order (all[r * n + k]), on every process: one
  // exchange that a step's several global quantities share.
  virtual void gather_all(const double* values, int n, std::vector<double>& all) const { all.assign(values, values + n); }
  // Global sums (in place), minimum and maximum, the same on every process. Sums are formed in
  // process order, so they are the same from run to run on a given process count.
  virtual void sum(double* /*values*/, int /*n*/) const {}
  // Sums (in place) of values that one process holds each, the others giving zero (what only a
  // block's owner knows: its contact force, its damping averages). Adding zeros is exact in any
  // order, so one reduction gives the owner's value on every process, without every process
  // receiving every other's array as `sum` does.
  virtual void sum_held(double* /*values*/, int /*n*/) const {}
  virtual double min(double v) const { return v; }
  virtual double max(double v) const { return v; }
  // The first non-empty message of all processes (in rank order): an error found on one process
  // is raised on all of them, so that none is left waiting for the others.
  virtual std::string first_message(const std::string& message) const { return message; }

  // Where the processes' time went (collective): one line per process with the seconds spent
  // exchanging and waiting, by verb, for the run's summary; empty for a serial run.
  virtual std::string time_report() const { return {}; }

  // Makes the whole model current on process `root` (on every process for root < 0): each
  // process sends the state of the blocks it owns (their gridpoints, zones and motion) and of
  // the contacts it owns (those whose point lies on one of its blocks). On the receiving side
  // the contact list becomes every contact of the model, sorted by key; `local_contacts` gets the
  // list it replaced (so that a process can go on stepping with it after writing output).
  virtual void collect(Model&, int /*root*/, ContactList* /*local_contacts*/ = nullptr,
                       unsigned /*parts*/ = kWholeState) {}
};

// The serial run's communication, for callers that have none of their own.
Communication& serial_communication();

}  // namespace rockdem
