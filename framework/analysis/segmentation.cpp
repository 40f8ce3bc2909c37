// Segmentation of a shear record into stages, monotonic segments, cycles and quadrants; see
// segmentation.hpp for the definitions. One pass per stage, no allocation per row beyond the
// label vector, so that calibration can afford to call it on every model evaluation.
#include "framework/analysis/segmentation.hpp"

#include <algorithm>
#include <cmath>

namespace rockdem {
namespace {

int quadrant_of(int side, bool away) {
  if (side > 0) return away ? 1 : 4;
  return away ? 3 : 2;
}

double median(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Rows of one segment that share a quadrant: moving away from u = 0 or returning toward it.
struct Part {
  std::size_t begin, end;
  int side;      // side of u = 0 the rows are on
  bool away;
  bool reached;  // a returning part that arrived at the origin (within the threshold) or crossed it
};

}  // namespace

const StageInfo* Segmentation::find_stage(int stage) const {
  for (const auto& s : stages)
    if (s.stage == stage) return &s;
  return nullptr;
}

void find_reversals(const MeasurementFile& f, std::size_t b, std::size_t e, double h, std::vector<std::size_t>& turns,
                    int& first_motion) {
  // A reversal is confirmed once the displacement has come back by more than h from the running
  // extreme. Before the first stroke is confirmed, small wiggles around the start are noise and
  // belong to the first segment.
  const auto& rows = f.rows;
  auto u = [&](std::size_t i) { return rows[i].shear_disp_mm; };
  turns.clear();
  first_motion = 0;
  if (b >= e) return;
  int dir = 0;
  std::size_t ext = b, imin = b, imax = b;
  for (std::size_t i = b + 1; i < e; ++i) {
    const double ui = u(i);
    if (dir == 0) {
      if (ui > u(imax)) imax = i;
      if (ui < u(imin)) imin = i;
      if (u(imax) - ui > h) {
        dir = first_motion = -1;
        ext = i;
      } else if (ui - u(imin) > h) {
        dir = first_motion = +1;
        ext = i;
      }
    } else if (dir > 0) {
      if (ui > u(ext)) {
        ext = i;
      } else if (u(ext) - ui > h) {
        turns.push_back(ext);
        dir = -1;
        ext = i;
      }
    } else {
      if (ui < u(ext)) {
        ext = i;
      } else if (ui - u(ext) > h) {
        turns.push_back(ext);
        dir = +1;
        ext = i;
      }
    }
  }
}

double stage_normal_stress(const MeasurementFile& f, std::size_t begin, std::size_t end) {
  std::vector<double> sigma;
  sigma.reserve(end - begin);
  for (std::size_t i = begin; i < end; ++i) sigma.push_back(f.rows[i].normal_stress_MPa);
  return median(sigma);
}

Segmentation segment(const MeasurementFile& f, const SegmentationOptions& options) {
  Segmentation out;
  const auto& rows = f.rows;
  out.labels.resize(rows.size());
  std::vector<std::size_t> turns;
  auto u = [&](std::size_t i) { return rows[i].shear_disp_mm; };

  std::size_t b = 0;
  while (b < rows.size()) {
    std::size_t e = b;
    const int stage_no = rows[b].stage;
    while (e < rows.size() && rows[e].stage == stage_no) ++e;

    StageInfo st;
    st.stage = stage_no;
    st.begin = b;
    st.end = e;
    st.u_min = st.u_max = u(b);
    for (std::size_t i = b; i < e; ++i) {
      st.u_min = std::min(st.u_min, u(i));
      st.u_max = std::max(st.u_max, u(i));
    }
    st.normal_stress_MPa = stage_normal_stress(f, b, e);
    const auto given = options.threshold_mm.find(stage_no);
    const double h = given != options.threshold_mm.end() ? given->second
                                                         : options.reversal_fraction * (st.u_max - st.u_min);
    st.threshold = h;

    int first_dir = 0;
    find_reversals(f, b, e, h, turns, first_dir);

    st.first_segment = out.segments.size();
    st.segment_count = turns.size() + 1;
    for (std::size_t k = 0; k <= turns.size(); ++k) {
      Segment sg;
      sg.stage = stage_no;
      sg.index = static_cast<int>(k);
      sg.motion = first_dir == 0 ? 0 : (k % 2 == 0 ? first_dir : -first_dir);
      sg.curve_begin = k == 0 ? b : turns[k - 1];
      sg.begin = k == 0 ? b : turns[k - 1] + 1;
      sg.end = k < turns.size() ? turns[k] + 1 : e;
      sg.u_start = u(sg.curve_begin);
      sg.u_end = u(sg.end - 1);
      out.segments.push_back(sg);
    }

    // Quadrants and cycles. A segment that starts near the origin (within h) moves away on the
    // side it moves to; one that starts beyond h returns toward the origin and, if it ends beyond
    // h on the other side, moves away again from its first passage through zero. A new cycle
    // starts when the joint moves away on the first stroke's side after having come back.
    int cycle = 1, s0 = 0;
    bool first_part = true, prev_reached = false;
    Part parts[2];
    for (std::size_t k = st.first_segment; k < out.segments.size(); ++k) {
      const Segment& sg = out.segments[k];
      auto label = [&](std::size_t i, int quadrant, int direction) {
        out.labels[i] = RowLabel{stage_no, sg.index, cycle, quadrant, direction, sg.motion};
      };
      if (sg.motion == 0) {
        for (std::size_t i = sg.begin; i < sg.end; ++i) label(i, 0, 0);
        continue;
      }
      const int m = sg.motion;
      const int start_side = std::abs(sg.u_start) > h ? (sg.u_start > 0 ? 1 : -1) : m;
      int nparts = 0;
      if (start_side == m) {
        parts[nparts++] = Part{sg.begin, sg.end, m, true, false};
      } else if (m * sg.u_end > h) {
        std::size_t r = sg.begin;
        while (r < sg.end && m * u(r) < 0.0) ++r;
        parts[nparts++] = Part{sg.begin, r, -m, false, true};
        parts[nparts++] = Part{r, sg.end, m, true, false};
      } else {
        parts[nparts++] = Part{sg.begin, sg.end, -m, false, std::abs(sg.u_end) <= h};
      }
      for (int p = 0; p < nparts; ++p) {
        const Part& pt = parts[p];
        if (pt.begin == pt.end) {  // crossed zero within one sample: still a return to the origin
          prev_reached = prev_reached || pt.reached;
          continue;
        }
        if (s0 == 0) s0 = pt.side;
        if (pt.away && pt.side == s0 && !first_part && prev_reached) ++cycle;
        const int q = quadrant_of(pt.side, pt.away);
        for (std::size_t i = pt.begin; i < pt.end; ++i) label(i, q, pt.away ? 1 : -1);
        prev_reached = !pt.away && pt.reached;
        first_part = false;
      }
    }
    st.first_side = s0;
    st.cycles = cycle;
    out.stages.push_back(st);
    b = e;
  }
  return out;
}

std::string quadrant_phrase(int quadrant) {
  switch (quadrant) {
    case 1: return "forward shearing (quadrant 1)";
    case 4: return "reverse shearing (quadrant 4)";
    case 3: return "forward shearing on the negative side (quadrant 3)";
    case 2: return "reverse shearing from the negative side (quadrant 2)";
    default: return "no shear motion";
  }
}

}  // namespace rockdem
