#include "framework/mechanics/zones.hpp"

#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/core/threads.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

namespace {

// CST shape-function gradients scaled by twice the area: dN_i/dx = b[i]/(2A), dN_i/dy = c[i]/(2A),
// with b_i = y_j - y_k, c_i = x_k - x_j for (i, j, k) cyclic (Zienkiewicz & Taylor, FEM vol. 1,
// ch. 6). Returns 2A (positive for a counter-clockwise zone).
double cst_gradients(const Vec2& x0, const Vec2& x1, const Vec2& x2, double b[3], double c[3]) {
  b[0] = x1.y() - x2.y();
  b[1] = x2.y() - x0.y();
  b[2] = x0.y() - x1.y();
  c[0] = x2.x() - x1.x();
  c[1] = x0.x() - x2.x();
  c[2] = x1.x() - x0.x();
  return cross(x1 - x0, x2 - x0);
}

// Rotate a symmetric in-plane tensor given as (xx, yy, xy) by the angle whose cosine and sine are
// c and s: T <- R T R^T.
void rotate_tensor(double c, double s, double& txx, double& tyy, double& txy) {
  const double cc = c * c, ss = s * s, cs = c * s;
  const double xx = cc * txx - 2.0 * cs * txy + ss * tyy;
  const double yy = ss * txx + 2.0 * cs * txy + cc * tyy;
  const double xy = cs * (txx - tyy) + (cc - ss) * txy;
  txx = xx;
  tyy = yy;
  txy = xy;
}

void check_material(const Model& m, int material) {
  if (material < 0 || material >= static_cast<int>(m.materials.size()) || !m.materials[material])
    throw InputError("add_deformable_block: material index " + std::to_string(material) +
                     " does not name a defined rock material");
}

}  // namespace

Eigen::Matrix3d plane_strain_elasticity(double bulk, double shear) {
  const double a1 = bulk + 4.0 * shear / 3.0, a2 = bulk - 2.0 * shear / 3.0;
  Eigen::Matrix3d d;
  d << a1, a2, 0.0, a2, a1, 0.0, 0.0, 0.0, shear;
  return d;
}

int add_rigid_block(Model& m, const Polygon& polygon, double density, const std::string& name, int group) {
  if (!(density > 0.0) || !std::isfinite(density))
    throw InputError("block '" + name + "': density must be positive, got " + std::to_string(density));
  Polygon p = polygon;
  if (!is_simple(p))
    throw InputError("block '" + name + "': outline is not a simple polygon (needs >= 3 distinct vertices, "
                     "non-zero area and no crossing or touching edges)");
  make_ccw(p);
  Block b;
  b.id = static_cast<BlockId>(m.blocks.size());
  b.name = name;
  b.rigid = true;
  b.group = group;
  b.density = density;
  b.mass = density * signed_area(p);
  b.inertia = density * second_moments(p).polar();
  b.xc0 = b.xc = polygon_centroid(p);
  b.first_gp = static_cast<int>(m.gp.size());
  b.n_gp = static_cast<int>(p.size());
  b.first_zone = static_cast<int>(m.zones.size());
  b.n_zone = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    GridPoint g;
    g.x0 = g.x = p[i];
    g.block = static_cast<int>(m.blocks.size());
    g.local = static_cast<LocalIndex>(i);
    b.boundary.push_back(static_cast<int>(m.gp.size()));
    b.rest_offsets.push_back(p[i] - b.xc0);
    m.gp.push_back(g);
  }
  m.blocks.push_back(std::move(b));
  return static_cast<int>(m.blocks.size()) - 1;
}

int add_deformable_block(Model& m, const TriMesh& mesh, int material, const std::string& name, int group) {
  check_material(m, material);
  const RockMaterialBase& mat = *m.materials[material];
  const double rho = mat.density();
  if (mesh.triangles.empty() || mesh.boundary.size() < 3)
    throw InputError("block '" + name + "': empty zone mesh");
  Block b;
  b.id = static_cast<BlockId>(m.blocks.size());
  b.name = name;
  b.rigid = false;
  b.group = group;
  b.density = rho;
  b.first_gp = static_cast<int>(m.gp.size());
  b.n_gp = static_cast<int>(mesh.nodes.size());
  b.first_zone = static_cast<int>(m.zones.size());
  b.n_zone = static_cast<int>(mesh.triangles.size());
  for (size_t i = 0; i < mesh.nodes.size(); ++i) {
    GridPoint g;
    g.x0 = g.x = mesh.nodes[i];
    g.block = static_cast<int>(m.blocks.size());
    g.local = static_cast<LocalIndex>(i);
    m.gp.push_back(g);
  }
  for (int v : mesh.boundary) b.boundary.push_back(b.first_gp + v);

  double area = 0.0;
  Vec2 first_moment = Vec2::Zero();
  for (const auto& t : mesh.triangles) {
    Zone z;
    z.n = {b.first_gp + t[0], b.first_gp + t[1], b.first_gp + t[2]};
    const Vec2 &p0 = mesh.nodes[t[0]], &p1 = mesh.nodes[t[1]], &p2 = mesh.nodes[t[2]];
    z.area = 0.5 * cross(p1 - p0, p2 - p0);
    if (!(z.area > 0.0))
      throw InputError("block '" + name + "': zone " + std::to_string(m.zones.size() - b.first_zone) +
                       " has non-positive area (zones must be counter-clockwise)");
    z.material = material;
    mat.init(z.material_state.data());
    for (int k = 0; k < 3; ++k) m.gp[z.n[k]].mass += rho * z.area / 3.0;
    area += z.area;
    first_moment += z.area * (p0 + p1 + p2) / 3.0;
    m.zones.push_back(z);
  }
  b.mass = rho * area;
  b.xc0 = b.xc = first_moment / area;
  double inertia = 0.0;
  for (const auto& t : mesh.triangles) {
    const Polygon tri{mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]};
    const double a = signed_area(tri);
    inertia += rho * (second_moments(tri).polar() + a * (polygon_centroid(tri) - b.xc0).squaredNorm());
  }
  b.inertia = inertia;
  m.blocks.push_back(std::move(b));
  return static_cast<int>(m.blocks.size()) - 1;
}

namespace {

// One zone's update (steps 1-4 of zone_forces) and the forces it puts on its three gridpoints:
// force(k, fx, fy) for corner k, whose gridpoint takes -(fx, fy) (one thread: at once; several:
// later, in zone order).
template <class Force>
void zone_update(Model& m, int iz, double dt, double beta_stiffness, Force&& force) {
  Zone& z = m.zones[static_cast<std::size_t>(iz)];
  const GridPoint& g0 = m.gp[z.n[0]];
  const GridPoint& g1 = m.gp[z.n[1]];
  const GridPoint& g2 = m.gp[z.n[2]];
  double b[3], c[3];
  const double a2 = cst_gradients(g0.x, g1.x, g2.x, b, c);
  if (!(a2 > 0.0)) {
    const Block& blk = m.blocks[g0.block];
    const std::string what = std::isfinite(a2) ? "turned inside out (area " + std::to_string(0.5 * a2) + " m^2)"
                                               : "has non-finite gridpoint positions";
    throw InstabilityError("zone " + std::to_string(iz - blk.first_zone) + " of block '" + blk.name + "' " +
                           what + " at step " + std::to_string(m.step));
  }
  // Strain rate and spin on the mid-step configuration x - v dt/2 (see zones.hpp).
  const double h = 0.5 * dt;
  double bm[3], cm[3];
  const double a2m = cst_gradients(g0.x - h * g0.v, g1.x - h * g1.v, g2.x - h * g2.v, bm, cm);
  const double inv = 1.0 / a2m;
  const Vec2* v[3] = {&g0.v, &g1.v, &g2.v};
  // Velocity gradient L_ij = sum_n v_i^n dN^n/dx_j.
  double lxx = 0.0, lxy = 0.0, lyx = 0.0, lyy = 0.0;
  for (int k = 0; k < 3; ++k) {
    lxx += v[k]->x() * bm[k];
    lxy += v[k]->x() * cm[k];
    lyx += v[k]->y() * bm[k];
    lyy += v[k]->y() * cm[k];
  }
  const Voigt3 rate(lxx * inv, lyy * inv, (lxy + lyx) * inv);  // engineering shear rate
  const double spin = 0.5 * (lyx - lxy) * inv;                  // counter-clockwise [rad/s]

  // On the mid-step configuration a rigid turn by theta has spin (2/dt) tan(theta/2) (Cayley
  // transform): the stress turns by exactly theta, whose cosine and sine follow from
  // tau = tan(theta/2) without trigonometric functions: cos = (1 - tau^2)/(1 + tau^2),
  // sin = 2 tau/(1 + tau^2) (the atan, sin and cos they replace took 18 % of a laboratory DEM
  // run; docs/performance.md).
  const double tau = 0.5 * spin * dt;
  if (tau != 0.0) {
    const double inv1 = 1.0 / (1.0 + tau * tau);
    const double cr = (1.0 - tau * tau) * inv1, sr = 2.0 * tau * inv1;
    rotate_tensor(cr, sr, z.stress[0], z.stress[1], z.stress[2]);
    double exy = 0.5 * z.strain[2];
    rotate_tensor(cr, sr, z.strain[0], z.strain[1], exy);
    z.strain[2] = 2.0 * exy;
  }

  const RockMaterialBase& mat = *m.materials[z.material];
  const Voigt3 de = rate * dt;
  if (dt != 0.0) {
    mat.update(z.material_state.data(), de, z.stress, z.szz);
    z.strain += de;
  }
  Voigt3 s = z.stress;
  if (beta_stiffness != 0.0)
    s += beta_stiffness * plane_strain_elasticity(mat.bulk_modulus(), mat.shear_modulus()) * rate;

  // f_n = -A B_n^T sigma = -(1/2) (b_n sxx + c_n sxy, c_n syy + b_n sxy): the 2A of the
  // gradients cancels the area, leaving the traction on the side opposite node n.
  for (int k = 0; k < 3; ++k) force(k, 0.5 * (b[k] * s[0] + c[k] * s[2]), 0.5 * (c[k] * s[1] + b[k] * s[2]));
}

}  // namespace

// Which zone corners add to each gridpoint, for the threaded loops: the slots 3 iz + k (corner k
// of zone iz) of the owned zones, gridpoint by gridpoint in ascending zone order, so that a
// gridpoint summing its slots in this order adds what one thread's zone loop adds, in its order.
// Kept between steps; remade whenever the zones' corners, the gridpoints or the owned zones change
// (an excavation, a restart, a new partition): each threaded pass compares the corners it reads.
struct ZoneGather {
  std::vector<std::array<int, 3>> corners;      // per zone, as when made
  std::vector<std::array<int, 2>> zone_ranges;  // the owned zones then
  bool decomposed = false;
  std::size_t gridpoints = 0;
  std::vector<int> start;  // per gridpoint: its slots are slot[start[i] .. start[i + 1])
  std::vector<int> slot;
  std::vector<double> values;  // per slot (3 per zone) or per slot and direction (6 per zone)

  bool fits(const Model& m) const {
    return corners.size() == m.zones.size() && gridpoints == m.gp.size() && decomposed == m.part.decomposed() &&
           (!decomposed || zone_ranges == m.part.zone_ranges);
  }
  bool same_corners(const Model& m) const {
    for (std::size_t z = 0; z < m.zones.size(); ++z)
      if (corners[z] != m.zones[z].n) return false;
    return true;
  }
  void rebuild(const Model& m) {
    corners.resize(m.zones.size());
    for (std::size_t z = 0; z < m.zones.size(); ++z) corners[z] = m.zones[z].n;
    zone_ranges = m.part.zone_ranges;
    decomposed = m.part.decomposed();
    gridpoints = m.gp.size();
    start.assign(gridpoints + 1, 0);
    for_owned_zones(m, [&](int iz) {
      for (int g : m.zones[static_cast<std::size_t>(iz)].n) ++start[static_cast<std::size_t>(g) + 1];
    });
    for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    slot.resize(static_cast<std::size_t>(start.back()));
    std::vector<int> next(start.begin(), start.end() - 1);
    for_owned_zones(m, [&](int iz) {
      for (int k = 0; k < 3; ++k)
        slot[static_cast<std::size_t>(next[static_cast<std::size_t>(m.zones[static_cast<std::size_t>(iz)].n[static_cast<std::size_t>(k)])]++)] = 3 * iz + k;
    });
  }
};

// This thread's table (the loops' workers reach it through a reference).
ZoneGather& zone_gather() {
  thread_local ZoneGather g;
  return g;
}

void zone_forces(Model& m, double dt, double beta_stiffness, int threads) {
  if (threads <= 1) {
    for_owned_zones(m, [&](int iz) {
      const Zone& z = m.zones[static_cast<std::size_t>(iz)];
      zone_update(m, iz, dt, beta_stiffness, [&](int k, double fx, double fy) {
        GridPoint& g = m.gp[static_cast<std::size_t>(z.n[static_cast<std::size_t>(k)])];
        g.f.x() -= fx;
        g.f.y() -= fy;
      });
    });
    return;
  }
  // The zones on several threads, each writing its forces to its own slots; then each gridpoint,
  // on several threads too, takes its zones' forces in zone order, as the loop above adds them
  // (the same sums to the bit).
  ZoneGather& gather = zone_gather();
  std::vector<double>& forces = gather.values;
  forces.resize(6 * m.zones.size());
  std::atomic<bool> moved{false};
  for_owned_zone_ranges(m, [&](int first, int last) {
    threaded_for(threads, first, last, [&](std::ptrdiff_t iz) {
      const auto z = static_cast<std::size_t>(iz);
      if (z >= gather.corners.size() || gather.corners[z] != m.zones[z].n) moved.store(true, std::memory_order_relaxed);
      double* slot = &forces[6 * z];
      zone_update(m, static_cast<int>(iz), dt, beta_stiffness, [&](int k, double fx, double fy) {
        slot[2 * k] = fx;
        slot[2 * k + 1] = fy;
      });
    });
  });
  if (moved || !gather.fits(m)) gather.rebuild(m);
  for_owned_gridpoint_ranges(m, [&](int first, int last) {
    threaded_for(threads, first, last, [&](std::ptrdiff_t i) {
      GridPoint& g = m.gp[static_cast<std::size_t>(i)];
      for (int e = gather.start[static_cast<std::size_t>(i)]; e < gather.start[static_cast<std::size_t>(i) + 1]; ++e) {
        const auto k = static_cast<std::size_t>(gather.slot[static_cast<std::size_t>(e)]);
        g.f.x() -= forces[2 * k];
        g.f.y() -= forces[2 * k + 1];
      }
    });
  });
}

namespace {

// One zone's contribution to the stiffness of its three gridpoints (0 for an inverted zone, which
// zone_forces reports).
void zone_stiffness_of(const Model& m, int iz, double k[3]) {
  const Zone& z = m.zones[static_cast<std::size_t>(iz)];
  const GridPoint* g[3] = {&m.gp[z.n[0]], &m.gp[z.n[1]], &m.gp[z.n[2]]};
  k[0] = k[1] = k[2] = 0.0;
  double b[3], c[3];
  const double a2 = cst_gradients(g[0]->x, g[1]->x, g[2]->x, b, c);
  if (!(a2 > 0.0)) return;
  const RockMaterialBase& mat = *m.materials[z.material];
  const double a1 = mat.bulk_modulus() + 4.0 * mat.shear_modulus() / 3.0;
  const double al = mat.bulk_modulus() - 2.0 * mat.shear_modulus() / 3.0;
  const double gs = mat.shear_modulus();
  // K_mn = A B_m^T D B_n with B_n = [b 0; 0 c; c b]/(2A): K_mn = (D-weighted products)/(4A).
  const double f = 1.0 / (2.0 * a2);
  for (int mi = 0; mi < 3; ++mi) {
    double row_x = 0.0, row_y = 0.0;
    for (int n = 0; n < 3; ++n) {
      const double kxx = f * (a1 * b[mi] * b[n] + gs * c[mi] * c[n]);
      const double kxy = f * (al * b[mi] * c[n] + gs * c[mi] * b[n]);
      const double kyx = f * (al * c[mi] * b[n] + gs * b[mi] * c[n]);
      const double kyy = f * (a1 * c[mi] * c[n] + gs * b[mi] * b[n]);
      row_x += std::abs(kxx) + std::abs(kxy);
      row_y += std::abs(kyx) + std::abs(kyy);
    }
    k[mi] = std::max(row_x, row_y);
  }
}

}  // namespace

void zone_stiffness(Model& m, int threads) {
  auto add = [&](int iz, const double k[3]) {
    const Zone& z = m.zones[static_cast<std::size_t>(iz)];
    for (int i = 0; i < 3; ++i) m.gp[static_cast<std::size_t>(z.n[static_cast<std::size_t>(i)])].stiffness += k[i];
  };
  if (threads <= 1) {
    for_owned_zones(m, [&](int iz) {
      double k[3];
      zone_stiffness_of(m, iz, k);
      add(iz, k);
    });
    return;
  }
  // As zone_forces: the zones on several threads, then each gridpoint takes its zones' shares in
  // zone order.
  ZoneGather& gather = zone_gather();
  if (!gather.fits(m) || !gather.same_corners(m)) gather.rebuild(m);
  std::vector<double>& ks = gather.values;
  ks.resize(3 * m.zones.size());
  for_owned_zone_ranges(m, [&](int first, int last) {
    threaded_for(threads, first, last, [&](std::ptrdiff_t iz) { zone_stiffness_of(m, static_cast<int>(iz), &ks[3 * static_cast<std::size_t>(iz)]); });
  });
  for_owned_gridpoint_ranges(m, [&](int first, int last) {
    threaded_for(threads, first, last, [&](std::ptrdiff_t i) {
      GridPoint& g = m.gp[static_cast<std::size_t>(i)];
      for (int e = gather.start[static_cast<std::size_t>(i)]; e < gather.start[static_cast<std::size_t>(i) + 1]; ++e)
        g.stiffness += ks[static_cast<std::size_t>(gather.slot[static_cast<std::size_t>(e)])];
    });
  });
}

}  // namespace rockdem
