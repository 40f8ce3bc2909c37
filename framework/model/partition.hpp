#pragma once
// Which part of the model this process computes, in a domain-decomposed run (framework/parallel/
// fills it; a serial run leaves it empty and computes everything). Every process holds the whole
// model's arrays, so that block, gridpoint and zone positions, and the contact keys, are the same on
// every rank count; a process steps only the blocks it owns, keeps the blocks within contact reach
// of them (its ghosts) current by receiving their positions and velocities every step, and leaves
// the rest as they were. Physics code asks this table, never a communicator.
#include <array>
#include <cstdint>
#include <vector>

namespace rockdem {

struct Model;

struct Partition {
  enum Role : std::uint8_t { owned = 0, ghost = 1, elsewhere = 2 };
  std::vector<std::uint8_t> role;    // per block position; empty: serial, every block owned
  std::vector<int> owner;            // per block position: the owning process
  int rank = 0;                      // this process
  // Gridpoints and zones of the owned blocks, as ranges [first, last) merged where contiguous.
  std::vector<std::array<int, 2>> gp_ranges, zone_ranges, block_ranges;
  std::vector<int> owned_blocks;     // positions, ascending
  std::vector<int> ghost_blocks;     // positions, ascending (set at each contact detection)

  bool decomposed() const { return !role.empty(); }
  bool owns(int block) const { return role.empty() || role[static_cast<std::size_t>(block)] == owned; }
  // Owned or ghost: its state is current on this process.
  bool current(int block) const { return role.empty() || role[static_cast<std::size_t>(block)] != elsewhere; }
};

// Sets `owner` and `rank`, the owned roles (ghosts are found later, at each contact detection) and
// the owned ranges; with an empty `owner` the model is serial again.
void assign_owners(Model& m, std::vector<int> owner, int rank);

// Calls f(i) for every gridpoint (zone, block) this process owns, in ascending order.
template <class F>
void for_owned_gridpoints(const Model& m, F&& f);
template <class F>
void for_owned_zones(const Model& m, F&& f);
template <class F>
void for_owned_blocks(const Model& m, F&& f);

}  // namespace rockdem
