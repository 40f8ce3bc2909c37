#pragma once
// Contact points between blocks. A contact point is a boundary gridpoint (a corner of a rigid block
// or a boundary gridpoint of a deformable one) against a boundary edge of another block: paired
// with a facing edge (the common plane of the two faces), or, for a corner that faces no edge,
// against the other block's boundary with its corners rounded by the rounding length d (Cundall
// 1988, UDEC). Edge-to-edge contact is represented by the point contacts of both edges.
//
// Contacts are keyed by decomposition-free ids (block id of the point, its local gridpoint index,
// block id of the other block), so the same contact has the same key on any rank count and keeps
// its joint-law state while the point slides from one edge of the other block to the next.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "framework/core/types.hpp"
#include "framework/model/contact_index.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

// Two contact normals within 30 degrees (cosine above this) act along one plane: one interface's
// cluster, one contact of a corner that faces a block along both its edges, and the same contact
// when a corner's key passes to its other side (detection.cpp, ContactStore::merge).
inline constexpr double kSamePlaneCos = 0.866;

struct ContactKey {
  BlockId point_block{};
  LocalIndex point_local = 0;
  BlockId other_block{};
  // Which of the point's own edges the contact acts along: 0 for a point on a flat stretch of its
  // boundary, or for a corner the edge before it (loop position k-1 -> k); 1 the edge after it.
  // A corner nested in a concave corner of the other block touches it along both edges and then
  // has one contact per side.
  std::int32_t side = 0;
  bool operator==(const ContactKey&) const = default;
  bool operator<(const ContactKey& o) const {
    if (point_block != o.point_block) return point_block < o.point_block;
    if (point_local != o.point_local) return point_local < o.point_local;
    if (other_block != o.other_block) return other_block < o.other_block;
    return side < o.side;
  }
};

struct ContactKeyHash {
  std::size_t operator()(const ContactKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(static_cast<std::uint32_t>(id_value(k.point_block)));
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(k.point_local);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(id_value(k.other_block));
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(k.side);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

struct Contact {
  ContactKey key;
  int point = 0;        // gridpoint index of the contact point
  int point_loop = 0;   // position of that gridpoint in its block's boundary loop
  bool face_mode = false;  // own edge paired with a facing edge of the other block (see detection.cpp)
  int other = 0;        // block index of the other block
  int edge = 0;         // position in the other block's boundary loop of the edge's first point
  double s = 0.0;       // parameter along that edge (0..1) of the projection
  Vec2 normal = Vec2::UnitY();  // unit normal, from the other block toward the point
  double length = 0.0;  // contact length [m]; stresses times length give forces per metre
  double span = 0.0;    // the most length the contact can take: its own stretch along the joint [m]
                        // (bounds its stiffness for the stable time step whatever the coverage)
  double overlap = 0.0; // minus the signed distance to the other block's (rounded) boundary [m]
  int joint = 0;        // index of the joint model in ContactStore::models
  double pretouch_gap = 0.0;     // >0: found within the detection distance but not yet touching;
                                 // the joint law starts when this gap has closed [m]
  double pending_closure = 0.0;  // overlap found at creation, fed to the law as closure [m]
  // The joint-law history (base law and effects) is not here but in the list's ContactStates,
  // sized by the joint models the contacts use (below).
  JointResponse response;     // last response (stresses, offsets, slip/open)
  bool fresh = true;          // created at the last detection, law state just initialised

  // Force of the last response on the point's block [N per m of thickness]; the other block gets
  // the opposite at the projection point. Compression pushes the point away from the other block;
  // shear resists the relative slip (tangent t = (n_y, -n_x), the direction du_s is measured in).
  Vec2 force() const {
    const Vec2 t(normal.y(), -normal.x());
    return length * (response.sigma_n * normal - response.tau * t);
  }
  // The contact's state as a category for output (names in kContactStateNames). Open wins over
  // slipping: an open joint carries no shear stress, whatever the slip flag says.
  int state_category() const { return response.open ? 2 : (response.slipping ? 1 : 0); }
};

inline constexpr const char* kContactStateNames[3] = {"elastic", "slipping", "open"};

// The joint-law states of a contact list, item i's at at(i): one stretch of `stride()` bytes per
// contact, as many as the largest state among the store's joint models needs (base law and the
// effects composed with it, joint_law.hpp), not the most any model may have (kJointStateBytes).
// Kept apart from Contact so that a Coulomb-slip contact does not carry a Continuously-Yielding-
// with-wear one's 256 bytes through every step and every detection pass (LAMMPS keeps per-contact
// history apart from the neighbour list in the same way, sized by the pair style).
class ContactStates {
 public:
  ContactStates() = default;
  // n zeroed states of `stride` bytes (a multiple of kStateAlign).
  ContactStates(std::size_t stride, std::size_t n) { reset(stride, n); }
  void reset(std::size_t stride, std::size_t n) {
    chunks_ = (stride + kStateAlign - 1) / kStateAlign;
    data_.assign(chunks_ * n, Chunk{});
  }
  std::size_t stride() const { return chunks_ * kStateAlign; }
  std::size_t size() const { return chunks_ == 0 ? 0 : data_.size() / chunks_; }
  std::byte* at(std::size_t i) { return data_[i * chunks_].bytes; }
  const std::byte* at(std::size_t i) const { return data_[i * chunks_].bytes; }
  // Room for n states without reallocating (a list assembled state by state).
  void reserve(std::size_t n) { data_.reserve(chunks_ * n); }
  // Appends one state (stride() bytes from `s`, or zeros).
  void push_back(const std::byte* s = nullptr) {
    data_.resize(data_.size() + chunks_);
    if (s) std::memcpy(at(size() - 1), s, stride());
  }
  void swap(ContactStates& o) noexcept {
    std::swap(chunks_, o.chunks_);
    data_.swap(o.data_);
  }
  bool operator==(const ContactStates&) const = default;

  static constexpr std::size_t kStateAlign = 16;  // as JointStateBlock's

 private:
  struct alignas(kStateAlign) Chunk {
    std::byte bytes[kStateAlign]{};
    bool operator==(const Chunk& o) const { return std::memcmp(bytes, o.bytes, kStateAlign) == 0; }
  };
  std::size_t chunks_ = 0;
  std::vector<Chunk> data_;
};

// A contact list with its states, as it moves between the store and what holds a copy (the last
// good state, a collect's own list, a checkpoint being read).
struct ContactList {
  std::vector<Contact> items;
  ContactStates states;
};

// What a block edge made by the rock-mass generator lies on: a joint set or named joint (by its
// name; empty for a glued cut that is no joint: a region's or an opening's outline) and whether
// it is a rock bridge (glued) rather than the joint's trace.
struct EdgeLabel {
  std::string joint;
  bool bridge = false;
  bool operator==(const EdgeLabel&) const = default;
};

// Which joint model acts between two block groups, and, if `labels` is not empty, only at
// contacts against an edge with one of these labels (indices in ContactStore::edge_labels).
struct JointAssignment {
  int group_a = -1, group_b = -1;  // -1: any group
  int model = 0;
  std::vector<int> labels{};
};


class ContactStore {
 public:
  std::vector<Contact> items;
  ContactStates states;  // items[i]'s joint-law state at states.at(i)
  // Shared so that a stage can put in force other parameter values of the same law (the per-stage
  // rows of the report's Table 4-2) while the contacts keep their state.
  std::vector<std::shared_ptr<const JointModel>> models;
  std::vector<std::string> model_names;  // the case-file names of the joint models
  std::vector<JointAssignment> assignments;
  std::vector<std::string> group_names;  // block-group names by index, for messages
  std::vector<EdgeLabel> edge_labels;    // the labels Block::edge_joint refers to
  double rounding = 1e-3;         // corner rounding length d [m]
  double tolerance = 0.0;         // extra detection distance beyond d [m]

  // Joint model for a pair of groups at an edge with label `edge_label` (-1: none): the first
  // assignment for that label whose groups match wins over the first group assignment (one
  // without labels); InputError if none matches.
  int model_for(int group_a, int group_b, int edge_label = -1) const;

  // Replace the contact list with `found`, carrying over the law state of contacts whose key
  // persists (or whose corner's key passed to its other side: contact_store.cpp) and
  // initialising the state of new ones. Returns the number of new contacts.
  std::size_t merge(std::vector<Contact>&& found);

  // Bytes of state per contact for these joint models: the largest of their states, rounded up
  // to ContactStates::kStateAlign (at least one stretch of it).
  std::size_t state_stride() const;

  const Contact* find(const ContactKey& k) const;
  // With the caller's own look-up hint (threads of one detection each keep theirs).
  const Contact* find(const ContactKey& k, std::size_t& hint) const;

  // Replace the contact list as it is, law state included (checkpoint restore), and rebuild the
  // index; unlike merge() nothing is re-initialised. The states must be one per item.
  void restore(ContactList&& all);
  // The list and its states, moved out (the store is left empty).
  ContactList take();
  // A copy of the list and its states.
  ContactList copy() const { return {items, states}; }

 private:
  ContactIndex index_;
  ContactStates spare_states_;  // the states' storage of the list before the last merge, reused
  std::vector<std::ptrdiff_t> continues_;  // merge(): per found contact, the old one it continues
  std::vector<char> claimed_;              // merge(): per old contact, whether one continues it
};

}  // namespace rockdem
