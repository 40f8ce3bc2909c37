#include "framework/contact/detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "framework/geometry/polygon.hpp"

namespace rockdem {
namespace {

struct Box {
  Vec2 lo, hi;
};

Box block_box(const Model& m, const Block& b, double margin) {
  Box box{Vec2::Constant(std::numeric_limits<double>::max()), Vec2::Constant(-std::numeric_limits<double>::max())};
  for (int g : b.boundary) {
    box.lo = box.lo.cwiseMin(m.gp[g].x);
    box.hi = box.hi.cwiseMax(m.gp[g].x);
  }
  box.lo.array() -= margin;
  box.hi.array() += margin;
  return box;
}

// Closest point of segment ab to p: parameter s in [0,1].
double project(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  if (l2 <= 0.0) return 0.0;
  return std::clamp((p - a).dot(ab) / l2, 0.0, 1.0);
}

bool inside_polygon(const Model& m, const Block& b, const Vec2& p) {
  return crossing_number_inside(p, b.boundary.size(), [&](std::size_t i) -> const Vec2& { return m.gp[b.boundary[i]].x; });
}

struct Projection {
  int edge = 0;
  double s = 0.0;
  double dist = 0.0;  // signed: positive outside the other block
  Vec2 normal = Vec2::UnitY();
};


// Signed distance and normal of p relative to boundary edge i of b, with convex corners rounded
// by radius d (Cundall 1988; UDEC): near a convex vertex the straight part of each edge stops at
// the tangent point, and between the two tangent points the boundary is an arc of radius d (less
// where the edges are too short). A point that passes a corner therefore sees its normal turn
// smoothly from one face to the next, and a point pressed slightly into a face near a corner
// keeps that face's normal rather than jumping to the other face. Flat and concave vertices are
// not rounded; beyond their ends the normal points from the vertex to the point when the point
// is outside both edges, else it is the mean of the two edge normals.
constexpr double kSin5 = 0.08715574274765817;  // sin(5 degrees)

Projection project_rounded(const Model& m, const Block& b, const Vec2& p, int i, double d) {
  const int n = static_cast<int>(b.boundary.size());
  const Vec2& a = m.gp[b.boundary[i]].x;
  const Vec2& c = m.gp[b.boundary[(i + 1) % n]].x;
  const Vec2& ap = m.gp[b.boundary[(i - 1 + n) % n]].x;
  const Vec2& cn = m.gp[b.boundary[(i + 2) % n]].x;
  const double len = (c - a).norm();
  const Vec2 u = (c - a) / len;
  const Vec2 nrm(u.y(), -u.x());
  const Vec2 up = (a - ap).normalized(), un = (cn - c).normalized();
  // Tangent length and radius of the rounding at a vertex turning by angle th (left turns are
  // convex on a counter-clockwise loop).
  // Tangent length and radius of the rounding at a vertex where the unit direction turns from e1
  // to e2 (left turns are convex on a counter-clockwise loop); tan(th/2) = sin th / (1 + cos th).
  auto rounding = [&](const Vec2& e1, const Vec2& e2, double l1, double l2, double& t, double& r) {
    t = r = 0.0;
    // Only real corners are rounded: a boundary gridpoint of a deformable block on a straight
    // face turns by a tiny angle, and rounding it with radius d would bend the normal of points
    // that merely pass over it.
    const double sn = cross(e1, e2), cs = e1.dot(e2);
    if (d <= 0.0 || sn <= 0.0 || (cs > 0.0 && sn < kSin5)) return;
    const double h = sn / (1.0 + cs);
    t = std::min({d * h, 0.5 * l1, 0.5 * l2});
    r = t / h;
  };
  double ta, ra, tb, rb;
  rounding(up, u, len, (a - ap).norm(), ta, ra);
  rounding(u, un, len, (cn - c).norm(), tb, rb);
  const double xi = (p - a).dot(u);
  Projection pr;
  pr.edge = i;
  pr.s = std::clamp(xi / len, 0.0, 1.0);
  auto arc = [&](const Vec2& centre, double r) {
    const Vec2 q = p - centre;
    const double qn = q.norm();
    pr.normal = qn > 1e-14 ? Vec2(q / qn) : nrm;
    pr.dist = qn - r;
  };
  const Vec2 nprev(up.y(), -up.x()), nnext(un.y(), -un.x());
  const Vec2 ca = a + ta * u - ra * nrm, cb = c - tb * u - rb * nrm;
  // The arc of a rounded corner serves the points in its sector, between the two edge normals.
  if (xi < ta && ta > 0.0 && cross(nprev, p - ca) >= 0.0 && cross(p - ca, nrm) >= 0.0) {
    arc(ca, ra);
  } else if (xi > len - tb && tb > 0.0 && cross(nrm, p - cb) >= 0.0 && cross(p - cb, nnext) >= 0.0) {
    arc(cb, rb);
  } else if (xi < 0.0 || xi > len) {
    const Vec2& v = xi < 0.0 ? a : c;
    const Vec2& other = xi < 0.0 ? nprev : nnext;
    const Vec2 dv = p - v;
    if (dv.dot(nrm) > 0.0 && dv.dot(other) > 0.0) {
      pr.dist = dv.norm();
      pr.normal = dv / std::max(pr.dist, 1e-300);
    } else {
      pr.normal = (nrm + other).normalized();
      pr.dist = dv.dot(pr.normal);
    }
  } else {
    pr.normal = nrm;
    pr.dist = (p - a).dot(nrm);
  }
  return pr;
}

// Outward normal of the boundary at gridpoint loop position k of block a if the boundary is flat
// there (the two edges turn by less than ~5 degrees); zero for a corner.
Vec2 flat_normal(const Model& m, const Block& a, int k) {
  const int n = static_cast<int>(a.boundary.size());
  const Vec2& p = m.gp[a.boundary[k]].x;
  const Vec2 e1 = (p - m.gp[a.boundary[(k - 1 + n) % n]].x).normalized();
  const Vec2 e2 = (m.gp[a.boundary[(k + 1) % n]].x - p).normalized();
  if (e1.dot(e2) < std::cos(5.0 * M_PI / 180.0)) return Vec2::Zero();
  return Vec2(e1.y() + e2.y(), -(e1.x() + e2.x())).normalized();
}

// Face-to-face pairing. A gridpoint on a flat part of its block's boundary meets the other block
// across the joint plane: its contact uses the other block's face whose outward normal is opposite
// to its own, extended beyond the face's ends, with that face's normal. The contact length (the
// point's tributary clipped to the other face's extent) then grows or shrinks continuously as an
// edge of the other block slides over the point, and the normal never swings around a corner of
// the other block because of the small elastic interpenetration of the joint (which otherwise
// gives the point a sideways normal as a block corner passes over it).
bool face_projection(const Model& m, const Block& b, const Vec2& p, const Vec2& own, int e, double w, Projection& pr) {
  const int n = static_cast<int>(b.boundary.size());
  const Vec2& a = m.gp[b.boundary[e]].x;
  const Vec2& c = m.gp[b.boundary[(e + 1) % n]].x;
  const double len = (c - a).norm();
  const Vec2 u = (c - a) / len;
  const Vec2 nrm(u.y(), -u.x());
  if (nrm.dot(own) > -0.94) return false;  // not facing (more than ~20 degrees apart)
  const double xi = (p - a).dot(u);
  if (xi < -w || xi > len + w) return false;
  pr.edge = e;
  pr.s = std::clamp(xi / len, 0.0, 1.0);
  pr.normal = nrm;
  pr.dist = (p - a).dot(nrm);
  return true;
}

Projection closest_face(const Model& m, const Block& b, const Vec2& p, const Vec2& own, double w, bool& found) {
  Projection best, pr;
  found = false;
  const int n = static_cast<int>(b.boundary.size());
  for (int i = 0; i < n; ++i)
    if (face_projection(m, b, p, own, i, w, pr) && std::abs(pr.dist) <= w && (!found || std::abs(pr.dist) < std::abs(best.dist))) {
      best = pr;
      found = true;
    }
  return best;
}

Projection closest_edge(const Model& m, const Block& b, const Vec2& p, double d) {
  Projection best;
  double best_abs = std::numeric_limits<double>::max();
  const int n = static_cast<int>(b.boundary.size());
  for (int i = 0; i < n; ++i) {
    const Vec2& a = m.gp[b.boundary[i]].x;
    const Vec2& c = m.gp[b.boundary[(i + 1) % n]].x;
    // Cheap bound first: distance to the segment itself.
    const double sp = project(p, a, c);
    if ((p - (a + sp * (c - a))).norm() > best_abs + d) continue;
    const Projection pr = project_rounded(m, b, p, i, d);
    if (std::abs(pr.dist) < best_abs) {
      best_abs = std::abs(pr.dist);
      best = pr;
    }
  }
  // A point inside the block is penetrating: make sure the sign says so.
  if (best.dist > 0.0 && inside_polygon(m, b, p)) best.dist = -best.dist;
  return best;
}

// Part of segment ab whose distance from the line through p (normal n) is at most w, projected on
// the tangent t: returns false if empty.
bool band_interval(const Vec2& a, const Vec2& b, const Vec2& p, const Vec2& n, const Vec2& t, double w,
                   double& lo, double& hi) {
  const double ha = (a - p).dot(n), hb = (b - p).dot(n);
  double s0 = 0.0, s1 = 1.0;
  const double dh = hb - ha;
  if (std::abs(dh) < 1e-300) {
    if (std::abs(ha) > w) return false;
  } else {
    double sa = (-w - ha) / dh, sb = (w - ha) / dh;
    if (sa > sb) std::swap(sa, sb);
    s0 = std::max(s0, sa);
    s1 = std::min(s1, sb);
    if (s0 >= s1) return false;
  }
  const double ta = (a - p).dot(t), tb = (b - p).dot(t);
  const double x0 = ta + s0 * (tb - ta), x1 = ta + s1 * (tb - ta);
  lo = std::min(x0, x1);
  hi = std::max(x0, x1);
  return hi > lo;
}

}  // namespace

std::vector<std::pair<int, int>> broad_phase(const Model& m, double margin) {
  const int nb = static_cast<int>(m.blocks.size());
  std::vector<Box> boxes(nb);
  double mean_size = 0.0;
  for (int i = 0; i < nb; ++i) {
    boxes[i] = block_box(m, m.blocks[i], margin);
    mean_size += (boxes[i].hi - boxes[i].lo).maxCoeff();
  }
  std::vector<std::pair<int, int>> pairs;
  if (nb < 2) return pairs;
  mean_size /= nb;
  // Cells about the mean block size: each block falls in a few cells, each cell holds a few blocks.
  const double cell = std::max(mean_size, 1e-12);
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  grid.reserve(static_cast<std::size_t>(nb) * 4);
  auto key = [](std::int64_t ix, std::int64_t iy) { return (ix << 32) ^ (iy & 0xffffffff); };
  for (int i = 0; i < nb; ++i) {
    const auto x0 = static_cast<std::int64_t>(std::floor(boxes[i].lo.x() / cell));
    const auto x1 = static_cast<std::int64_t>(std::floor(boxes[i].hi.x() / cell));
    const auto y0 = static_cast<std::int64_t>(std::floor(boxes[i].lo.y() / cell));
    const auto y1 = static_cast<std::int64_t>(std::floor(boxes[i].hi.y() / cell));
    for (auto ix = x0; ix <= x1; ++ix)
      for (auto iy = y0; iy <= y1; ++iy) grid[key(ix, iy)].push_back(i);
  }
  for (auto& [k, list] : grid) {
    for (std::size_t a = 0; a < list.size(); ++a)
      for (std::size_t b = a + 1; b < list.size(); ++b) {
        const int i = std::min(list[a], list[b]), j = std::max(list[a], list[b]);
        const Box &A = boxes[i], &B = boxes[j];
        if (A.lo.x() <= B.hi.x() && B.lo.x() <= A.hi.x() && A.lo.y() <= B.hi.y() && B.lo.y() <= A.hi.y())
          pairs.emplace_back(i, j);
      }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::size_t detect_contacts(Model& m, const DetectionSettings& s) {
  std::vector<Contact> found;
  found.reserve(m.contacts.items.size() + 16);
  const auto pairs = broad_phase(m, s.distance);
  auto scan = [&](int ia, int ib) {
    const Block& A = m.blocks[ia];
    const Block& B = m.blocks[ib];
    const Box bb = block_box(m, B, s.distance);
    const int na = static_cast<int>(A.boundary.size());
    for (int k = 0; k < na; ++k) {
      const int g = A.boundary[k];
      const Vec2& p = m.gp[g].x;
      if (p.x() < bb.lo.x() || p.x() > bb.hi.x() || p.y() < bb.lo.y() || p.y() > bb.hi.y()) continue;
      const Vec2 own = flat_normal(m, A, k);
      bool face = false;
      Projection pr;
      if (own.squaredNorm() > 0.0) pr = closest_face(m, B, p, own, s.distance, face);
      if (!face) pr = closest_edge(m, B, p, m.contacts.rounding);
      if (pr.dist > 10.0 * s.distance) continue;
      const ContactKey key{A.id, m.gp[g].local, B.id};
      const Contact* old = m.contacts.find(key);
      const bool closed = old && !old->response.open && !old->fresh;
      if (pr.dist > s.distance && !closed) continue;
      Contact c;
      c.key = key;
      c.point = g;
      c.point_loop = k;
      c.face_mode = face;
      c.other = ib;
      c.edge = pr.edge;
      c.s = pr.s;
      c.normal = pr.normal;
      c.overlap = -pr.dist;
      c.joint = m.contacts.model_for(A.group, B.group, B.edge_label(pr.edge));
      if (old) c.pretouch_gap = old->pretouch_gap;
      else c.pretouch_gap = std::max(0.0, pr.dist);  // not yet touching: the law starts when it closes
      c.pending_closure = old ? old->pending_closure : std::max(0.0, -pr.dist);
      found.push_back(c);
    }
  };
  for (const auto& [i, j] : pairs) {
    scan(i, j);
    scan(j, i);
  }
  const std::size_t created = m.contacts.merge(std::move(found));
  update_contact_lengths(m, s);
  return created;
}

void update_contact_geometry(Model& m) {
  for (Contact& c : m.contacts.items) {
    const Block& B = m.blocks[c.other];
    const Block& A = m.blocks[m.gp[c.point].block];
    const int n = static_cast<int>(B.boundary.size());
    const Vec2& p = m.gp[c.point].x;
    int e = c.edge;
    // Face mode: slide along the facing edges of the other block, staying on the last one beyond
    // the face's end (see face_projection).
    const Vec2 own = c.face_mode ? flat_normal(m, A, c.point_loop) : Vec2::Zero();
    Projection pr;
    if (own.squaredNorm() > 0.0 && face_projection(m, B, p, own, e, kInf, pr)) {
      const int dir = pr.s >= 1.0 ? 1 : -1;
      for (int it = 0; it < n && (dir > 0 ? pr.s >= 1.0 : pr.s <= 0.0); ++it) {
        const int next = (e + dir + n) % n;
        Projection q;
        if (!face_projection(m, B, p, own, next, kInf, q)) break;
        e = next;
        pr = q;
      }
      c.edge = e;
      c.s = pr.s;
      c.normal = pr.normal;
      c.overlap = -pr.dist;
      continue;
    }
    // Slide along the other boundary: at most n moves, normally zero or one.
    for (int it = 0; it < n; ++it) {
      const Vec2& a = m.gp[B.boundary[e]].x;
      const Vec2& b = m.gp[B.boundary[(e + 1) % n]].x;
      const Vec2 ab = b - a;
      const double raw = (p - a).dot(ab) / ab.squaredNorm();
      if (raw < 0.0) {
        const int prev = (e - 1 + n) % n;
        const Vec2& pa = m.gp[B.boundary[prev]].x;
        if ((p - pa).dot(a - pa) / (a - pa).squaredNorm() < 1.0 && it + 1 < n) { e = prev; continue; }
      } else if (raw > 1.0) {
        const int next = (e + 1) % n;
        const Vec2& nb = m.gp[B.boundary[(next + 1) % n]].x;
        if ((p - b).dot(nb - b) > 0.0 && it + 1 < n) { e = next; continue; }
      }
      break;
    }
    c.edge = e;
    pr = project_rounded(m, B, p, e, m.contacts.rounding);
    c.s = pr.s;
    c.normal = pr.normal;
    c.overlap = -pr.dist;
  }
}

void update_contact_lengths(Model& m, const DetectionSettings& s) {
  auto& items = m.contacts.items;
  const double w = s.distance;
  // Own and facing intervals, on the tangent through each contact point.
  struct Span {
    std::size_t c;
    double lo, hi;   // along the cluster tangent, absolute coordinate
    double at;       // the contact point's own coordinate
    bool touching;
  };
  // Cluster by block pair and normal direction (normals of the second block's points flipped).
  struct Cluster {
    BlockId a, b;
    Vec2 n;
    std::vector<Span> spans;
  };
  std::vector<Cluster> clusters;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> by_pair;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Contact& c = items[i];
    const BlockId a = std::min(c.key.point_block, c.key.other_block);
    const BlockId b = std::max(c.key.point_block, c.key.other_block);
    const Vec2 n = c.key.point_block == a ? c.normal : Vec2(-c.normal);
    const std::int64_t pk = (static_cast<std::int64_t>(a) << 32) | static_cast<std::uint32_t>(b);
    auto& list = by_pair[pk];
    std::size_t ci = clusters.size();
    for (std::size_t k : list)
      if (clusters[k].n.dot(n) > 0.866) { ci = k; break; }  // within 30 degrees
    if (ci == clusters.size()) {
      clusters.push_back({a, b, n, {}});
      list.push_back(ci);
    }
    const Vec2 t(clusters[ci].n.y(), -clusters[ci].n.x());
    // Own tributary: the half-edges on both sides of the point, inside the contact band.
    const Block& A = m.blocks[m.gp[c.point].block];
    const Block& B = m.blocks[c.other];
    const int na = static_cast<int>(A.boundary.size());
    const int local = c.point_loop;
    const Vec2& p = m.gp[c.point].x;
    const Vec2& prev = m.gp[A.boundary[(local - 1 + na) % na]].x;
    const Vec2& next = m.gp[A.boundary[(local + 1) % na]].x;
    double lo = 0.0, hi = 0.0, l1, h1;
    bool any = false;
    if (band_interval(0.5 * (prev + p), p, p, c.normal, t, w, l1, h1)) { lo = l1; hi = h1; any = true; }
    if (band_interval(p, 0.5 * (p + next), p, c.normal, t, w, l1, h1)) {
      lo = any ? std::min(lo, l1) : l1;
      hi = any ? std::max(hi, h1) : h1;
      any = true;
    }
    // The other block's surface inside the band, walking from the contact edge both ways.
    const int nb = static_cast<int>(B.boundary.size());
    double olo = 0.0, ohi = 0.0;
    bool oany = false;
    for (int dir : {+1, -1}) {
      int e = c.edge;
      for (int k = 0; k < nb; ++k) {
        const Vec2& ea = m.gp[B.boundary[e]].x;
        const Vec2& eb = m.gp[B.boundary[(e + 1) % nb]].x;
        if (!band_interval(ea, eb, p, c.normal, t, w, l1, h1)) break;
        olo = oany ? std::min(olo, l1) : l1;
        ohi = oany ? std::max(ohi, h1) : h1;
        oany = true;
        e = (e + dir + nb) % nb;
      }
    }
    double x0 = 0, x1 = 0;
    if (any && oany) {
      x0 = std::max(lo, olo);
      x1 = std::min(hi, ohi);
    }
    const double base = p.dot(t);
    const bool touching = !c.response.open && c.pretouch_gap <= 0.0;
    clusters[ci].spans.push_back({i, base + x0, base + std::max(x0, x1), base, touching});
  }
  // Each touching contact owns its Voronoi cell among the touching contacts of both blocks along
  // the interface, clipped to its own stretch. The cells partition the overlap, and they change
  // continuously as points of one block slide past points of the other or past an edge's end
  // (a newly covered point starts with a cell of zero length, not with half its tributary).
  for (Cluster& cl : clusters) {
    std::vector<const Span*> touching;
    for (const Span& sp : cl.spans) {
      if (sp.touching) touching.push_back(&sp);
      else items[sp.c].length = sp.hi - sp.lo;  // carries no stress; kept for output
    }
    std::sort(touching.begin(), touching.end(), [](const Span* a, const Span* b) { return a->at < b->at; });
    for (std::size_t k = 0; k < touching.size(); ++k) {
      const Span& sp = *touching[k];
      double lo = sp.lo, hi = sp.hi;
      if (k > 0) lo = std::max(lo, 0.5 * (touching[k - 1]->at + sp.at));
      if (k + 1 < touching.size()) hi = std::min(hi, 0.5 * (sp.at + touching[k + 1]->at));
      items[sp.c].length = std::max(0.0, hi - lo);
    }
  }
}

}  // namespace rockdem
