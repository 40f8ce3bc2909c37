#include "framework/parallel/mpi_communication.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <tuple>

#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <metis.h>
#include <mpi.h>

#include "framework/core/error.hpp"
#include "framework/model/state_fields.hpp"

namespace rockdem {
namespace {

constexpr int kTagBorders = 8;  // borders(): box counts, then boxes, between processes whose domains meet

// A block's box, grown by the margin, as CGAL's box intersection takes it, with the block's position.
using BlockBox = CGAL::Box_intersection_d::Box_with_info_d<double, 2, int>;

BlockBox block_box(const Model& m, int b, double margin) {
  double lo[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  double hi[2] = {-lo[0], -lo[1]};
  for (int g : m.blocks[static_cast<std::size_t>(b)].boundary) {
    const Vec2& x = m.gp[static_cast<std::size_t>(g)].x;
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], x[d] - margin);
      hi[d] = std::max(hi[d], x[d] + margin);
    }
  }
  return BlockBox(lo, hi, b);
}

// Calls f(i, j) once for every pair of overlapping boxes.
template <class F>
void overlapping_pairs(std::vector<BlockBox>& boxes, F&& f) {
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const BlockBox& a, const BlockBox& b) {
    f(a.info(), b.info());
  });
}

// Appends the fields of `item` (those of role `state` only, or all) to `out` / reads them back,
// through the model's field tables (state_fields.hpp): a field added there travels too.
template <class Item, std::size_t N>
void pack(const fields::Field<Item> (&table)[N], const Item& item, bool state_only, std::vector<std::byte>& out) {
  for (const auto& f : table) {
    if (state_only && f.role != fields::Role::state) continue;
    const std::size_t at = out.size();
    out.resize(at + f.bytes());
    f.get(item, out.data() + at);
  }
}
template <class Item, std::size_t N>
const std::byte* unpack(const fields::Field<Item> (&table)[N], Item& item, bool state_only, const std::byte* in) {
  for (const auto& f : table) {
    if (state_only && f.role != fields::Role::state) continue;
    f.set(item, in);
    in += f.bytes();
  }
  return in;
}

template <class T>
void put(std::vector<std::byte>& out, T v) {
  const std::size_t at = out.size();
  out.resize(at + sizeof v);
  std::memcpy(out.data() + at, &v, sizeof v);
}
template <class T>
T take(const std::byte*& in) {
  T v;
  std::memcpy(&v, in, sizeof v);
  in += sizeof v;
  return v;
}

// Adds the wall time from construction to destruction to `total`.
class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), t0_(MPI_Wtime()) {}
  ~Stopwatch() { total_ += MPI_Wtime() - t0_; }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  double t0_;
};

bool owned_contact(const Model& m, const Contact& c) { return m.part.owns(m.gp[static_cast<std::size_t>(c.point)].block); }

// The order of a serial run's contact list: block pairs by position (lower, higher), the lower
// block's points first, then each point's place in its boundary loop and its side (detection.cpp
// visits them so). A collected list in this order is the serial run's list.
bool serial_order(const Model& m, const Contact& a, const Contact& b) {
  auto rank_of = [&](const Contact& c) {
    const int pa = m.gp[static_cast<std::size_t>(c.point)].block, ob = c.other;
    return std::make_tuple(std::min(pa, ob), std::max(pa, ob), pa > ob, c.point_loop, c.key.side);
  };
  return rank_of(a) < rank_of(b);
}

}  // namespace

std::unique_ptr<Communication> make_communication() {
  int started = 0, finished = 0;
  MPI_Initialized(&started);
  MPI_Finalized(&finished);
  if (!started || finished) return nullptr;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size < 2) return nullptr;
  return std::make_unique<MpiCommunication>();
}

MpiCommunication::MpiCommunication() {
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  started_ = MPI_Wtime();
}

std::string MpiCommunication::time_report() const {
  const double mine[8] = {MPI_Wtime() - started_, spent_.borders, spent_.forward, spent_.reduce, spent_.collect,
                          forwards_ > 0 ? forward_bytes_ / static_cast<double>(forwards_) : 0.0,
                          static_cast<double>(borders_done_),
                          borders_done_ > 0 ? boxes_received_ / static_cast<double>(borders_done_) : 0.0};
  std::vector<double> all(8 * static_cast<std::size_t>(size_));
  MPI_Gather(mine, 8, MPI_DOUBLE, all.data(), 8, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (rank_ != 0) return {};
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(2);
  os << "time in communication (exchanging and waiting), by process:";
  for (int r = 0; r < size_; ++r) {
    const double* t = &all[8 * static_cast<std::size_t>(r)];
    const double comm = t[1] + t[2] + t[3] + t[4];
    os << "\n  process " << r << ": " << comm << " s of " << t[0] << " s (" << 100.0 * comm / t[0] << " %): borders " << t[1]
       << " s (ghosts found " << static_cast<long>(t[6]) << " times of " << borders_done_ + borders_skipped_ << ", "
       << static_cast<long>(t[7]) << " boxes of other processes' blocks received each time), forward " << t[2] << " s (" << t[5] / 1024.0 << " KiB sent a step), reductions " << t[3] << " s, collect "
       << t[4] << " s";
  }
  os << "\n  ownership checked " << owner_checks_ << " times (" << spent_.owners << " s on process 0, its collects included): "
     << owner_changes_ << " changes, " << blocks_moved_ << " blocks moved; load imbalance at the last check " << last_imbalance_;
  return os.str();
}

namespace {

// The block-contact graph decompose() and plan_owners() partition: blocks, and the pairs whose
// boxes, grown by the margin, overlap; weights from the work each carries (every contact of the
// model's list counts, so the list must be the whole model's).
struct BlockGraph {
  std::vector<std::set<int>> adj;
  std::map<std::pair<int, int>, idx_t> contacts;  // per block pair, the contacts it has now
  std::vector<idx_t> vwgt;
};

BlockGraph block_graph(const Model& m, double margin) {
  const int nb = static_cast<int>(m.blocks.size());
  BlockGraph g;
  std::vector<BlockBox> boxes;
  boxes.reserve(static_cast<std::size_t>(nb));
  for (int b = 0; b < nb; ++b) boxes.push_back(block_box(m, b, margin));
  g.adj.resize(static_cast<std::size_t>(nb));
  overlapping_pairs(boxes, [&](int i, int j) {
    g.adj[static_cast<std::size_t>(i)].insert(j);
    g.adj[static_cast<std::size_t>(j)].insert(i);
  });
  g.vwgt.resize(static_cast<std::size_t>(nb));
  for (int b = 0; b < nb; ++b) {
    const Block& B = m.blocks[static_cast<std::size_t>(b)];
    g.vwgt[static_cast<std::size_t>(b)] = 1 + B.n_zone + B.n_gp;
  }
  // A contact costs about three times a zone or a gridpoint per step (geometry, joint law,
  // detection; measured on scripts/bench/parallel/rock_mass_10k.toml, docs/parallel.md).
  for (const Contact& c : m.contacts.items) {
    const int a = m.gp[static_cast<std::size_t>(c.point)].block, o = c.other;
    ++g.contacts[{std::min(a, o), std::max(a, o)}];
    g.vwgt[static_cast<std::size_t>(a)] += 3;
  }
  return g;
}

// METIS's k-way partition of the graph into `parts`, computed on process 0 and sent to all.
std::vector<int> partition_graph(const BlockGraph& g, int parts, int rank) {
  const int nb = static_cast<int>(g.vwgt.size());
  std::vector<int> owner(static_cast<std::size_t>(nb), 0);
  if (nb <= parts) {
    // No more blocks than processes: one each, and the processes left over wait.
    for (int b = 0; b < nb; ++b) owner[static_cast<std::size_t>(b)] = b;
    return owner;
  }
  int status = METIS_OK;
  if (rank == 0) {
    std::vector<idx_t> xadj{0}, adjncy, adjwgt;
    for (int b = 0; b < nb; ++b) {
      for (int o : g.adj[static_cast<std::size_t>(b)]) {
        adjncy.push_back(o);
        const auto it = g.contacts.find({std::min(b, o), std::max(b, o)});
        // A pair without contacts yet still costs its narrow-phase checks.
        adjwgt.push_back(1 + (it == g.contacts.end() ? 0 : it->second));
      }
      xadj.push_back(static_cast<idx_t>(adjncy.size()));
    }
    idx_t n = nb, ncon = 1, np = parts, cut = 0;
    std::vector<idx_t> part(static_cast<std::size_t>(nb), 0);
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // the same partition every run
    std::vector<idx_t> vwgt = g.vwgt;
    status = METIS_PartGraphKway(&n, &ncon, xadj.data(), adjncy.data(), vwgt.data(), nullptr, adjwgt.data(), &np, nullptr,
                                 nullptr, options, &cut, part.data());
    for (int b = 0; b < nb; ++b) owner[static_cast<std::size_t>(b)] = static_cast<int>(part[static_cast<std::size_t>(b)]);
  }
  MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (status != METIS_OK) throw std::runtime_error("METIS could not partition the block graph (status " + std::to_string(status) + ")");
  MPI_Bcast(owner.data(), nb, MPI_INT, 0, MPI_COMM_WORLD);
  return owner;
}

// Largest process weight over the mean; `weight` gets each process's.
double imbalance_of(const std::vector<int>& owner, const std::vector<idx_t>& vwgt, int parts, std::vector<long>* weight = nullptr) {
  std::vector<long> w(static_cast<std::size_t>(parts), 0);
  for (std::size_t b = 0; b < owner.size(); ++b) w[static_cast<std::size_t>(owner[b])] += vwgt[b];
  const double total = static_cast<double>(std::accumulate(w.begin(), w.end(), 0L));
  const double worst = static_cast<double>(*std::max_element(w.begin(), w.end()));
  if (weight) *weight = std::move(w);
  return total > 0.0 ? worst * parts / total : 1.0;
}

// Gives the parts of a fresh partition the labels (processes) that keep the most block weight
// where it is: the pair of fresh part and present owner sharing the most weight first, then the
// next among those left (the processor reassignment of scratch-remap repartitioning, Oliker &
// Biswas 1998). A new partition then moves only the blocks it has to.
std::vector<int> matched_to_owners(const std::vector<int>& fresh, const std::vector<int>& owner, const std::vector<idx_t>& vwgt,
                                   int parts) {
  const auto P = static_cast<std::size_t>(parts);
  std::vector<long> shared(P * P, 0);  // [fresh part][owner]
  for (std::size_t b = 0; b < fresh.size(); ++b)
    shared[static_cast<std::size_t>(fresh[b]) * P + static_cast<std::size_t>(owner[b])] += vwgt[b];
  std::vector<std::size_t> order(P * P);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return shared[a] > shared[b]; });
  std::vector<int> label(P, -1);
  std::vector<char> taken(P, 0);
  for (std::size_t k : order) {
    const std::size_t f = k / P, o = k % P;
    if (label[f] >= 0 || taken[o]) continue;
    label[f] = static_cast<int>(o);
    taken[o] = 1;
  }
  std::vector<int> out(fresh.size());
  for (std::size_t b = 0; b < fresh.size(); ++b) out[b] = label[static_cast<std::size_t>(fresh[b])];
  return out;
}

}  // namespace

DecompositionReport MpiCommunication::decompose(Model& m, double margin) {
  const auto t0 = std::chrono::steady_clock::now();
  DecompositionReport rep;
  rep.processes = size_;
  const BlockGraph g = block_graph(m, margin);
  const std::vector<int> owner = partition_graph(g, size_, rank_);
  assign_owners(m, owner, rank_);
  rep.imbalance = imbalance_of(owner, g.vwgt, size_, &rep.weight);
  rep.blocks.assign(static_cast<std::size_t>(size_), 0);
  for (std::size_t b = 0; b < owner.size(); ++b) {
    ++rep.blocks[static_cast<std::size_t>(owner[b])];
    for (int o : g.adj[b])
      if (o > static_cast<int>(b) && owner[static_cast<std::size_t>(o)] != owner[b]) ++rep.cut_pairs;
  }
  settled_imbalance_ = rep.imbalance;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

OwnerChange MpiCommunication::plan_owners(Model& m, double margin, double limit, ContactList* local) {
  OwnerChange ch;
  const Partition& p = m.part;
  if (!p.decomposed()) return ch;
  const double t0 = MPI_Wtime();
  const auto nb = m.blocks.size();
  // This process's weight (decompose()'s: each contact counts on the process owning its point)
  // and, per block it owns, how many of its contacts are with its own process's blocks and with
  // which others'. A process holds every contact of the blocks it owns, both ways round.
  long weight = 0;
  for (int b : p.owned_blocks) {
    const Block& B = m.blocks[static_cast<std::size_t>(b)];
    weight += 1 + B.n_zone + B.n_gp;
  }
  std::vector<int> at_home(nb, 0);
  std::vector<std::pair<int, int>> abroad;  // (owned block, block of another process it touches), once per contact
  for (const Contact& c : m.contacts.items) {
    const int a = m.gp[static_cast<std::size_t>(c.point)].block, o = c.other;
    for (auto [own, other] : {std::pair{a, o}, std::pair{o, a}}) {
      if (!p.owns(own)) continue;
      if (own == a) weight += 3;
      if (p.owner[static_cast<std::size_t>(other)] == rank_) ++at_home[static_cast<std::size_t>(own)];
      else abroad.emplace_back(own, other);
    }
  }
  // A stray: a block that touches other processes' blocks and none of its owner's, whose owner
  // has other blocks (a process's only block stays: the processes beyond the blocks' count wait).
  // Sent as [block, n, the n blocks it touches (one per contact)]: where it goes is decided below,
  // with every process's strays known.
  std::sort(abroad.begin(), abroad.end());
  std::vector<int> mine;
  if (p.owned_blocks.size() > 1)
    for (std::size_t i = 0; i < abroad.size();) {
      std::size_t j = i;
      while (j < abroad.size() && abroad[j].first == abroad[i].first) ++j;
      if (at_home[static_cast<std::size_t>(abroad[i].first)] == 0) {
        mine.insert(mine.end(), {abroad[i].first, static_cast<int>(j - i)});
        for (std::size_t k = i; k < j; ++k) mine.push_back(abroad[k].second);
      }
      i = j;
    }
  // Every process's weight and strays.
  const double local_n[2] = {static_cast<double>(weight), static_cast<double>(mine.size())};
  std::vector<double> all;
  gather_all(local_n, 2, all);
  double total = 0.0, worst = 0.0;
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(static_cast<std::size_t>(size_), 0);
  for (int r = 0; r < size_; ++r) {
    total += all[2 * static_cast<std::size_t>(r)];
    worst = std::max(worst, all[2 * static_cast<std::size_t>(r)]);
    counts[static_cast<std::size_t>(r)] = static_cast<int>(all[2 * static_cast<std::size_t>(r) + 1]);
    if (r > 0) displs[static_cast<std::size_t>(r)] = displs[static_cast<std::size_t>(r) - 1] + counts[static_cast<std::size_t>(r) - 1];
  }
  ch.imbalance_before = ch.imbalance_after = total > 0.0 ? worst * size_ / total : 1.0;
  ++owner_checks_;
  last_imbalance_ = ch.imbalance_before;
  std::vector<int> owner = p.owner;
  // Repartition when the balance has become worse than the limit and than what the last
  // partition reached by more than 0.02 (a model that cannot be balanced better, such as one
  // whose largest block outweighs a process's share, is not partitioned again at every check).
  if (limit > 0.0 && ch.imbalance_before > limit && ch.imbalance_before > settled_imbalance_ + 0.02 &&
      nb > static_cast<std::size_t>(size_)) {
    collect(m, -1, local, kWholeState);
    ch.collected = true;
    const BlockGraph g = block_graph(m, margin);
    std::vector<int> fresh;
    try {
      fresh = matched_to_owners(partition_graph(g, size_, rank_), p.owner, g.vwgt, size_);
    } catch (const std::runtime_error&) {
      // (Raised on every process alike.) A run does not need a new partition: it goes on as it is.
      fresh = p.owner;
    }
    const double before = imbalance_of(p.owner, g.vwgt, size_), after = imbalance_of(fresh, g.vwgt, size_);
    settled_imbalance_ = std::min(before, after);
    // Worth the move only for a clear gain (a partition 0.003 better moved 66 of 171 blocks).
    if (after < before - 0.01) {
      owner = fresh;
      ch.repartitioned = true;
      ch.imbalance_before = before;
      ch.imbalance_after = last_imbalance_ = after;
    }
  } else {
    std::vector<int> strays(static_cast<std::size_t>(displs.back() + counts.back()));
    MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_INT, strays.data(), counts.data(), displs.data(), MPI_INT,
                   MPI_COMM_WORLD);
    // In process order, which is ascending block order within each: a stray goes to the process
    // owning most of the blocks it touches, as they are owned by then, unless one of them is by
    // then its own process's (two strays touching each other across two processes would otherwise
    // trade places at every check).
    for (std::size_t k = 0; k + 1 < strays.size(); k += 2 + static_cast<std::size_t>(strays[k + 1])) {
      const int b = strays[k];
      std::map<int, long> touches;  // process -> contacts
      for (int i = 0; i < strays[k + 1]; ++i) ++touches[owner[static_cast<std::size_t>(strays[k + 2 + static_cast<std::size_t>(i)])]];
      if (touches.count(owner[static_cast<std::size_t>(b)])) continue;
      int to = -1;
      long most = 0;
      for (const auto& [r, n] : touches)
        if (n > most) {
          most = n;
          to = r;
        }
      owner[static_cast<std::size_t>(b)] = to;
      ch.strays.push_back(b);
    }
  }
  for (std::size_t b = 0; b < nb; ++b) ch.moved += owner[b] != p.owner[b];
  if (ch.moved > 0) {
    ch.owner = std::move(owner);
    ++owner_changes_;
    blocks_moved_ += ch.moved;
  }
  ch.seconds = MPI_Wtime() - t0;
  spent_.owners += ch.seconds;
  return ch;
}

void MpiCommunication::borders(Model& m, double margin) {
  Partition& p = m.part;
  if (!p.decomposed()) return;
  const Stopwatch watch(spent_.borders);
  // The ghosts were found with boxes grown by `margin`, twice the detection distance the broad
  // phase grows them by: while no point has moved more than a quarter of it since, every pair the
  // broad phase can find still lies within those boxes, and the ghosts are still enough.
  bool still_enough = anchor_blocks_ == p.owned_blocks && anchor_margin_ == margin;
  // (An excavation renumbers the blocks and forgets the ghosts: then they are found again.)
  for (const Neighbour& n : neighbours_)
    for (int b : n.recv)
      still_enough = still_enough && static_cast<std::size_t>(b) < p.role.size() && p.role[static_cast<std::size_t>(b)] == Partition::ghost;
  double moved = 0.0;
  if (still_enough) {
    std::size_t k = 0;
    for (int b : p.owned_blocks)
      for (int g : m.blocks[static_cast<std::size_t>(b)].boundary)
        moved = std::max(moved, (m.gp[static_cast<std::size_t>(g)].x - anchor_[k++]).lpNorm<Eigen::Infinity>());
  }
  int local_ok = still_enough && moved < 0.25 * margin ? 1 : 0, all_ok = 0;
  MPI_Allreduce(&local_ok, &all_ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (all_ok) {
    ++borders_skipped_;
    return;
  }
  ++borders_done_;
  anchor_.clear();
  for (int b : p.owned_blocks)
    for (int g : m.blocks[static_cast<std::size_t>(b)].boundary) anchor_.push_back(m.gp[static_cast<std::size_t>(g)].x);
  anchor_blocks_ = p.owned_blocks;
  anchor_margin_ = margin;
  // The boxes of this process's blocks, and its domain: the box around them all. Only processes
  // whose domains meet exchange boxes, and each sends only those of its boxes that meet the
  // other's domain (a box of theirs that overlaps one of ours meets our domain, so no pair with
  // one of our blocks is missed: the pairs, and so the ghosts, are those that sending every box
  // to every process finds, at a cost that follows the partition's boundary, not the model's
  // size). Sent as [block, lo x, lo y, hi x, hi y].
  std::vector<BlockBox> boxes;
  boxes.reserve(p.owned_blocks.size());
  double domain[4] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                      -std::numeric_limits<double>::max(), -std::numeric_limits<double>::max()};
  for (int b : p.owned_blocks) {
    boxes.push_back(block_box(m, b, margin));
    const BlockBox& box = boxes.back();
    domain[0] = std::min(domain[0], box.min_coord(0));
    domain[1] = std::min(domain[1], box.min_coord(1));
    domain[2] = std::max(domain[2], box.max_coord(0));
    domain[3] = std::max(domain[3], box.max_coord(1));
  }
  std::vector<double> domains(4 * static_cast<std::size_t>(size_));
  MPI_Allgather(domain, 4, MPI_DOUBLE, domains.data(), 4, MPI_DOUBLE, MPI_COMM_WORLD);
  auto meets = [](const double* d, double x0, double y0, double x1, double y1) {  // closed boxes
    return d[0] <= x1 && x0 <= d[2] && d[1] <= y1 && y0 <= d[3];
  };
  std::vector<int> near;  // the other processes whose domains meet ours (empty ones meet none)
  for (int r = 0; r < size_; ++r)
    if (r != rank_ && meets(&domains[4 * static_cast<std::size_t>(r)], domain[0], domain[1], domain[2], domain[3]))
      near.push_back(r);
  const std::size_t own = boxes.size();
  std::vector<std::vector<double>> out(near.size()), in(near.size());
  std::vector<int> out_n(near.size()), in_n(near.size());
  for (std::size_t k = 0; k < near.size(); ++k) {
    const double* d = &domains[4 * static_cast<std::size_t>(near[k])];
    for (std::size_t i = 0; i < own; ++i) {
      const BlockBox& b = boxes[i];
      if (meets(d, b.min_coord(0), b.min_coord(1), b.max_coord(0), b.max_coord(1)))
        out[k].insert(out[k].end(), {static_cast<double>(b.info()), b.min_coord(0), b.min_coord(1), b.max_coord(0), b.max_coord(1)});
    }
    out_n[k] = static_cast<int>(out[k].size());
  }
  std::vector<MPI_Request> req(2 * near.size());
  for (std::size_t k = 0; k < near.size(); ++k) {
    MPI_Irecv(&in_n[k], 1, MPI_INT, near[k], kTagBorders, MPI_COMM_WORLD, &req[2 * k]);
    MPI_Isend(&out_n[k], 1, MPI_INT, near[k], kTagBorders, MPI_COMM_WORLD, &req[2 * k + 1]);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  for (std::size_t k = 0; k < near.size(); ++k) {
    in[k].resize(static_cast<std::size_t>(in_n[k]));
    MPI_Irecv(in[k].data(), in_n[k], MPI_DOUBLE, near[k], kTagBorders, MPI_COMM_WORLD, &req[2 * k]);
    MPI_Isend(out[k].data(), out_n[k], MPI_DOUBLE, near[k], kTagBorders, MPI_COMM_WORLD, &req[2 * k + 1]);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  for (const auto& v : in)
    for (std::size_t k = 0; k + 4 < v.size(); k += 5) {
      double lo[2] = {v[k + 1], v[k + 2]}, hi[2] = {v[k + 3], v[k + 4]};
      boxes.emplace_back(lo, hi, static_cast<int>(v[k]));
    }
  boxes_received_ += static_cast<double>(boxes.size() - own);
  // Pairs across two processes, one of them this one: the other's block is a ghost here, ours a
  // ghost there. Both sides find the same pairs from the same boxes, so the lists agree.
  std::map<int, std::pair<std::set<int>, std::set<int>>> lists;  // rank -> (send, recv)
  overlapping_pairs(boxes, [&](int i, int j) {
    const int oi = p.owner[static_cast<std::size_t>(i)], oj = p.owner[static_cast<std::size_t>(j)];
    if (oi == oj) return;
    if (oi == rank_) {
      lists[oj].first.insert(i);
      lists[oj].second.insert(j);
    } else if (oj == rank_) {
      lists[oi].first.insert(j);
      lists[oi].second.insert(i);
    }
  });
  for (std::size_t b = 0; b < p.role.size(); ++b)
    if (p.role[b] == Partition::ghost) p.role[b] = Partition::elsewhere;
  std::set<int> ghosts;
  neighbours_.clear();
  for (auto& [r, sr] : lists) {
    Neighbour n;
    n.rank = r;
    n.send.assign(sr.first.begin(), sr.first.end());
    n.recv.assign(sr.second.begin(), sr.second.end());
    ghosts.insert(sr.second.begin(), sr.second.end());
    neighbours_.push_back(std::move(n));
  }
  p.ghost_blocks.assign(ghosts.begin(), ghosts.end());
  for (int b : p.ghost_blocks) p.role[static_cast<std::size_t>(b)] = Partition::ghost;
}

void MpiCommunication::forward(Model& m) {
  if (!m.part.decomposed() || neighbours_.empty()) return;
  const Stopwatch watch(spent_.forward);
  // Per block: its motion (centroid, velocity, angle, spin), then each boundary gridpoint's
  // position and velocity, in loop order.
  auto block_size = [&](int b) { return 6 + 4 * m.blocks[static_cast<std::size_t>(b)].boundary.size(); };
  std::vector<MPI_Request> req;
  req.reserve(2 * neighbours_.size());
  for (Neighbour& n : neighbours_) {
    std::size_t size = 0;
    for (int b : n.recv) size += block_size(b);
    n.recv_buf.resize(size);
    req.emplace_back();
    MPI_Irecv(n.recv_buf.data(), static_cast<int>(size), MPI_DOUBLE, n.rank, 7, MPI_COMM_WORLD, &req.back());
  }
  for (Neighbour& n : neighbours_) {
    n.send_buf.clear();
    for (int b : n.send) {
      const Block& B = m.blocks[static_cast<std::size_t>(b)];
      n.send_buf.insert(n.send_buf.end(), {B.xc.x(), B.xc.y(), B.vc.x(), B.vc.y(), B.theta, B.omega});
      for (int g : B.boundary) {
        const GridPoint& G = m.gp[static_cast<std::size_t>(g)];
        n.send_buf.insert(n.send_buf.end(), {G.x.x(), G.x.y(), G.v.x(), G.v.y()});
      }
    }
    forward_bytes_ += 8.0 * static_cast<double>(n.send_buf.size());
    req.emplace_back();
    MPI_Isend(n.send_buf.data(), static_cast<int>(n.send_buf.size()), MPI_DOUBLE, n.rank, 7, MPI_COMM_WORLD, &req.back());
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  ++forwards_;
  for (const Neighbour& n : neighbours_) {
    const double* in = n.recv_buf.data();
    for (int b : n.recv) {
      Block& B = m.blocks[static_cast<std::size_t>(b)];
      B.xc = Vec2(in[0], in[1]);
      B.vc = Vec2(in[2], in[3]);
      B.theta = in[4];
      B.omega = in[5];
      in += 6;
      for (int g : B.boundary) {
        GridPoint& G = m.gp[static_cast<std::size_t>(g)];
        G.x = Vec2(in[0], in[1]);
        G.v = Vec2(in[2], in[3]);
        in += 4;
      }
    }
  }
}

void MpiCommunication::gather_all(const double* values, int n, std::vector<double>& all) const {
  const Stopwatch watch(spent_.reduce);
  all.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(size_));
  MPI_Allgather(values, n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, MPI_COMM_WORLD);
}

void MpiCommunication::sum(double* values, int n) const {
  // Every process adds the parts in process order, so the sum is the same on all of them and
  // in every run on this process count.
  std::vector<double> all;
  gather_all(values, n, all);
  for (int k = 0; k < n; ++k) {
    double s = 0.0;
    for (int r = 0; r < size_; ++r) s += all[static_cast<std::size_t>(r) * static_cast<std::size_t>(n) + static_cast<std::size_t>(k)];
    values[k] = s;
  }
}

void MpiCommunication::sum_held(double* values, int n) const {
  const Stopwatch watch(spent_.reduce);
  if (n > 0) MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}

double MpiCommunication::min(double v) const {
  const Stopwatch watch(spent_.reduce);
  double out = v;
  MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

double MpiCommunication::max(double v) const {
  const Stopwatch watch(spent_.reduce);
  double out = v;
  MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

std::string MpiCommunication::first_message(const std::string& message) const {
  const int mine = message.empty() ? size_ : rank_;
  int first = size_;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == size_) return {};
  int length = rank_ == first ? static_cast<int>(message.size()) : 0;
  MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
  std::string out = rank_ == first ? message : std::string(static_cast<std::size_t>(length), ' ');
  MPI_Bcast(out.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
  return out;
}

void MpiCommunication::collect(Model& m, int root, ContactList* local_contacts, unsigned parts) {
  const bool zones = parts & kZoneState, with_contacts = parts & kContactState;
  if (!m.part.decomposed()) return;
  const Stopwatch watch(spent_.collect);
  // What this process owns: per block its position, motion, gridpoints and zones; then its contacts.
  std::vector<std::byte> mine;
  put<std::int64_t>(mine, static_cast<std::int64_t>(m.part.owned_blocks.size()));
  for (int b : m.part.owned_blocks) {
    const Block& B = m.blocks[static_cast<std::size_t>(b)];
    put<std::int32_t>(mine, b);
    pack(fields::kBlockFields, B, true, mine);
    for (int i = B.first_gp; i < B.first_gp + B.n_gp; ++i) pack(fields::kGridPointFields, m.gp[static_cast<std::size_t>(i)], true, mine);
    if (zones)
      for (int i = B.first_zone; i < B.first_zone + B.n_zone; ++i) pack(fields::kZoneFields, m.zones[static_cast<std::size_t>(i)], true, mine);
  }
  std::int64_t owned_contacts = 0;
  if (with_contacts)
    for (const Contact& c : m.contacts.items) owned_contacts += owned_contact(m, c);
  put<std::int64_t>(mine, owned_contacts);
  // Each contact's fields, then its joint-law state. The stride is the same on every process (the
  // same joint models); it travels so that a mismatch stops here instead of misreading states.
  const std::size_t stride = m.contacts.states.stride();
  put<std::int64_t>(mine, static_cast<std::int64_t>(stride));
  if (with_contacts)
    for (std::size_t i = 0; i < m.contacts.items.size(); ++i)
      if (owned_contact(m, m.contacts.items[i])) {
        pack(fields::kContactFields, m.contacts.items[i], false, mine);
        mine.insert(mine.end(), m.contacts.states.at(i), m.contacts.states.at(i) + stride);
      }
  if (mine.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("collecting the model state: one process's part exceeds 2 GB");
  const int count = static_cast<int>(mine.size());
  const bool receive = root < 0 || rank_ == root;
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(static_cast<std::size_t>(size_), 0);
  if (root < 0) MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  else MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, MPI_COMM_WORLD);
  std::vector<std::byte> all;
  if (receive) {
    for (int r = 1; r < size_; ++r) displs[static_cast<std::size_t>(r)] = displs[static_cast<std::size_t>(r) - 1] + counts[static_cast<std::size_t>(r) - 1];
    all.resize(static_cast<std::size_t>(displs.back()) + static_cast<std::size_t>(counts.back()));
  }
  if (root < 0)
    MPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
  else
    MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, root, MPI_COMM_WORLD);
  if (!receive) return;
  ContactList gathered;
  gathered.states.reset(stride, 0);
  for (int r = 0; r < size_; ++r) {
    const std::byte* in = all.data() + displs[static_cast<std::size_t>(r)];
    const auto blocks = take<std::int64_t>(in);
    for (std::int64_t k = 0; k < blocks; ++k) {
      Block& B = m.blocks[static_cast<std::size_t>(take<std::int32_t>(in))];
      in = unpack(fields::kBlockFields, B, true, in);
      for (int i = B.first_gp; i < B.first_gp + B.n_gp; ++i) in = unpack(fields::kGridPointFields, m.gp[static_cast<std::size_t>(i)], true, in);
      if (zones)
        for (int i = B.first_zone; i < B.first_zone + B.n_zone; ++i) in = unpack(fields::kZoneFields, m.zones[static_cast<std::size_t>(i)], true, in);
    }
    const auto nc = take<std::int64_t>(in);
    if (take<std::int64_t>(in) != static_cast<std::int64_t>(stride)) {
      // Only the receiving processes see it (a collect to process 0 leaves the others going on
      // to the next exchange): an exception here would leave them waiting, so the run stops.
      std::fprintf(stderr, "rockdem: internal error: collecting the model state, process %d sent joint-law states of another size than process %d's %zu bytes\n",
                   r, rank_, stride);
      MPI_Abort(MPI_COMM_WORLD, 70);
    }
    for (std::int64_t k = 0; k < nc; ++k) {
      Contact c;
      in = unpack(fields::kContactFields, c, false, in);
      gathered.items.push_back(std::move(c));
      gathered.states.push_back(in);
      in += stride;
    }
  }
  if (!with_contacts) return;
  // In the serial run's order, each state with its contact.
  std::vector<std::size_t> order(gathered.items.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return serial_order(m, gathered.items[a], gathered.items[b]); });
  ContactList contacts;
  contacts.items.reserve(order.size());
  contacts.states.reset(stride, 0);
  contacts.states.reserve(order.size());
  for (std::size_t i : order) {
    contacts.items.push_back(std::move(gathered.items[i]));
    contacts.states.push_back(gathered.states.at(i));
  }
  if (local_contacts) *local_contacts = m.contacts.take();
  m.contacts.restore(std::move(contacts));
}

}  // namespace rockdem
