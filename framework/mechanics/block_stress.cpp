#include "framework/mechanics/block_stress.hpp"

#include <limits>

#include "framework/model/model.hpp"

namespace rockdem {

bool block_stress_known(const Block& b) { return !b.rigid || (!b.fixed && b.prescribed == 0); }

std::vector<Voigt3> block_mean_stress(const Model& m) {
  std::vector<Voigt3> out(m.blocks.size(), Voigt3::Zero());
  for (std::size_t bi = 0; bi < m.blocks.size(); ++bi) {
    const Block& b = m.blocks[bi];
    if (!b.rigid) {
      double area = 0.0;
      for (int z = b.first_zone; z < b.first_zone + b.n_zone; ++z) {
        const Zone& zn = m.zones[static_cast<std::size_t>(z)];
        out[bi] += zn.area * zn.stress;
        area += zn.area;
      }
      if (area > 0.0) out[bi] /= area;
      continue;
    }
    if (!block_stress_known(b)) {
      out[bi].setConstant(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    double area = 0.0;  // present area of the boundary loop (counter-clockwise: positive)
    const std::size_t n = b.boundary.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2& p = m.gp[static_cast<std::size_t>(b.boundary[i])].x;
      const Vec2& q = m.gp[static_cast<std::size_t>(b.boundary[(i + 1) % n])].x;
      area += 0.5 * cross(p, q);
    }
    if (!(area > 0.0)) continue;
    double sxx = 0.0, syy = 0.0, sxy = 0.0;
    for (int k = b.first_gp; k < b.first_gp + b.n_gp; ++k) {
      const GridPoint& g = m.gp[static_cast<std::size_t>(k)];
      const Vec2 r = g.x - b.xc;
      sxx += r.x() * g.f.x();
      syy += r.y() * g.f.y();
      sxy += 0.5 * (r.x() * g.f.y() + r.y() * g.f.x());
    }
    out[bi] = Voigt3(sxx, syy, sxy) / area;
  }
  return out;
}

}  // namespace rockdem
