#pragma once
// The broad phase of contact detection, and the buffers a detection pass reuses.
//
// Block boxes (grown by the detection margin) are binned on a uniform grid of cells about the
// mean block size, laid over the boxes' extent as one flat array (a counting sort of the
// blocks by cell, no hash map); a pair is reported only from the cell holding the lower-left
// corner of its boxes' intersection, so each candidate pair comes out once without a set. The
// cost of a pass is then linear in the number of blocks, and its arrays are kept from one pass
// to the next so that a pass allocates nothing once the model has been seen.
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
};
DetectionBuffers& detection_buffers();

}  // namespace rockdem
