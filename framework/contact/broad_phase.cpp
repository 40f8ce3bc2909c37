#include "framework/contact/broad_phase.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "framework/contact/detection.hpp"
#include "framework/core/error.hpp"

namespace rockdem {
namespace {

struct Box {
  Vec2 lo, hi;
};

// The grid's own arrays, kept between passes with the rest of the detection buffers.
struct GridBuffers {
  std::vector<Box> boxes;
  std::vector<int> start;    // per cell: first entry (counting sort), size cells + 1
  std::vector<int> entries;  // block indices, cell by cell
  std::vector<int> cursor;   // per cell: next entry to fill
  std::vector<std::int32_t> cell_lo;  // per block: x0, x1, y0, y1 cell ranges
};

GridBuffers& grid_buffers() {
  thread_local GridBuffers g;
  return g;
}

}  // namespace

DetectionBuffers& detection_buffers() {
  thread_local DetectionBuffers b;
  return b;
}

ClusterBuffers& cluster_buffers() {
  thread_local ClusterBuffers b;
  return b;
}

void PairTable::reset(std::size_t expected) {
  std::size_t size = 16;
  while (size < 2 * expected) size *= 2;
  keys_.assign(size, -1);  // block ids are not negative, so no pair key is -1
  values_.resize(size);
}

int& PairTable::at(std::int64_t key) {
  const std::size_t mask = keys_.size() - 1;
  auto h = static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull;
  for (std::size_t s = static_cast<std::size_t>(h >> 32) & mask;; s = (s + 1) & mask) {
    if (keys_[s] == key) return values_[s];
    if (keys_[s] == -1) {
      keys_[s] = key;
      values_[s] = -1;
      return values_[s];
    }
  }
}

void broad_phase_pairs(const Model& m, double margin, std::vector<std::pair<int, int>>& pairs) {
  pairs.clear();
  const int nb = static_cast<int>(m.blocks.size());
  if (nb < 2) return;
  GridBuffers& g = grid_buffers();
  g.boxes.resize(static_cast<std::size_t>(nb));
  const Box empty{Vec2::Constant(std::numeric_limits<double>::max()), Vec2::Constant(-std::numeric_limits<double>::max())};
  Box all = empty;
  double mean_size = 0.0;
  // A decomposed run (partition.hpp) looks only at blocks whose state is current here, and keeps
  // the pairs with a block of its own.
  const Partition& part = m.part;
  int counted = 0;
  for (int i = 0; i < nb; ++i) {
    Box& box = g.boxes[static_cast<std::size_t>(i)];
    box = empty;
    if (!part.current(i)) continue;
    ++counted;
    for (int p : m.blocks[static_cast<std::size_t>(i)].boundary) {
      box.lo = box.lo.cwiseMin(m.gp[static_cast<std::size_t>(p)].x);
      box.hi = box.hi.cwiseMax(m.gp[static_cast<std::size_t>(p)].x);
    }
    box.lo.array() -= margin;
    box.hi.array() += margin;
    all.lo = all.lo.cwiseMin(box.lo);
    all.hi = all.hi.cwiseMax(box.hi);
    mean_size += (box.hi - box.lo).maxCoeff();
  }
  if (counted < 2) return;
  mean_size /= counted;
  // A non-finite box would make the grid below infinitely large (its sizing loop never ends and
  // the cell arrays grow without bound); the engine stops such a state first, this is the guard.
  if (!all.lo.allFinite() || !all.hi.allFinite() || !std::isfinite(mean_size))
    throw InstabilityError("contact detection: a block has a non-finite or overflowing position (extent " +
                           std::to_string(all.hi.x() - all.lo.x()) + " m by " + std::to_string(all.hi.y() - all.lo.y()) +
                           " m); check stiffnesses, sizes, time functions and the time step");
  // Cells about the mean block size, so that each block covers a few cells and each cell holds a
  // few blocks; no more cells than 4 per block, so that a sparse model (a few blocks far apart)
  // does not get a huge empty grid.
  const Vec2 extent = all.hi - all.lo;
  double cell = std::max({mean_size, std::sqrt(extent.x() * extent.y() / (4.0 * nb)), 1e-12});
  auto cells_along = [&](double e) { return static_cast<std::int64_t>(std::floor(e / cell)) + 1; };
  while (cells_along(extent.x()) * cells_along(extent.y()) > 4LL * nb + 16) cell *= 1.5;
  const auto nx = static_cast<int>(cells_along(extent.x())), ny = static_cast<int>(cells_along(extent.y()));
  auto cx = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - all.lo.x()) / cell)), 0, nx - 1); };
  auto cy = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - all.lo.y()) / cell)), 0, ny - 1); };
  // Counting sort of the blocks by the cells their boxes cover.
  g.start.assign(static_cast<std::size_t>(nx) * ny + 1, 0);
  g.cell_lo.resize(4 * static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) {
    const Box& b = g.boxes[static_cast<std::size_t>(i)];
    std::int32_t* r = &g.cell_lo[4 * static_cast<std::size_t>(i)];
    if (!part.current(i)) {  // in no cell
      r[0] = r[2] = 0;
      r[1] = r[3] = -1;
      continue;
    }
    r[0] = cx(b.lo.x());
    r[1] = cx(b.hi.x());
    r[2] = cy(b.lo.y());
    r[3] = cy(b.hi.y());
    for (int y = r[2]; y <= r[3]; ++y)
      for (int x = r[0]; x <= r[1]; ++x) ++g.start[static_cast<std::size_t>(y) * nx + x + 1];
  }
  for (std::size_t c = 1; c < g.start.size(); ++c) g.start[c] += g.start[c - 1];
  g.entries.resize(static_cast<std::size_t>(g.start.back()));
  g.cursor.assign(g.start.begin(), g.start.end() - 1);
  for (int i = 0; i < nb; ++i) {
    const std::int32_t* r = &g.cell_lo[4 * static_cast<std::size_t>(i)];
    for (int y = r[2]; y <= r[3]; ++y)
      for (int x = r[0]; x <= r[1]; ++x) g.entries[static_cast<std::size_t>(g.cursor[static_cast<std::size_t>(y) * nx + x]++)] = i;
  }
  // Pairs within each cell, each reported from one cell only: the one holding the lower-left
  // corner of the two boxes' intersection.
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const std::size_t c = static_cast<std::size_t>(y) * nx + x;
      for (int a = g.start[c]; a < g.start[c + 1]; ++a)
        for (int b = a + 1; b < g.start[c + 1]; ++b) {
          const int i = std::min(g.entries[static_cast<std::size_t>(a)], g.entries[static_cast<std::size_t>(b)]);
          const int j = std::max(g.entries[static_cast<std::size_t>(a)], g.entries[static_cast<std::size_t>(b)]);
          const Box &A = g.boxes[static_cast<std::size_t>(i)], &B = g.boxes[static_cast<std::size_t>(j)];
          if (!(A.lo.x() <= B.hi.x() && B.lo.x() <= A.hi.x() && A.lo.y() <= B.hi.y() && B.lo.y() <= A.hi.y())) continue;
          if (cx(std::max(A.lo.x(), B.lo.x())) != x || cy(std::max(A.lo.y(), B.lo.y())) != y) continue;
          if (!part.owns(i) && !part.owns(j)) continue;
          pairs.emplace_back(i, j);
        }
    }
  // The order the narrow phase visits pairs in (and so the order of the contact list) stays the
  // one of the earlier hash-grid broad phase: sorted by (i, j).
  std::sort(pairs.begin(), pairs.end());
}

std::vector<std::pair<int, int>> broad_phase(const Model& m, double margin) {
  std::vector<std::pair<int, int>> pairs;
  broad_phase_pairs(m, margin, pairs);
  return pairs;
}

}  // namespace rockdem
