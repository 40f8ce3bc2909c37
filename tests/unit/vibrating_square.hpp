// A free elastic square of 4 x 4 cells, given an initial velocity field that excites its highest
// modes (alternating signs), with no load: only damping and changes of mass change its energy.
// Shared by the time-step and mass tests.
#pragma once

#include <memory>

#include "framework/io/case.hpp"
#include "framework/mechanics/zones.hpp"
#include "models/rock/elastic.hpp"

namespace rockdem::test {

inline void build_vibrating_square(Model& m) {
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{2500.0, 20e9, 15e9}));
  add_deformable_block(m, mesh_rectangle(0.0, 0.0, 1.0, 1.0, 4, 4), 0, "square", 0);
  for (std::size_t i = 0; i < m.gp.size(); ++i) m.gp[i].v = Vec2(i % 2 ? 1e-3 : -1e-3, i % 3 ? 1e-3 : -1e-3);
}

}  // namespace rockdem::test
