#pragma once
// The broad phase of contact detection, and the buffers a detection pass reuses.
//
// Block boxes (grown by the detection margin) are binned on a uniform grid of cells about the
// mean block size, laid over the boxes' extent as one flat array (a counting sort of the
// blocks by cell, no hash map); a pair is reported only from the cell holding the lower-left
// corner of its boxes' intersection, so each candidate pair comes out once without a set. The
// cost of a pass is then linear in the number of blocks, and its arrays are kept from one pass
// to the next so that a pass allocates nothing once the model has been seen.
#include <cstdint>
#include <utility>
#include <vector>

#include "framework/model/model.hpp"

namespace rockdem {

// Candidate block pairs (i < j) whose boxes, grown by `margin`, overlap; sorted by (i, j).
// `pairs` is overwritten (its storage reused).
void broad_phase_pairs(const Model& m, double margin, std::vector<std::pair<int, int>>& pairs);

// Storage a detection pass fills and empties again, kept between passes (one set per thread):
// reallocating the contact list every pass cost page faults on fresh memory that grew with the
// model (a third of a pass on 16k blocks).
struct DetectionBuffers {
  std::vector<Contact> found;
  std::vector<std::pair<int, int>> pairs;
  std::vector<std::vector<Contact>> chunks;  // a threaded pass: the contacts of each stretch of pairs
};
DetectionBuffers& detection_buffers();

// The contact-length pass (update_contact_lengths) groups contacts into clusters (one block pair,
// normals within 30 degrees). Its storage, kept between passes: a hash map of block pairs with a
// vector per cluster, rebuilt every pass, made the pass grow 2.6 times per block from 1k to 16k
// blocks (docs/performance.md).
struct ClusterSpan {
  int cluster;
  std::size_t c;   // the contact
  double lo, hi;   // its stretch along the cluster tangent, absolute coordinate
  double at;       // the contact point's own coordinate
  bool touching;
};
struct ClusterHead {
  Vec2 n;    // the cluster's normal (from the lower block id's side)
  int next;  // the block pair's next cluster, -1: none
};
// Block pair (a << 32 | b) -> first cluster: open addressing in one flat array.
class PairTable {
 public:
  void reset(std::size_t expected);  // empty, room for `expected` pairs
  int& at(std::int64_t key);         // the pair's entry, -1 when new
 private:
  std::vector<std::int64_t> keys_;
  std::vector<int> values_;
};
struct ClusterBuffers {
  PairTable pairs;
  std::vector<ClusterHead> clusters;
  std::vector<int> cluster_of;      // per contact
  std::vector<ClusterSpan> spans;   // per contact
  std::vector<std::size_t> start, cursor;  // counting sort of the spans by cluster
  std::vector<const ClusterSpan*> sorted, touching;
  std::vector<double> cuts;  // shares of coincident points' cells
};
ClusterBuffers& cluster_buffers();

}  // namespace rockdem
