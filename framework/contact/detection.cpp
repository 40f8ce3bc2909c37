#include "framework/contact/detection.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "framework/contact/boundary_geometry.hpp"
#include "framework/contact/broad_phase.hpp"
#include "framework/core/threads.hpp"
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
  bool arc = false;   // measured against the rounding arc of a convex corner ...
  Vec2 centre = Vec2::Zero();  // ... with this centre
  double radius = 0.0;         // and radius
};

// Signed distance and normal of p relative to boundary edge i of b, with convex corners rounded
// by radius d (Cundall 1988; UDEC): near a convex vertex the straight part of each edge stops at
// the tangent point, and between the two tangent points the boundary is an arc of radius d (less
// where the edges are too short). A point that passes a corner therefore sees its normal turn
// smoothly from one face to the next, and a point pressed slightly into a face near a corner
// keeps that face's normal rather than jumping to the other face. Flat and concave vertices are
// not rounded; beyond their ends the normal points from the vertex to the point when the point
// is outside both edges, else it is the mean of the two edge normals.
Projection project_rounded(const Model& m, const Block& b, const BoundaryEdge* geo, const Vec2& p, int i) {
  const int n = static_cast<int>(b.boundary.size());
  const Vec2& a = m.gp[b.boundary[i]].x;
  const Vec2& c = m.gp[b.boundary[(i + 1) % n]].x;
  const BoundaryEdge& edge = geo[i];
  const BoundaryEdge& prev = geo[(i - 1 + n) % n];
  const BoundaryEdge& next = geo[(i + 1) % n];
  const double len = edge.len;
  const Vec2& u = edge.u;
  const Vec2& nrm = edge.nrm;
  const Vec2& up = prev.u;
  const Vec2& un = next.u;
  const double ta = edge.t, ra = edge.r, tb = next.t, rb = next.r;
  const double xi = (p - a).dot(u);
  Projection pr;
  pr.edge = i;
  pr.s = std::clamp(xi / len, 0.0, 1.0);
  auto arc = [&](const Vec2& centre, double r) {
    const Vec2 q = p - centre;
    const double qn = q.norm();
    pr.normal = qn > 1e-14 ? Vec2(q / qn) : nrm;
    pr.dist = qn - r;
    pr.arc = true;
    pr.centre = centre;
    pr.radius = r;
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
    const double on = dv.dot(nrm), oo = dv.dot(other);
    if (on > 0.0 && oo > 0.0) {
      pr.dist = dv.norm();
      pr.normal = dv / std::max(pr.dist, 1e-300);
    } else {
      // Along the corner's mean normal the face runs on a little past its vertex, so that a point
      // at a coincident corner still meets the face it lies on. That extension stops at the
      // rounding length d across the mean normal: beyond it the reading is the distance to that
      // short cap, signed by the side of the corner the point lies on. Unbounded, the mean normal
      // of a sharp corner (a 22-degree wedge tip) runs almost along both faces, and a point 32 mm
      // beside one face read 4 mm deep along it, a contact with a load its geometry did not have;
      // through a flat vertex (a gridpoint on a deformable block's face) the face's line ran on
      // past the block, and points of other blocks 0.1 to 0.9 m beyond it read as touching it.
      const Vec2 nm = (nrm + other).normalized();
      const Vec2 tm(nm.y(), -nm.x());
      const double h = dv.dot(nm), across = dv.dot(tm), beyond = std::abs(across) - m.contacts.rounding;
      if (beyond <= 0.0) {
        pr.normal = nm;
        pr.dist = h;
      } else {
        const BoundaryEdge& corner = xi < 0.0 ? edge : next;
        const bool convex = (xi < 0.0 ? cross(up, u) : cross(u, un)) > 0.0;
        const bool outside = corner.flat ? dv.dot(corner.flat_normal) > 0.0 : convex && (on > 0.0 || oo > 0.0);
        const Vec2 q = h * nm + std::copysign(beyond, across) * tm;
        const double r = q.norm();
        pr.dist = outside ? r : -r;
        pr.normal = r > 1e-300 ? Vec2((outside ? q : Vec2(-q)) / r) : nm;
      }
    }
  } else {
    pr.normal = nrm;
    pr.dist = (p - a).dot(nrm);
  }
  return pr;
}

// The point's own side of a contact: the outward normal of the boundary at loop position k of
// block a along the given side (ContactKey::side), and the other end of that own edge. Where the
// boundary is flat (the two edges turn by less than ~5 degrees, e.g. a gridpoint in the middle of
// a deformable block's face) the point has one side, 0, with the mean normal of its two edges.
struct OwnSide {
  Vec2 normal = Vec2::Zero();
  Vec2 far = Vec2::Zero();  // other end of the own edge (a corner's) along this side
  bool flat = false;
};

OwnSide own_side(const Model& m, const Block& a, const BoundaryEdge* geo, int k, int side) {
  const int n = static_cast<int>(a.boundary.size());
  const Vec2& prev = m.gp[a.boundary[(k - 1 + n) % n]].x;
  const Vec2& next = m.gp[a.boundary[(k + 1) % n]].x;
  OwnSide o;
  if (geo[k].flat) {
    o.flat = true;
    o.normal = geo[k].flat_normal;
    o.far = next;
    return o;
  }
  o.normal = side == 0 ? geo[(k - 1 + n) % n].nrm : geo[k].nrm;
  o.far = side == 0 ? prev : next;
  return o;
}

// Face-to-face pairing. A point meets the other block across a joint plane when one of its own
// edges faces an edge of the other block: outward normals opposite within about 20 degrees, and,
// for a corner, the two edges sharing more than a sliver of their extent along the joint (`min_share`).
// The contact then uses that edge of the other block, extended beyond its ends, with its normal.
// This is the two-dimensional common plane of the touching faces (Cundall 1988's common plane for
// 3DEC): two equal blocks stacked corner on corner, a T-junction or a corner nested in a concave
// corner all meet along the right plane, and the normal never swings around a corner of the other
// block because of the small elastic interpenetration of the joint. A corner whose edges face
// nothing (a tip pressed into a tip, a corner into a face at an angle) is left to the rounded
// corners (closest_edge).
bool face_projection(const Model& m, const Block& b, const BoundaryEdge* geo, const Vec2& p, const OwnSide& own,
                     int e, double w, double min_share, Projection& pr, double* shared = nullptr) {
  const Vec2& nrm = geo[e].nrm;
  if (nrm.dot(own.normal) > -0.94) return false;  // not facing (more than ~20 degrees apart)
  const Vec2& a = m.gp[b.boundary[e]].x;
  const Vec2& u = geo[e].u;
  const double len = geo[e].len;
  const double xi = (p - a).dot(u);
  if (xi < -w || xi > len + w) return false;
  if (!own.flat) {
    const double xf = (own.far - a).dot(u);
    const double share = std::min(std::max(xi, xf), len) - std::max(std::min(xi, xf), 0.0);
    if (share <= min_share) return false;
    if (shared) *shared = share;
  }
  pr.edge = e;
  pr.s = std::clamp(xi / len, 0.0, 1.0);
  pr.normal = nrm;
  pr.dist = (p - a).dot(nrm);
  pr.arc = false;
  return true;
}

// Where the face bends (the next or previous edge of the other block faces the point too, e.g. at
// a vertex of the opening's 24 sides), its normal and distance turn from one edge's to the next
// edge's over the rounding length d either side of the vertex, half and half at the vertex. With
// one edge's plane or the other's, a point sliding past the vertex saw its normal turn by the
// bend at once; a point and its mirror (the other block's point at the same vertex) each took a
// different edge, so that sliding closed one and opened the other and their stresses drifted
// apart; and a point in the wedge outside a convex vertex went from one edge to the other and
// back at every step.
void bend_at_vertex(const Model& m, const Block& b, const BoundaryEdge* geo, const Vec2& p, const OwnSide& own,
                    double d, Projection& pr) {
  if (d <= 0.0) return;
  const int n = static_cast<int>(b.boundary.size());
  const int e = pr.edge;
  const double len = geo[e].len;
  const double xi = (p - m.gp[b.boundary[e]].x).dot(geo[e].u);
  const bool at_end = xi > len - d, at_start = xi < d;
  if (!at_end && !at_start) return;
  Projection q;
  const int other = at_end ? (e + 1) % n : (e - 1 + n) % n;
  if (other == e || !face_projection(m, b, geo, p, own, other, kInf, -kInf, q)) return;
  // Weight of the neighbouring edge: 0 at d before the vertex, 1/2 at it, 1 at d beyond.
  const double beyond = at_end ? xi - len : -xi;
  const double wt = std::clamp(0.5 + 0.5 * beyond / d, 0.0, 1.0);
  const Vec2 nb = ((1.0 - wt) * pr.normal + wt * q.normal).normalized();
  pr.dist = (1.0 - wt) * pr.dist + wt * q.dist;
  pr.normal = nb;
}

// A new contact needs the two edges to share more than 1 % of w along the joint; one that the side
// already holds closed (`held`, asked only when no edge passes that test) keeps its face while the
// edges are no more than w apart, the reach the face test allows beyond an edge's end. With the one
// limit for both, a corner at a four-block junction that had slid to the very end of the facing
// edge (shares of 0.036 to 0.040 mm against the 0.04 mm limit) lost its face at one detection and
// found it again at a later one. Its contact was dropped each time with 33-80 MPa on it, since the
// corner's other side still faced the block and no rounded contact took over, and it came back
// fresh: up to 19 times in one event of the drift study, 2.3 kJ/m of stored energy lost.
template <class Held>
Projection closest_face(const Model& m, const Block& b, const BoundaryEdge* geo, const Vec2& p, const OwnSide& own,
                        double w, const Held& held, bool& found) {
  Projection best, near, pr;
  found = false;
  bool any_near = false;
  const int n = static_cast<int>(b.boundary.size());
  const double new_share = 0.01 * w;
  for (int i = 0; i < n; ++i) {
    double share = kInf;
    if (!face_projection(m, b, geo, p, own, i, w, -w, pr, &share) || std::abs(pr.dist) > w) continue;
    if (share > new_share) {
      if (!found || std::abs(pr.dist) < std::abs(best.dist)) best = pr;
      found = true;
    } else if (!any_near || std::abs(pr.dist) < std::abs(near.dist)) {
      near = pr;
      any_near = true;
    }
  }
  if (!found && any_near && held()) {
    best = near;
    found = true;
  }
  if (found) bend_at_vertex(m, b, geo, p, own, m.contacts.rounding, best);
  return best;
}

Projection closest_edge(const Model& m, const Block& b, const BoundaryEdge* geo, const Vec2& p, double d, double w) {
  Projection best;
  double best_abs = std::numeric_limits<double>::max();
  const int n = static_cast<int>(b.boundary.size());
  for (int i = 0; i < n; ++i) {
    // Cheap bounds first: the distance to the edge's box, then to the segment itself. The box test
    // only skips edges the segment test would skip (its margin, 1e-9 of the reach, is far above
    // the round-off of either distance for coordinates within kilometres of the origin at a
    // millimetre reach), without a division and a square root for each.
    const BoundaryEdge& e = geo[i];
    const double reach = best_abs + d, box_reach = reach * (1.0 + 1e-9);
    if (e.lo.x() - p.x() > box_reach || p.x() - e.hi.x() > box_reach || e.lo.y() - p.y() > box_reach ||
        p.y() - e.hi.y() > box_reach)
      continue;
    const Vec2& a = m.gp[b.boundary[i]].x;
    const Vec2& c = m.gp[b.boundary[i + 1 == n ? 0 : i + 1]].x;
    const double sp = project(p, a, c);
    if ((p - (a + sp * (c - a))).norm() > reach) continue;
    const Projection pr = project_rounded(m, b, geo, p, i);
    if (std::abs(pr.dist) < best_abs) {
      best_abs = std::abs(pr.dist);
      best = pr;
    }
  }
  // A point inside the block is penetrating: make sure the sign says so. Beyond an edge's end the
  // distance is measured along the corner's mean normal, which extends the face a little past its
  // vertex (a point at a coincident corner still meets the face it lies on, within the detection
  // distance w); a point outside the block that this reads as deeper than w is not touching it:
  // behind that line lies the outside of a concave block (a point in the opening of a C-shaped
  // far-field block, 3 m from its inner face, was read as 3.2 m inside it through the line of its
  // back edge, and kept as a touching contact).
  if (best.dist > 0.0 || best.dist < -w) {
    const bool inside = inside_polygon(m, b, p);
    if ((best.dist > 0.0 && inside) || (best.dist < 0.0 && !inside)) best.dist = -best.dist;
  }
  return best;
}

// Corner against corner (UDEC; Cundall 1988): when the point is itself a convex corner of its block
// and lies in the sector of a rounded corner of the other block, both corners are rounded: the
// normal runs along the line joining the two rounding centres and the gap is their distance less
// both radii. The contact of corner a on corner b and that of b on a then have opposite normals;
// two tips pressed together push along the line joining them; and two corners sliding past each
// other along a shared joint (the junction of four blocks) never overlap: their gap is smallest,
// zero, when they are side by side, where the normal is that of the joint.
void corner_to_corner(const Model& m, const Block& a, const BoundaryEdge* geo, int k, Projection& pr) {
  if (!pr.arc) return;
  const Vec2& p = m.gp[a.boundary[k]].x;
  const double t = geo[k].t, r = geo[k].r;
  if (r <= 0.0) return;
  const Vec2 own_centre = p + t * geo[k].u - r * geo[k].nrm;
  const Vec2 join = own_centre - pr.centre;
  const double jn = join.norm();
  if (jn < 1e-14) return;
  pr.normal = join / jn;
  pr.dist = jn - r - pr.radius;
}

// Part of segment ab whose height above the line through p (normal n) lies in [h0, h1], projected
// on the tangent t: returns false if empty.
bool band_interval(const Vec2& a, const Vec2& b, const Vec2& p, const Vec2& n, const Vec2& t, double h0, double h1,
                   double& lo, double& hi) {
  const double ha = (a - p).dot(n), hb = (b - p).dot(n);
  double s0 = 0.0, s1 = 1.0;
  const double dh = hb - ha;
  if (std::abs(dh) < 1e-300) {
    if (ha < h0 || ha > h1) return false;
  } else {
    double sa = (h0 - ha) / dh, sb = (h1 - ha) / dh;
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

// Where the other block's boundary passes from one joint model's edges to another's (a joint trace
// that runs on as a rock bridge), a closed contact keeps its model while its point is within the
// rounding length d of that vertex. The model goes with the edge the point projects on, and a point
// at the vertex itself (the corner of the block on the other side of the bridge's end) went from
// one edge to the other with micrometres of motion: in the drift study's first earthquake a few
// such corners changed model at almost every detection, each change starting the law afresh (a
// bridge at 23 MPa shear dropped to nothing, then rebuilt intact, cohesion and all): 8.6 kJ/m of
// stored energy lost by t = 2.1 s, the event's first second. An edge shorter than 2d whose two
// neighbours both have the contact's model never gives a closed contact its own model.
bool keeps_model_at_vertex(const Model& m, const Block& A, const Block& B, const BoundaryEdge* gb, const Vec2& p, int e,
                           int old_model) {
  const double d = m.contacts.rounding;
  const int n = static_cast<int>(B.boundary.size());
  const double xi = (p - m.gp[B.boundary[e]].x).dot(gb[e].u);
  const auto model_of = [&](int edge) { return m.contacts.model_for(A.group, B.group, B.edge_label(edge)); };
  return (xi < d && model_of((e - 1 + n) % n) == old_model) || (xi > gb[e].len - d && model_of((e + 1) % n) == old_model);
}

}  // namespace

std::size_t detect_contacts(Model& m, const DetectionSettings& s, int threads) {
  // Buffers kept between passes (broad_phase.hpp); merge() hands the old contact list back.
  DetectionBuffers& buffers = detection_buffers();
  std::vector<Contact>& found = buffers.found;
  found.clear();
  broad_phase_pairs(m, s.distance, buffers.pairs);
  const auto& pairs = buffers.pairs;
  BoundaryGeometry& geometry = boundary_geometry();
  geometry.update(m, m.contacts.rounding, threads);
  // Candidate contacts of one point: one per own side that faces an edge of the other block, or
  // else one against the rounded boundary (see face_projection and corner_to_corner).
  struct Candidate {
    int side;
    bool face;
    Projection pr;
  };
  auto candidates = [&](const Block& A, const BoundaryEdge* ga, int k, const Block& B, const BoundaryEdge* gb,
                        Candidate out[2]) -> int {
    const Vec2& p = m.gp[A.boundary[k]].x;
    const OwnSide own0 = own_side(m, A, ga, k, 0);
    const int nsides = own0.flat ? 1 : 2;
    const OwnSide own[2] = {own0, nsides == 2 ? own_side(m, A, ga, k, 1) : own0};
    int nf = 0;
    for (int side = 0; side < nsides; ++side) {
      bool face = false;
      const auto held = [&] {
        std::size_t hint = 0;
        const Contact* old = m.contacts.find({A.id, m.gp[A.boundary[k]].local, B.id, side}, hint);
        return old && !old->response.open && !old->fresh;
      };
      const Projection pr = closest_face(m, B, gb, p, own[side], s.distance, held, face);
      if (face) out[nf++] = {side, true, pr};
    }
    // Both edges of a corner face the other block: two contacts if they meet it along different
    // planes (a corner nested in a concave corner), else the nearer (a blunt corner on a face).
    if (nf == 2 && out[0].pr.normal.dot(out[1].pr.normal) > kSamePlaneCos) {
      const double d0 = std::abs(out[0].pr.dist), d1 = std::abs(out[1].pr.dist);
      bool second = d1 < d0 || (d1 == d0 && own[1].normal.dot(out[1].pr.normal) < own[0].normal.dot(out[0].pr.normal));
      // The side that already has the contact keeps it unless the other is nearer by more than
      // half the detection distance: a corner nested in a shallow concave corner (a vertex of the
      // opening's 24 sides, 15 degrees, in the block wrapped around it) is about as near to both
      // planes, and choosing by the nearer alone switched its contact between them every few
      // hundred steps, each switch a new key, then a fresh law state, and a normal turned by 15
      // degrees: a stage that never settled.
      std::size_t hint = 0;
      const LocalIndex local = m.gp[A.boundary[k]].local;
      const bool held0 = m.contacts.find({A.id, local, B.id, 0}, hint) != nullptr;
      const bool held1 = m.contacts.find({A.id, local, B.id, 1}, hint) != nullptr;
      if (held0 != held1) second = held1 ? d1 < d0 + 0.5 * s.distance : d1 < d0 - 0.5 * s.distance;
      if (second) out[0] = out[1];
      nf = 1;
    }
    if (nf > 0) return nf;
    Projection pr = closest_edge(m, B, gb, p, m.contacts.rounding, s.distance);
    if (nsides == 2) corner_to_corner(m, A, ga, k, pr);
    // Key the contact by the own side that faces it best, so that a contact moving between the
    // face and the rounded descriptions keeps its key and its state.
    const int side = nsides == 2 && own[1].normal.dot(pr.normal) < own[0].normal.dot(pr.normal) ? 1 : 0;
    out[0] = {side, false, pr};
    return 1;
  };
  auto scan = [&](int ia, int ib, std::vector<Contact>& out, std::size_t& hint) {
    const Block& A = m.blocks[ia];
    const Block& B = m.blocks[ib];
    const Box bb = block_box(m, B, s.distance);
    const BoundaryEdge* ga = geometry.of(ia);
    const BoundaryEdge* gb = geometry.of(ib);
    const int na = static_cast<int>(A.boundary.size());
    Candidate cand[2];
    for (int k = 0; k < na; ++k) {
      const int g = A.boundary[k];
      const Vec2& p = m.gp[g].x;
      if (p.x() < bb.lo.x() || p.x() > bb.hi.x() || p.y() < bb.lo.y() || p.y() > bb.hi.y()) continue;
      const int nc = candidates(A, ga, k, B, gb, cand);
      for (int ic = 0; ic < nc; ++ic) {
        const Projection& pr = cand[ic].pr;
        if (pr.dist > 10.0 * s.distance) continue;
        const ContactKey key{A.id, m.gp[g].local, B.id, cand[ic].side};
        const Contact* old = m.contacts.find(key, hint);
        const bool closed = old && !old->response.open && !old->fresh;
        if (pr.dist > s.distance && !closed) continue;
        Contact c;
        c.key = key;
        c.point = g;
        c.point_loop = k;
        c.face_mode = cand[ic].face;
        c.other = ib;
        c.edge = pr.edge;
        c.s = pr.s;
        c.normal = pr.normal;
        c.overlap = -pr.dist;
        c.joint = m.contacts.model_for(A.group, B.group, B.edge_label(pr.edge));
        if (closed && old->joint != c.joint && keeps_model_at_vertex(m, A, B, gb, p, pr.edge, old->joint)) c.joint = old->joint;
        if (old) c.pretouch_gap = old->pretouch_gap;
        else c.pretouch_gap = std::max(0.0, pr.dist);  // not yet touching: the law starts when it closes
        c.pending_closure = old ? old->pending_closure : std::max(0.0, -pr.dist);
        out.push_back(c);
      }
    }
  };
  if (threads <= 1 || pairs.size() < static_cast<std::size_t>(kThreadedLoopMin)) {
    std::size_t hint = 0;
    for (const auto& [i, j] : pairs) {
      scan(i, j, found, hint);
      scan(j, i, found, hint);
    }
  } else {
    // Stretches of the pair list on several threads, each into its own list; the lists joined in
    // order give the contacts in the order one thread finds them. More stretches than threads, so
    // that a thread that drew a dense part of the model does not leave the others waiting.
    const std::size_t nchunks = std::min<std::size_t>(8 * static_cast<std::size_t>(threads), pairs.size());
    buffers.chunks.resize(nchunks);
    threaded_chunks(threads, static_cast<std::ptrdiff_t>(nchunks), [&](std::ptrdiff_t ci) {
      std::vector<Contact>& out = buffers.chunks[static_cast<std::size_t>(ci)];
      out.clear();
      std::size_t hint = 0;
      const std::size_t first = pairs.size() * static_cast<std::size_t>(ci) / nchunks;
      const std::size_t last = pairs.size() * static_cast<std::size_t>(ci + 1) / nchunks;
      for (std::size_t p = first; p < last; ++p) {
        scan(pairs[p].first, pairs[p].second, out, hint);
        scan(pairs[p].second, pairs[p].first, out, hint);
      }
    });
    for (std::size_t ci = 0; ci < nchunks; ++ci) found.insert(found.end(), buffers.chunks[ci].begin(), buffers.chunks[ci].end());
  }
  const std::size_t created = m.contacts.merge(std::move(found));
  update_contact_lengths(m, s, threads);
  return created;
}

void update_contact_geometry(Model& m, int threads) {
  BoundaryGeometry& geometry = boundary_geometry();
  geometry.update(m, m.contacts.rounding, threads);
  // Each contact reads positions and writes only itself: on several threads as they come.
  threaded_for(threads, 0, static_cast<std::ptrdiff_t>(m.contacts.items.size()), [&](std::ptrdiff_t ic) {
    Contact& c = m.contacts.items[static_cast<std::size_t>(ic)];
    const Block& B = m.blocks[c.other];
    const int ia = m.gp[c.point].block;
    const Block& A = m.blocks[ia];
    const BoundaryEdge* ga = geometry.of(ia);
    const BoundaryEdge* gb = geometry.of(c.other);
    const int n = static_cast<int>(B.boundary.size());
    const Vec2& p = m.gp[c.point].x;
    int e = c.edge;
    // Face mode: slide along the facing edges of the other block, staying on the last one beyond
    // the face's end (see face_projection).
    Projection pr;
    const OwnSide own = own_side(m, A, ga, c.point_loop, c.key.side);
    if (c.face_mode && face_projection(m, B, gb, p, own, e, kInf, -kInf, pr)) {
      const int dir = pr.s >= 1.0 ? 1 : -1;
      for (int it = 0; it < n && (dir > 0 ? pr.s >= 1.0 : pr.s <= 0.0); ++it) {
        const int next = (e + dir + n) % n;
        Projection q;
        if (!face_projection(m, B, gb, p, own, next, kInf, -kInf, q)) break;
        // Beyond the end of this edge and before the start of the next (outside a convex vertex
        // of the other block) the point stays where it is: moving on put it before the next
        // edge's start, and the step after moved it back, the normal turning by the vertex's angle
        // every step (a point at a 15-degree vertex of the opening: a contact and its mirror fed
        // alternating normals, their stresses drifting apart and the stage never settling).
        if (dir > 0 ? q.s <= 0.0 : q.s >= 1.0) break;
        e = next;
        pr = q;
      }
      bend_at_vertex(m, B, gb, p, own, m.contacts.rounding, pr);
      c.edge = e;
      c.s = pr.s;
      c.normal = pr.normal;
      c.overlap = -pr.dist;
      return;
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
    pr = project_rounded(m, B, gb, p, e);
    if (!own.flat) corner_to_corner(m, A, ga, c.point_loop, pr);
    c.s = pr.s;
    c.normal = pr.normal;
    c.overlap = -pr.dist;
  });
}

void update_contact_lengths(Model& m, const DetectionSettings& s, int threads) {
  auto& items = m.contacts.items;
  const double w = s.distance;
  // Own and facing intervals, on the tangent through each contact point (ClusterSpan).
  // Cluster by block pair and normal direction (normals of the second block's points flipped).
  // The clusters of a block pair are chained from the pair's entry in a flat table; spans are
  // gathered cluster by cluster afterwards (a stable counting sort), all in buffers kept between
  // calls (ClusterBuffers, broad_phase.hpp).
  ClusterBuffers& cb = cluster_buffers();
  auto& clusters = cb.clusters;
  clusters.clear();
  cb.pairs.reset(items.size());
  // The clusters, in contact order (a cluster's normal is its first contact's); then each
  // contact's stretch on its cluster's tangent, on several threads (each writes its own span).
  cb.cluster_of.resize(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Contact& c = items[i];
    const BlockId a = std::min(c.key.point_block, c.key.other_block);
    const BlockId b = std::max(c.key.point_block, c.key.other_block);
    const Vec2 n = c.key.point_block == a ? c.normal : Vec2(-c.normal);
    const std::int64_t pk = (static_cast<std::int64_t>(a) << 32) | static_cast<std::uint32_t>(b);
    int& head = cb.pairs.at(pk);
    int ci = -1, last = -1;
    for (int k = head; k >= 0; last = k, k = clusters[static_cast<std::size_t>(k)].next)
      if (clusters[static_cast<std::size_t>(k)].n.dot(n) > kSamePlaneCos) { ci = k; break; }
    if (ci < 0) {
      ci = static_cast<int>(clusters.size());
      clusters.push_back({n, -1});
      (last < 0 ? head : clusters[static_cast<std::size_t>(last)].next) = ci;
    }
    cb.cluster_of[i] = ci;
  }
  cb.spans.resize(items.size());
  threaded_for(threads, 0, static_cast<std::ptrdiff_t>(items.size()), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const Contact& c = items[i];
    const int ci = cb.cluster_of[i];
    const Vec2 t(clusters[static_cast<std::size_t>(ci)].n.y(), -clusters[static_cast<std::size_t>(ci)].n.x());
    // Own tributary: the half-edges on both sides of the point, inside the contact band.
    const Block& A = m.blocks[m.gp[c.point].block];
    const Block& B = m.blocks[c.other];
    const int na = static_cast<int>(A.boundary.size());
    const int local = c.point_loop;
    const Vec2& p = m.gp[c.point].x;
    const Vec2& prev = m.gp[A.boundary[(local - 1 + na) % na]].x;
    const Vec2& next = m.gp[A.boundary[(local + 1) % na]].x;
    // The band reaches from the point to the other block's surface (height `overlap` along the
    // normal) and the tolerance w beyond both: a point pressed deeper than w still meets the
    // surface it is pressed into and keeps a length (with a band of +-w about the point alone, a
    // corner 30 mm deep had length 0, carried no force and sank further).
    const double bl = std::min(0.0, c.overlap) - w, bh = std::max(0.0, c.overlap) + w;
    double lo = 0.0, hi = 0.0, l1, h1;
    bool any = false;
    if (band_interval(0.5 * (prev + p), p, p, c.normal, t, bl, bh, l1, h1)) { lo = l1; hi = h1; any = true; }
    if (band_interval(p, 0.5 * (p + next), p, c.normal, t, bl, bh, l1, h1)) {
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
        if (!band_interval(ea, eb, p, c.normal, t, bl, bh, l1, h1)) break;
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
    items[i].span = any ? hi - lo : 0.0;
    cb.spans[i] = {ci, i, base + x0, base + std::max(x0, x1), base, touching};
  });
  // Spans cluster by cluster, each cluster's in contact order.
  cb.start.assign(clusters.size() + 1, 0);
  for (const ClusterSpan& sp : cb.spans) ++cb.start[static_cast<std::size_t>(sp.cluster) + 1];
  for (std::size_t k = 1; k < cb.start.size(); ++k) cb.start[k] += cb.start[k - 1];
  cb.sorted.resize(cb.spans.size());
  cb.cursor.assign(cb.start.begin(), cb.start.end() - 1);
  for (const ClusterSpan& sp : cb.spans) cb.sorted[cb.cursor[static_cast<std::size_t>(sp.cluster)]++] = &sp;
  // Each touching contact owns its Voronoi cell among the touching contacts of both blocks along
  // the interface, clipped to its own stretch. The cells partition the overlap, and they change
  // continuously as points of one block slide past points of the other or past an edge's end
  // (a newly covered point starts with a cell of zero length, not with half its tributary).
  // Points at the same place (the coincident corners of two equal blocks stacked, a point and its
  // mirror, the other block's point at the same vertex) stand for one place of the joint and share
  // its cell: each part of it goes in equal shares to those whose own stretch covers it. The same
  // place is within half the rounding length, the resolution of the corners' geometry (not the
  // detection distance, which laboratory cases set to centimetres): with 1e-9 of the detection
  // distance, the tip of a 6-degree sliver and the corner beside it, micrometres apart and each
  // with its stretch on one side, took the whole 0.36 m cell in turn as round-off moved one past
  // the other, and the stage never settled. Mixing the shares into the points' own cells in
  // proportion to their spread (so that the hand-over is gradual) was tried and not kept: a
  // length that changes with micrometres of motion while the stress stays does work no force did,
  // and in the drift study's test without shaking, with elastic joints, motion grew from nothing
  // at a four-block crossing (2.6e-7 m/s in 2 s; with the step, 5.5e-10).
  auto& touching = cb.touching;
  const double tie = std::max(1e-9 * w, 0.5 * m.contacts.rounding);
  std::vector<double>& cuts = cb.cuts;
  for (std::size_t cl = 0; cl < clusters.size(); ++cl) {
    touching.clear();
    for (std::size_t k = cb.start[cl]; k < cb.start[cl + 1]; ++k) {
      const ClusterSpan& sp = *cb.sorted[k];
      if (sp.touching) touching.push_back(&sp);
      else items[sp.c].length = sp.hi - sp.lo;  // carries no stress; kept for output
    }
    std::sort(touching.begin(), touching.end(),
              [](const ClusterSpan* a, const ClusterSpan* b) { return a->at < b->at || (a->at == b->at && a->c < b->c); });
    const std::size_t nt = touching.size();
    for (std::size_t k = 0; k < nt;) {
      std::size_t end = k + 1;
      while (end < nt && touching[end]->at - touching[k]->at <= tie) ++end;
      const double left = k > 0 ? 0.5 * (touching[k - 1]->at + touching[k]->at) : -kInf;
      const double right = end < nt ? 0.5 * (touching[end - 1]->at + touching[end]->at) : kInf;
      if (end == k + 1) {
        const ClusterSpan& sp = *touching[k];
        items[sp.c].length = std::max(0.0, std::min(sp.hi, right) - std::max(sp.lo, left));
      } else {
        cuts.clear();
        for (std::size_t q = k; q < end; ++q) {
          items[touching[q]->c].length = 0.0;
          cuts.push_back(std::clamp(touching[q]->lo, left, right));
          cuts.push_back(std::clamp(touching[q]->hi, left, right));
        }
        std::sort(cuts.begin(), cuts.end());
        for (std::size_t q = 0; q + 1 < cuts.size(); ++q) {
          const double a = cuts[q], b = cuts[q + 1], mid = 0.5 * (a + b);
          if (b <= a) continue;
          int cover = 0;
          for (std::size_t r = k; r < end; ++r) cover += touching[r]->lo <= mid && mid <= touching[r]->hi;
          for (std::size_t r = k; r < end; ++r)
            if (touching[r]->lo <= mid && mid <= touching[r]->hi) items[touching[r]->c].length += (b - a) / cover;
        }
      }
      k = end;
    }
  }
  // Hand-over: a contact created already pressed into a joint that carries load (a point that has
  // slid in under an edge of the other block, or whose neighbour changed owner) takes the law state
  // of the nearest established contact of the same interface and joint model, so that the mated
  // position, the stresses and the wear it starts from are the joint's, not a fresh surface's.
  for (std::size_t cl = 0; cl < clusters.size(); ++cl) {
    for (std::size_t k = cb.start[cl]; k < cb.start[cl + 1]; ++k) {
      const ClusterSpan& sp = *cb.sorted[k];
      Contact& c = items[sp.c];
      if (!c.fresh || c.pending_closure <= 0.0 || c.pretouch_gap > 0.0) continue;
      const Contact* donor = nullptr;
      std::size_t donor_at = 0;
      double best = kInf;
      for (std::size_t q = cb.start[cl]; q < cb.start[cl + 1]; ++q) {
        const ClusterSpan& o = *cb.sorted[q];
        const Contact& d = items[o.c];
        if (d.fresh || !o.touching || d.joint != c.joint || std::abs(o.at - sp.at) >= best) continue;
        best = std::abs(o.at - sp.at);
        donor = &d;
        donor_at = o.c;
      }
      if (!donor) continue;
      std::memcpy(m.contacts.states.at(sp.c), m.contacts.states.at(donor_at), m.contacts.states.stride());
      c.response = donor->response;
      c.pending_closure = 0.0;
    }
  }
}

}  // namespace rockdem
