#include "framework/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rockdem {

namespace {

double cross3(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }

double point_segment_distance(const Vec2& q, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  double t = l2 > 0.0 ? (q - a).dot(ab) / l2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (a + t * ab - q).norm();
}

bool on_segment_exact(const Vec2& q, const Vec2& a, const Vec2& b) {
  return cross3(a, b, q) == 0.0 && std::min(a.x(), b.x()) <= q.x() && q.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= q.y() && q.y() <= std::max(a.y(), b.y());
}

// True if segments ab and cd touch or cross (tol = 0: exact orientation tests; tol > 0: their
// distance is at most tol).
bool segments_touch(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double tol) {
  const double d1 = cross3(a, b, c), d2 = cross3(a, b, d), d3 = cross3(c, d, a), d4 = cross3(c, d, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  if (tol > 0.0) {
    const double dist = std::min({point_segment_distance(a, c, d), point_segment_distance(b, c, d),
                                  point_segment_distance(c, a, b), point_segment_distance(d, a, b)});
    return dist <= tol;
  }
  return on_segment_exact(c, a, b) || on_segment_exact(d, a, b) || on_segment_exact(a, c, d) ||
         on_segment_exact(b, c, d);
}

double abs_area(const std::vector<Vec2>& p) { return std::abs(signed_area(p)); }

// Sutherland-Hodgman: clip `subject` by the convex counter-clockwise polygon `clip`.
std::vector<Vec2> clip_convex(std::vector<Vec2> subject, const std::vector<Vec2>& clip) {
  std::vector<Vec2> out;
  for (size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const Vec2& a = clip[e];
    const Vec2& b = clip[(e + 1) % clip.size()];
    out.clear();
    for (size_t i = 0; i < subject.size(); ++i) {
      const Vec2& p = subject[i];
      const Vec2& q = subject[(i + 1) % subject.size()];
      const double sp = cross3(a, b, p), sq = cross3(a, b, q);
      if (sp >= 0.0) out.push_back(p);
      if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    subject.swap(out);
  }
  return subject;
}

struct Box {
  Vec2 lo, hi;
};
Box bounding_box(const Polygon& p) {
  Box b{p[0], p[0]};
  for (const auto& v : p) {
    b.lo = b.lo.cwiseMin(v);
    b.hi = b.hi.cwiseMax(v);
  }
  return b;
}

}  // namespace

double signed_area(const Polygon& p) {
  if (p.size() < 3) return 0.0;
  const Vec2 o = p[0];  // shift to the first vertex: avoids cancellation far from the origin
  double a = 0.0;
  for (size_t i = 1; i + 1 < p.size(); ++i) a += cross(p[i] - o, p[i + 1] - o);
  return 0.5 * a;
}

double perimeter(const Polygon& p) {
  double s = 0.0;
  for (size_t i = 0; i < p.size(); ++i) s += (p[(i + 1) % p.size()] - p[i]).norm();
  return s;
}

Vec2 polygon_centroid(const Polygon& p) {
  const Vec2 o = p.at(0);
  double a = 0.0;
  Vec2 s = Vec2::Zero();
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2 u = p[i] - o, w = p[(i + 1) % p.size()] - o;
    const double c = cross(u, w);
    a += c;
    s += c * (u + w);
  }
  if (a == 0.0) throw std::invalid_argument("polygon_centroid: polygon has zero area");
  return o + s / (3.0 * a);
}

SecondMoments second_moments(const Polygon& p) {
  // Moments about the first vertex, then the parallel-axis theorem to the centroid.
  const Vec2 o = p.at(0);
  double a = 0.0, sx = 0.0, sy = 0.0, ixx = 0.0, iyy = 0.0, ixy = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2 u = p[i] - o, w = p[(i + 1) % p.size()] - o;
    const double c = cross(u, w);
    a += 0.5 * c;
    sx += c * (u.x() + w.x()) / 6.0;
    sy += c * (u.y() + w.y()) / 6.0;
    ixx += c * (u.y() * u.y() + u.y() * w.y() + w.y() * w.y()) / 12.0;
    iyy += c * (u.x() * u.x() + u.x() * w.x() + w.x() * w.x()) / 12.0;
    ixy += c * (u.x() * w.y() + 2.0 * u.x() * u.y() + 2.0 * w.x() * w.y() + w.x() * u.y()) / 24.0;
  }
  if (a == 0.0) throw std::invalid_argument("second_moments: polygon has zero area");
  const double cx = sx / a, cy = sy / a;
  SecondMoments m;
  m.ixx = ixx - a * cy * cy;
  m.iyy = iyy - a * cx * cx;
  m.ixy = ixy - a * cx * cy;
  if (a < 0.0) {  // clockwise input: every sum changed sign
    m.ixx = -m.ixx;
    m.iyy = -m.iyy;
    m.ixy = -m.ixy;
  }
  return m;
}

bool make_ccw(Polygon& p) {
  if (signed_area(p) >= 0.0) return false;
  std::reverse(p.begin() + 1, p.end());  // keeps p[0] first
  return true;
}

bool is_convex(const Polygon& p) {
  const size_t n = p.size();
  if (n < 3) return false;
  int sign = 0;
  for (size_t i = 0; i < n; ++i) {
    const double c = cross3(p[i], p[(i + 1) % n], p[(i + 2) % n]);
    const int s = (c > 0.0) - (c < 0.0);
    if (s == 0) continue;
    if (sign == 0) sign = s;
    if (s != sign) return false;
  }
  return sign != 0;
}

bool is_simple(const Polygon& p, double tol) {
  const size_t n = p.size();
  if (n < 3) return false;
  for (size_t i = 0; i < n; ++i)
    if ((p[(i + 1) % n] - p[i]).norm() <= tol) return false;
  if (signed_area(p) == 0.0) return false;
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % n];
    // Adjacent edge (b, c): must not fold back onto (a, b).
    const Vec2& c = p[(i + 2) % n];
    if (std::abs(cross3(a, b, c)) <= tol * (b - a).norm() && (c - b).dot(a - b) > 0.0) return false;
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing vertex
      if (segments_touch(a, b, p[j], p[(j + 1) % n], tol)) return false;
    }
  }
  return true;
}

PointLocation locate_point(const Vec2& q, const Polygon& p, double tol) {
  const size_t n = p.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % n];
    if (tol > 0.0 ? point_segment_distance(q, a, b) <= tol : on_segment_exact(q, a, b))
      return PointLocation::boundary;
  }
  return crossing_number_inside(q, n, [&](size_t i) -> const Vec2& { return p[i]; }) ? PointLocation::inside
                                                                                      : PointLocation::outside;
}

std::vector<std::array<int, 3>> triangulate_polygon(const Polygon& p_in) {
  std::vector<std::array<int, 3>> tris;
  const int n = static_cast<int>(p_in.size());
  if (n < 3) return tris;
  std::vector<int> idx(n);
  for (int i = 0; i < n; ++i) idx[i] = i;
  if (signed_area(p_in) < 0.0) std::reverse(idx.begin(), idx.end());
  const auto& p = p_in;
  // Relative threshold below which a corner is read as straight (removed without a triangle).
  double scale = 0.0;
  for (const auto& v : p) scale = std::max(scale, (v - p[0]).norm());
  const double flat = 1e-14 * scale * scale;

  while (idx.size() > 3) {
    const int m = static_cast<int>(idx.size());
    int best = -1;
    double best_cross = -std::numeric_limits<double>::infinity();
    bool clipped = false;
    for (int k = 0; k < m; ++k) {
      const int ia = idx[(k + m - 1) % m], ib = idx[k], ic = idx[(k + 1) % m];
      const double c = cross3(p[ia], p[ib], p[ic]);
      if (std::abs(c) <= flat) {  // straight corner: drop the vertex, no area lost
        idx.erase(idx.begin() + k);
        clipped = true;
        break;
      }
      if (c <= 0.0) continue;  // reflex
      if (c > best_cross) {
        best_cross = c;
        best = k;
      }
      bool ear = true;
      for (int r = 0; r < m && ear; ++r) {
        const int ir = idx[r];
        if (ir == ia || ir == ib || ir == ic) continue;
        if (p[ir] == p[ia] || p[ir] == p[ib] || p[ir] == p[ic]) continue;
        if (cross3(p[ia], p[ib], p[ir]) >= 0.0 && cross3(p[ib], p[ic], p[ir]) >= 0.0 &&
            cross3(p[ic], p[ia], p[ir]) >= 0.0)
          ear = false;
      }
      if (ear) {
        tris.push_back({ia, ib, ic});
        idx.erase(idx.begin() + k);
        clipped = true;
        break;
      }
    }
    if (!clipped) {
      // Only reachable through round-off on nearly degenerate input: clip the most convex corner.
      if (best < 0) break;
      tris.push_back({idx[(best + m - 1) % m], idx[best], idx[(best + 1) % m]});
      idx.erase(idx.begin() + best);
    }
  }
  if (idx.size() == 3 && std::abs(cross3(p[idx[0]], p[idx[1]], p[idx[2]])) > flat)
    tris.push_back({idx[0], idx[1], idx[2]});
  return tris;
}

double intersection_area(const Polygon& a, const Polygon& b) {
  const Box ba = bounding_box(a), bb = bounding_box(b);
  if ((ba.hi.array() < bb.lo.array()).any() || (bb.hi.array() < ba.lo.array()).any()) return 0.0;
  const auto ta = triangulate_polygon(a), tb = triangulate_polygon(b);
  double area = 0.0;
  for (const auto& s : ta) {
    const std::vector<Vec2> subject{a[s[0]], a[s[1]], a[s[2]]};
    for (const auto& t : tb) {
      const std::vector<Vec2> clip{b[t[0]], b[t[1]], b[t[2]]};
      const auto piece = clip_convex(subject, clip);
      if (piece.size() >= 3) area += abs_area(piece);
    }
  }
  return area;
}

bool polygons_overlap(const Polygon& a, const Polygon& b, double tol) {
  const double threshold = tol * 0.5 * std::min(perimeter(a), perimeter(b));
  // A small positive floor so that exact edge contact (area zero up to round-off) is not read
  // as overlap when tol = 0.
  const double scale = std::max(abs_area(a), abs_area(b));
  return intersection_area(a, b) > std::max(threshold, 1e-12 * scale);
}

}  // namespace rockdem
