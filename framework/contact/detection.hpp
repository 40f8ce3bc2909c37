#pragma once
// Contact detection and contact geometry.
//
// Broad phase: block bounding boxes binned on a uniform grid (cost ~ linear in the block count).
// Narrow phase: every boundary gridpoint of one block against the boundary edges of the other, both
// ways (edge-to-edge contact is the row of point contacts of both edges, as in UDEC). A point's own
// edge that faces an edge of the other block pairs with it and takes its normal (the common plane
// of the two faces); a corner whose edges face nothing is measured against the other block's
// rounded corners, and two corners against each other push along the line joining their rounding
// centres (UDEC). docs/engine.md says why.
//
// Contact length: each contact owns the part of the interface nearest to it: the two half-edges
// next to its gridpoint, clipped to the band around the contact line where the other block's
// surface actually is, and shared evenly where touching contacts of both blocks cover the same
// stretch. Stress is the joint-law state; force = stress x length. Because lengths are clipped to
// the real overlap and never derived as force / length, a block edge sliding past a gridpoint of the
// other block cannot produce the shrinking-length stress spike of the CNWRA report (Figure 4-4).
#include "framework/model/model.hpp"

namespace rockdem {

struct DetectionSettings {
  double distance = 1e-3;  // detection distance: rounding length + tolerance [m]
};

// Find all contacts, merge them into the store (persisting law state by key) and compute lengths.
// Contacts that are closed in the joint law are kept even beyond the detection distance (a dilating
// joint stays in contact); open ones beyond it are dropped.
// With threads > 1 the narrow phase, the contact lengths' stretches and the boundary table run on
// that many threads (core/threads.hpp), with the contacts in the order one thread finds them.
std::size_t detect_contacts(Model& m, const DetectionSettings& s, int threads = 1);

// Update, for the current positions, each contact's projection onto the other block (edge, s,
// normal), walking to neighbouring edges as the point slides. Cheap; called every step.
void update_contact_geometry(Model& m, int threads = 1);

// Recompute contact lengths (coverage sharing among touching contacts).
void update_contact_lengths(Model& m, const DetectionSettings& s, int threads = 1);

// Candidate block pairs (i < j) whose boxes, grown by `margin`, overlap.
std::vector<std::pair<int, int>> broad_phase(const Model& m, double margin);

}  // namespace rockdem
