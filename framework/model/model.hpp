#pragma once
// The state of a 2D block model: blocks (rigid or deformable), their gridpoints and zones, and the
// contacts between them. Physics routines take a Model& and never see MPI.
//
// Rigid blocks keep their polygon vertices as gridpoints too, slaved to the rigid-body motion, so
// that contact detection and contact forces treat every block alike: contacts act on gridpoints and
// on boundary edges (pairs of consecutive boundary gridpoints); a rigid block then sums the forces
// on its gridpoints into a force and a moment at its centroid.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "framework/model/contact.hpp"
#include "framework/model/partition.hpp"
#include "framework/core/types.hpp"

namespace rockdem {

class RockMaterialBase;  // framework/plugin_api/rock_material.hpp

struct GridPoint {
  Vec2 x0 = Vec2::Zero();  // initial position [m]
  Vec2 x = Vec2::Zero();   // current position [m]
  Vec2 v = Vec2::Zero();   // velocity [m/s]
  Vec2 f = Vec2::Zero();   // unbalanced force of this step [N per m of out-of-plane thickness]
  double mass = 0.0;       // lumped mass (after mass scaling) [kg/m]
  double stiffness = 0.0;  // sum of the stiffnesses acting on it, for the stable time step [N/m/m]
  int block = 0;           // position of its block in Model::blocks
  LocalIndex local = 0;    // index within its block (with the block's id, a decomposition-free key)
  bool fixed_x = false, fixed_y = false;
  bool prescribed = false;  // velocity set by a boundary condition, not by the equation of motion
};

// Constant-strain triangle (zone) of a deformable block.
struct Zone {
  std::array<int, 3> n{};  // gridpoint indices (counter-clockwise)
  double area = 0.0;       // initial area [m^2]
  Voigt3 stress = Voigt3::Zero();  // sxx, syy, sxy [Pa], tension positive (continuum convention)
  double szz = 0.0;                // out-of-plane stress (plane strain) [Pa]
  Voigt3 strain = Voigt3::Zero();  // accumulated small strain
  int material = 0;                // index into Model::materials
  alignas(8) std::array<std::byte, 64> material_state{};  // rock-material history (plasticity)
};

struct Block {
  BlockId id{};
  std::string name;
  bool rigid = true;
  int group = 0;                // joint/material group index (case-file `group`)
  std::vector<int> boundary;    // gridpoint indices of the boundary loop, counter-clockwise
  int first_gp = 0, n_gp = 0;   // gridpoints [first_gp, first_gp + n_gp)
  int first_zone = 0, n_zone = 0;
  double density = 0.0;         // [kg/m^3]
  // Rigid-body state (also filled for deformable blocks as diagnostics).
  double mass = 0.0, inertia = 0.0;  // [kg/m], [kg m^2 / m]
  Vec2 xc0 = Vec2::Zero(), xc = Vec2::Zero(), vc = Vec2::Zero(), fc = Vec2::Zero();
  double theta = 0.0, omega = 0.0, moment = 0.0;
  double mass_scale = 1.0;
  bool fixed = false;           // rigid block held in place
  // Rigid block driven by velocity histories: bit mask of the driven components (kDriveX,
  // kDriveY, kDriveSpin); the others follow the equation of motion.
  std::uint8_t prescribed = 0;
  static constexpr std::uint8_t kDriveX = 1, kDriveY = 2, kDriveSpin = 4, kDriveAll = 7;
  std::vector<Vec2> rest_offsets;  // rigid: vertex offsets from the centroid at theta = 0
  // Per boundary edge i (from boundary[i] to boundary[i + 1]): the index of its label in
  // ContactStore::edge_labels (the joint set or named joint it lies on, or a rock bridge), -1 for
  // none. Empty for blocks without labels (hand-written blocks).
  std::vector<int> edge_joint;
  int edge_label(int edge) const { return edge_joint.empty() ? -1 : edge_joint[static_cast<std::size_t>(edge)]; }
};

struct Model {
  std::vector<Block> blocks;
  std::vector<GridPoint> gp;
  std::vector<Zone> zones;
  std::vector<std::unique_ptr<RockMaterialBase>> materials;
  ContactStore contacts;
  Vec2 gravity = Vec2::Zero();
  double time = 0.0;
  long step = 0;
  double thickness = 1.0;  // out-of-plane thickness [m] (2D: forces are per metre)
  Partition part;          // what this process computes (partition.hpp); empty: everything

  Model();
  ~Model();
  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;
};

namespace detail {
// f(i) for i in [0, n) in a serial run, else for i in the ranges.
template <class F>
void for_each_in(bool decomposed, std::size_t n, const std::vector<std::array<int, 2>>& ranges, F&& f) {
  if (!decomposed) {
    for (int i = 0, end = static_cast<int>(n); i < end; ++i) f(i);
    return;
  }
  for (const auto& r : ranges)
    for (int i = r[0]; i < r[1]; ++i) f(i);
}
// f(first, last) for [0, n) in a serial run, else for each of the ranges.
template <class F>
void for_ranges_in(bool decomposed, std::size_t n, const std::vector<std::array<int, 2>>& ranges, F&& f) {
  if (!decomposed) {
    if (n > 0) f(0, static_cast<int>(n));
    return;
  }
  for (const auto& r : ranges) f(r[0], r[1]);
}
}  // namespace detail

// Calls f(first, last) for each range [first, last) of gridpoints (zones, blocks) this process
// owns, ascending: one range [0, n) in a serial run. For loops that split a range over threads.
template <class F>
void for_owned_gridpoint_ranges(const Model& m, F&& f) {
  detail::for_ranges_in(m.part.decomposed(), m.gp.size(), m.part.gp_ranges, f);
}
template <class F>
void for_owned_zone_ranges(const Model& m, F&& f) {
  detail::for_ranges_in(m.part.decomposed(), m.zones.size(), m.part.zone_ranges, f);
}
template <class F>
void for_owned_block_ranges(const Model& m, F&& f) {
  detail::for_ranges_in(m.part.decomposed(), m.blocks.size(), m.part.block_ranges, f);
}

template <class F>
void for_owned_gridpoints(const Model& m, F&& f) {
  detail::for_each_in(m.part.decomposed(), m.gp.size(), m.part.gp_ranges, f);
}
template <class F>
void for_owned_zones(const Model& m, F&& f) {
  detail::for_each_in(m.part.decomposed(), m.zones.size(), m.part.zone_ranges, f);
}
template <class F>
void for_owned_blocks(const Model& m, F&& f) {
  detail::for_each_in(m.part.decomposed(), m.blocks.size(), m.part.block_ranges, f);
}

}  // namespace rockdem
