#pragma once
// A small Model built by hand for the output tests (no case file, no mesher): a rigid unit square
// (block 0, gridpoints 0-3) and, on top of it, a deformable unit square of two constant-strain
// triangles (block 1, gridpoints 4-7, zones 0-1), with three contacts (elastic, slipping, open)
// under one Coulomb joint model.
#include <cstring>
#include <memory>
#include <vector>

#include "framework/model/model.hpp"
#include "models/joint_laws/coulomb_slip.hpp"

namespace rockdem::test {

inline Model make_io_test_model() {
  Model m;
  m.thickness = 1.0;
  m.gravity = Vec2(0.0, -9.81);

  auto add_gp = [&](double x, double y, int b, LocalIndex l) {
    GridPoint g;
    g.x0 = g.x = Vec2(x, y);
    g.block = b;
    g.local = l;
    m.gp.push_back(g);
  };
  Block r;
  r.id = BlockId{0};
  r.name = "base";
  r.rigid = true;
  r.group = 0;
  r.first_gp = 0;
  r.n_gp = 4;
  r.boundary = {0, 1, 2, 3};
  r.density = 2600.0;
  r.mass = 2600.0;
  r.inertia = 2600.0 / 6.0;
  r.xc0 = r.xc = Vec2(0.5, 0.5);
  r.rest_offsets = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
  add_gp(0, 0, 0, 0);
  add_gp(1, 0, 0, 1);
  add_gp(1, 1, 0, 2);
  add_gp(0, 1, 0, 3);
  m.blocks.push_back(r);

  Block d;
  d.id = BlockId{1};
  d.name = "top";
  d.rigid = false;
  d.group = 1;
  d.first_gp = 4;
  d.n_gp = 4;
  d.first_zone = 0;
  d.n_zone = 2;
  d.boundary = {4, 5, 6, 7};
  d.density = 2600.0;
  d.mass = 2600.0;
  d.xc0 = d.xc = Vec2(0.5, 1.5);
  add_gp(0, 1, 1, 0);
  add_gp(1, 1, 1, 1);
  add_gp(1, 2, 1, 2);
  add_gp(0, 2, 1, 3);
  for (int i = 4; i < 8; ++i) m.gp[static_cast<std::size_t>(i)].mass = 2600.0 / 4;
  m.blocks.push_back(d);

  Zone z0, z1;
  z0.n = {4, 5, 6};
  z1.n = {4, 6, 7};
  z0.area = z1.area = 0.5;
  m.zones = {z0, z1};

  CoulombSlip::Params p{};
  p.kn = 1e10;
  p.ks = 1e10;
  p.friction = 0.6;
  m.contacts.models.push_back(std::make_unique<JointModel>(std::make_unique<JointLawAdapter<CoulombSlip>>(p),
                                                           std::vector<std::unique_ptr<EffectBase>>{}));
  m.contacts.model_names = {"rock_joint"};
  m.contacts.group_names = {"base", "top"};
  m.contacts.assignments = {{-1, -1, 0}};

  std::vector<Contact> cs(3);
  // Gridpoints 4 and 5 of the top block on the base's top edge (boundary position 2: (1,1)->(0,1)).
  cs[0].key = {BlockId{1}, 0, BlockId{0}};
  cs[0].point = 4;
  cs[0].other = 0;
  cs[0].edge = 2;
  cs[0].s = 1.0;
  cs[1].key = {BlockId{1}, 1, BlockId{0}};
  cs[1].point = 5;
  cs[1].other = 0;
  cs[1].edge = 2;
  cs[1].s = 0.0;
  // Corner 2 of the base against the top block's bottom edge (boundary position 0).
  cs[2].key = {BlockId{0}, 2, BlockId{1}, 1};
  cs[2].point = 2;
  cs[2].other = 1;
  cs[2].edge = 0;
  cs[2].s = 1.0;
  cs[2].normal = Vec2(0.0, -1.0);
  for (auto& c : cs) {
    c.length = 0.5;
    c.joint = 0;
  }
  m.contacts.merge(std::move(cs));  // initialises each contact's joint-law state
  return m;
}

// Fills the evolving state of `m` (positions, velocities, stresses, joint state, ...) with values
// that differ per item and field, so that a swapped or dropped field shows in a comparison.
inline void fill_io_test_state(Model& m, double seed) {
  double k = seed;
  auto next = [&k] { return k += 0.1234567891011; };  // distinct, non-round doubles
  m.time = next();
  m.step = 4242;
  m.gravity = Vec2(next(), next());
  for (auto& g : m.gp) {
    g.x = g.x0 + Vec2(1e-3 * next(), -1e-3 * next());
    g.v = Vec2(next(), next());
    g.f = Vec2(next(), next());
    g.mass = next();
    g.stiffness = next();
    g.fixed_x = g.local == 0;
    g.fixed_y = g.local == 1;
    g.prescribed = g.local == 2;
  }
  for (auto& b : m.blocks) {
    b.xc = b.xc0 + Vec2(next(), next());
    b.vc = Vec2(next(), next());
    b.fc = Vec2(next(), next());
    b.theta = next();
    b.omega = next();
    b.moment = next();
    b.mass = next();
    b.inertia = next();
    b.mass_scale = next();
    b.fixed = b.id == BlockId{0};
    b.prescribed = b.id == BlockId{1};
  }
  for (auto& z : m.zones) {
    z.stress = Voigt3(-1e6 * next(), -2e6 * next(), 3e5 * next());
    z.szz = -9e5 * next();
    z.strain = Voigt3(-1e-4 * next(), -2e-4 * next(), 3e-5 * next());
    for (std::size_t i = 0; i < z.material_state.size(); ++i)
      z.material_state[i] = static_cast<std::byte>((i * 37 + static_cast<std::size_t>(seed * 10)) & 0xff);
  }
  int ci = 0;
  for (auto& c : m.contacts.items) {
    std::byte* state = m.contacts.states.at(static_cast<std::size_t>(ci));
    for (std::size_t i = 0; i < m.contacts.states.stride(); ++i)
      state[i] = static_cast<std::byte>((i * 13 + 7 * static_cast<std::size_t>(ci) + 1) & 0xff);
    c.s = 0.25 * next();
    c.overlap = 1e-4 * next();
    c.length = next();
    c.span = 1.5 * next();
    c.response.sigma_n = 1e6 * next();
    c.response.tau = 1e5 * next();
    c.response.kn = 1e10 * next();
    c.response.ks = 1e9 * next();
    c.response.u_s = 1e-3 * next();
    c.response.u_n = -1e-5 * next();
    c.response.dilation = 1e-6 * next();
    c.response.dissipated = next();
    c.response.slipping = ci == 1;
    c.response.open = ci == 2;
    c.fresh = ci == 0;
    ++ci;
  }
}

}  // namespace rockdem::test
