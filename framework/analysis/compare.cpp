// Model/measurement comparison: compatibility checks, displacement alignment, error groups and
// the plain-language lines. See compare.hpp for the definitions.
#include "framework/analysis/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"

namespace rockdem {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string stage_list(const Segmentation& s) {
  const std::string out = join_names(s.stages, [](const auto& st) { return std::to_string(st.stage); });
  return out.empty() ? "none" : out;
}

std::string side_word(int side) { return side > 0 ? "positive" : side < 0 ? "negative" : "no"; }

std::string plural(std::size_t n, const char* word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// Running sums of one group; the stats follow at the end.
struct Acc {
  std::array<std::size_t, 2> n{};
  std::array<double, 2> e{}, e2{}, absm{}, mag{};
  void add(std::size_t v, double err, double measured) {
    ++n[v];
    e[v] += err;
    e2[v] += err * err;
    absm[v] += std::abs(measured);
    mag[v] += std::abs(measured + err) - std::abs(measured);
  }
};

ErrorGroup finish(int stage, int cycle, int quadrant, const Acc& a, const std::array<double, 2>& range) {
  ErrorGroup g;
  g.stage = stage;
  g.cycle = cycle;
  g.quadrant = quadrant;
  for (std::size_t v = 0; v < 2; ++v) {
    ErrorStats& s = g.var[v];
    s.n = a.n[v];
    if (s.n == 0) {
      s.rmse = s.nrmse = s.bias = s.magnitude_bias = s.mean_abs_measured = kNaN;
      continue;
    }
    const double n = static_cast<double>(s.n);
    s.rmse = std::sqrt(a.e2[v] / n);
    s.bias = a.e[v] / n;
    s.magnitude_bias = a.mag[v] / n;
    s.mean_abs_measured = a.absm[v] / n;
    s.nrmse = range[v] > 0.0 ? s.rmse / range[v] : kNaN;
  }
  return g;
}

// Interpolates the model curve rows [cb, ce) at progress coordinate x of each measured row in
// [db, de). progress(i) is monotone along an ideal segment; with noise the first passage is used:
// the running maximum of the model's progress is searched, and the interpolation runs between
// the two actual rows that straddle x, which is exact for a piecewise-linear model.
template <class ModelProgress, class DataProgress>
void interpolate(std::size_t db, std::size_t de, const MeasurementFile& model,
                 std::size_t cb, std::size_t ce, ModelProgress mp, DataProgress dp, std::vector<double>& runmax,
                 Alignment& out) {
  runmax.clear();
  double m = -std::numeric_limits<double>::infinity();
  for (std::size_t j = cb; j < ce; ++j) {
    m = std::max(m, mp(j));
    runmax.push_back(m);
  }
  for (std::size_t i = db; i < de; ++i) {
    const double x = dp(i);
    const auto k = static_cast<std::size_t>(std::lower_bound(runmax.begin(), runmax.end(), x) - runmax.begin());
    std::size_t j0 = 0, j1 = 0;
    double t = 0.0;
    if (k == 0 || k == runmax.size()) {
      j0 = j1 = k == 0 ? cb : ce - 1;
      if (k == runmax.size() || x < runmax.front()) ++out.outside;
    } else {
      j1 = cb + k;
      j0 = j1 - 1;
      const double x0 = mp(j0), x1 = mp(j1);  // x0 <= runmax[k-1] < x <= runmax[k] == x1
      t = x == x1 ? 1.0 : (x - x0) / (x1 - x0);
    }
    out.rows[i] = AlignedRow{j0, j1, t};
    for (std::size_t v = 0; v < 2; ++v) out.model[v][i] = aligned_value(out.rows[i], model, v);
  }
}

std::string worst_line(const ErrorGroup& g, std::size_t v, double range) {
  const CompareVariable& var = kCompareVariables[v];
  const ErrorStats& s = g.var[v];
  std::string where = "stage " + std::to_string(g.stage) + ", cycle " + std::to_string(g.cycle) + ", " +
                      quadrant_phrase(g.quadrant) + ": " + var.name + " ";
  const std::string unit = std::string(" ") + var.unit;
  const std::string tail = "; RMSE " + fmt("%.3g", s.rmse) + unit + ", NRMSE " + fmt("%.3f", s.nrmse) + ", " +
                           plural(s.n, "row");
  // Shear stress carries the shearing direction as its sign, so its over/under-prediction is one
  // of magnitude (strength); normal displacement keeps its sign (dilation positive).
  const bool magnitude = v == 0;
  const double b = magnitude ? s.magnitude_bias : s.bias;
  // A bias of at least half the RMSE is a systematic over/under-prediction; otherwise the model
  // scatters around the measurement (wrong shape, not wrong level).
  if (std::abs(b) >= 0.5 * s.rmse) {
    std::string line = where + (b > 0 ? "over" : "under") + "-predicted by " + fmt("%.3g", std::abs(b)) + unit +
                       (magnitude ? " in magnitude (" : b > 0 ? " (more dilation or less closure; " : " (less dilation or more closure; ");
    // A percentage of a near-zero mean (normal displacement near the mated position) says nothing.
    if (s.mean_abs_measured >= 0.05 * range) {
      line += fmt("%.0f", 100.0 * std::abs(b) / s.mean_abs_measured) + " % of the measured mean magnitude in this segment, " +
              fmt("%.3g", s.mean_abs_measured) + unit + ")";
    } else {
      line += "the measured values here are near zero: mean magnitude " + fmt("%.3g", s.mean_abs_measured) + unit + ")";
    }
    return line + tail;
  }
  return where + "off by " + fmt("%.3g", s.rmse) + unit + " RMS with little mean bias (" + fmt("%+.3g", b) +
         unit + "): scatter or a different shape rather than a level shift" + tail;
}

nlohmann::json stats_json(const ErrorStats& s) {
  return {{"n", s.n},         {"rmse", s.rmse}, {"nrmse", s.nrmse}, {"bias", s.bias}, {"magnitude_bias", s.magnitude_bias},
          {"mean_abs_measured", s.mean_abs_measured}};
}

nlohmann::json group_json(const ErrorGroup& g, bool stage, bool cycle, bool quadrant) {
  nlohmann::json j;
  if (stage) j["stage"] = g.stage;
  if (cycle) j["cycle"] = g.cycle;
  if (quadrant) j["quadrant"] = g.quadrant;
  for (std::size_t v = 0; v < 2; ++v) j[kCompareVariables[v].key] = stats_json(g.var[v]);
  return j;
}

}  // namespace

double compared_value(const MeasurementRow& r, std::size_t variable) {
  return variable == 0 ? r.shear_stress_MPa : r.normal_disp_mm;
}

double aligned_value(const AlignedRow& a, const MeasurementFile& model, std::size_t v) {
  if (a.j0 == AlignedRow::kNone) return kNaN;
  const double lo = compared_value(model.rows[a.j0], v), hi = compared_value(model.rows[a.j1], v);
  return a.t == 1.0 ? hi : lo + a.t * (hi - lo);  // a sample the model has is taken as is
}

SegmentationOptions model_segmentation_options(const Segmentation& data) {
  SegmentationOptions o;
  for (const auto& st : data.stages) o.threshold_mm[st.stage] = st.threshold;
  return o;
}

namespace {

void check_stage_lists(const Segmentation& data, const Segmentation& model) {
  bool same_stages = data.stages.size() == model.stages.size();
  for (std::size_t i = 0; same_stages && i < data.stages.size(); ++i)
    same_stages = data.stages[i].stage == model.stages[i].stage;
  if (!same_stages) {
    throw InputError("different stages: the measurement has stage(s) " + stage_list(data) + ", the model " +
                     stage_list(model));
  }
}

// What differs between stage i of the two records ("" if nothing); `structural` is set when it is
// the reversals (their number or where they are), which depend on the reversal threshold.
std::string stage_mismatch(const Segmentation& data, const Segmentation& model, std::size_t i,
                           const CompareOptions& options, bool& structural) {
  structural = false;
  const StageInfo& d = data.stages[i];
  const StageInfo& m = model.stages[i];
  const std::string st = "stage " + std::to_string(d.stage) + ": ";
  if (std::string why = normal_stress_mismatch(d, m.normal_stress_MPa, options); !why.empty()) return why;
  if (d.first_side != m.first_side) {
    return st + "opposite first strokes: the measurement first shears toward the " + side_word(d.first_side) +
           " side, the model toward the " + side_word(m.first_side) + " side";
  }
  const double amplitude = std::max(std::abs(d.u_min), std::abs(d.u_max));
  const double tol = options.endpoint_tolerance * amplitude;
  const std::string allowed = " (allowed difference " + fmt("%.3g", tol) + " mm, " +
                              fmt("%.3g", 100.0 * options.endpoint_tolerance) + " % of the amplitude " +
                              fmt("%.4g", amplitude) + " mm)";
  if (std::abs(d.u_max - m.u_max) > tol || std::abs(d.u_min - m.u_min) > tol) {
    return st + "different shear paths: the measurement spans " + fmt("%+.4g", d.u_min) + " .. " +
           fmt("%+.4g", d.u_max) + " mm, the model " + fmt("%+.4g", m.u_min) + " .. " + fmt("%+.4g", m.u_max) + " mm" +
           allowed;
  }
  structural = true;
  if (d.segment_count != m.segment_count || d.cycles != m.cycles) {
    return st + "different shear paths: the measurement has " + plural(d.segment_count - 1, "reversal") + " (" +
           plural(static_cast<std::size_t>(d.cycles), "cycle") + "), the model " +
           plural(m.segment_count - 1, "reversal") + " (" + plural(static_cast<std::size_t>(m.cycles), "cycle") + ")";
  }
  for (std::size_t k = 0; k < d.segment_count; ++k) {
    const Segment& ds = data.segments[d.first_segment + k];
    const Segment& ms = model.segments[m.first_segment + k];
    if (std::abs(ds.u_end - ms.u_end) > tol) {
      const bool last = k + 1 == d.segment_count;
      return st + "different shear paths: " +
             (last ? std::string("the stage ends") : "reversal " + std::to_string(k + 1) + " is") + " at " +
             fmt("%+.4g", ds.u_end) + " mm in the measurement, " + fmt("%+.4g", ms.u_end) + " mm in the model" +
             allowed;
    }
  }
  structural = false;
  return {};
}

}  // namespace

std::string normal_stress_mismatch(const StageInfo& d, double model_MPa, const CompareOptions& options) {
  const double sn_tol = options.normal_stress_tolerance * std::abs(d.normal_stress_MPa) + 0.01;
  if (!(std::abs(d.normal_stress_MPa - model_MPa) > sn_tol)) return {};
  return "stage " + std::to_string(d.stage) + ": different normal stress: the measurement " +
         fmt("%.4g", d.normal_stress_MPa) + " MPa, the model " + fmt("%.4g", model_MPa) +
         " MPa (medians; allowed difference " + fmt("%.2g", sn_tol) + " MPa)";
}

std::string normal_stress_mismatch(const Segmentation& data, const MeasurementFile& model,
                                   const std::vector<StageInfo>& model_stages, const CompareOptions& options) {
  for (std::size_t i = 0; i < model_stages.size(); ++i) {
    const StageInfo& m = model_stages[i];
    // The median lies between the extremes: where both pass, it does (no sort).
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t j = m.begin; j < m.end; ++j) {
      lo = std::min(lo, model.rows[j].normal_stress_MPa);
      hi = std::max(hi, model.rows[j].normal_stress_MPa);
    }
    const StageInfo& d = data.stages[i];
    if (normal_stress_mismatch(d, lo, options).empty() && normal_stress_mismatch(d, hi, options).empty()) continue;
    if (std::string why = normal_stress_mismatch(d, stage_normal_stress(model, m.begin, m.end), options); !why.empty())
      return why;
  }
  return {};
}

void check_compatible(const Segmentation& data, const Segmentation& model, const CompareOptions& options) {
  check_stage_lists(data, model);
  bool structural = false;
  for (std::size_t i = 0; i < data.stages.size(); ++i) {
    const std::string why = stage_mismatch(data, model, i, options, structural);
    if (!why.empty()) throw InputError(why);
  }
}

Alignment align(const MeasurementFile& data, const Segmentation& ds, const MeasurementFile& model,
                const Segmentation& ms, const CompareOptions& options) {
  Alignment out;
  for (auto& v : out.model) v.assign(data.rows.size(), kNaN);
  out.rows.assign(data.rows.size(), AlignedRow{});
  std::vector<double> runmax;
  std::vector<std::size_t> dturns, mturns;
  for (std::size_t si = 0; si < ds.stages.size(); ++si) {
    const StageInfo& dst = ds.stages[si];
    const StageInfo& mst = ms.stages[si];
    for (std::size_t k = 0; k < dst.segment_count; ++k) {
      const Segment& d = ds.segments[dst.first_segment + k];
      const Segment& m = ms.segments[mst.first_segment + k];
      if (d.motion != 0) {
        // Reversals below the segment threshold (an earthquake record's small back-and-forth)
        // still flip the shear stress. Where both records show the same finer reversals, align
        // piece by piece between them; where they do not (noise), on the whole segment. A
        // reversal near one threshold may be seen in one record and not the other, so the finest
        // of a few thresholds (doubling up to half the segment threshold) that agrees is used.
        int dfirst = 0, mfirst = 0;
        bool pieces = false;
        for (double f = options.fine_fraction; f > 0.0 && f <= 0.5 && !pieces; f *= 2.0) {
          find_reversals(data, d.curve_begin, d.end, f * dst.threshold, dturns, dfirst);
          if (dturns.empty()) break;  // none at this level: none at coarser ones either
          find_reversals(model, m.curve_begin, m.end, f * dst.threshold, mturns, mfirst);
          pieces = dturns.size() == mturns.size() && dfirst == mfirst;
        }
        if (pieces) {
          ++out.finely_aligned_segments;
        } else {
          dturns.clear();
          mturns.clear();
          dfirst = d.motion;
        }
        for (std::size_t p = 0; p <= dturns.size(); ++p) {
          // Progress along a piece is the displacement in its direction of motion.
          const double dir = p % 2 == 0 ? dfirst : -dfirst;
          interpolate(
              p == 0 ? d.begin : dturns[p - 1] + 1, p < dturns.size() ? dturns[p] + 1 : d.end, model,
              p == 0 ? m.curve_begin : mturns[p - 1], p < mturns.size() ? mturns[p] + 1 : m.end,
              [&](std::size_t j) { return dir * model.rows[j].shear_disp_mm; },
              [&](std::size_t i) { return dir * data.rows[i].shear_disp_mm; }, runmax, out);
        }
      } else {
        // No shear motion (a stage that only loads the joint normally): nothing to align on but
        // the fraction of the stage's duration (or of its rows, if time does not advance).
        const double dt0 = data.rows[d.curve_begin].time_s, dt1 = data.rows[d.end - 1].time_s;
        const double mt0 = model.rows[m.curve_begin].time_s, mt1 = model.rows[m.end - 1].time_s;
        const auto frac = [](double t, double t0, double t1, std::size_t i, std::size_t b, std::size_t e) {
          if (t1 > t0) return (t - t0) / (t1 - t0);
          return e - b > 1 ? static_cast<double>(i - b) / static_cast<double>(e - 1 - b) : 0.0;
        };
        interpolate(
            d.begin, d.end, model, m.curve_begin, m.end,
            [&](std::size_t j) { return frac(model.rows[j].time_s, mt0, mt1, j, m.curve_begin, m.end); },
            [&](std::size_t i) { return frac(data.rows[i].time_s, dt0, dt1, i, d.curve_begin, d.end); }, runmax, out);
      }
    }
  }
  return out;
}

void summarize(const MeasurementFile& data, const Segmentation& dseg, const Alignment& al,
               const CompareOptions& options, Comparison& out) {
  const auto& rows = data.rows;
  for (std::size_t v = 0; v < 2; ++v) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& r : rows) {
      lo = std::min(lo, compared_value(r, v));
      hi = std::max(hi, compared_value(r, v));
    }
    out.range[v] = rows.empty() ? 0.0 : hi - lo;
  }
  using Key = std::tuple<int, int, int>;
  Acc all;
  std::map<Key, Acc> by_stage, by_cycle, by_quadrant, by_segment;
  // Rows come in runs of one segment; remember the last groups instead of a lookup per row.
  Key last{-1, -1, -1};
  Acc *a_stage = nullptr, *a_cycle = nullptr, *a_quad = nullptr, *a_seg = nullptr;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const RowLabel& l = dseg.labels[i];
    const Key key{l.stage, l.cycle, l.quadrant};
    if (key != last) {
      a_stage = &by_stage[{l.stage, 0, 0}];
      a_cycle = &by_cycle[{l.stage, l.cycle, 0}];
      a_quad = &by_quadrant[{0, 0, l.quadrant}];
      a_seg = &by_segment[key];
      last = key;
    }
    for (std::size_t v = 0; v < 2; ++v) {
      const double meas = compared_value(rows[i], v);
      const double err = al.model[v][i] - meas;
      all.add(v, err, meas);
      a_stage->add(v, err, meas);
      a_cycle->add(v, err, meas);
      a_quad->add(v, err, meas);
      a_seg->add(v, err, meas);
    }
  }
  out.overall = finish(0, 0, 0, all, out.range);
  auto fill = [&](const std::map<Key, Acc>& m, std::vector<ErrorGroup>& dst) {
    dst.clear();
    for (const auto& [k, a] : m) dst.push_back(finish(std::get<0>(k), std::get<1>(k), std::get<2>(k), a, out.range));
  };
  fill(by_stage, out.stages);
  fill(by_cycle, out.cycles);
  fill(by_quadrant, out.quadrants);
  fill(by_segment, out.segments);
  // Quadrants in the report's order of a cycle: 1, 4, 3, 2 (0, no motion, last).
  std::stable_sort(out.quadrants.begin(), out.quadrants.end(), [](const ErrorGroup& a, const ErrorGroup& b) {
    auto rank = [](int q) { return q == 1 ? 0 : q == 4 ? 1 : q == 3 ? 2 : q == 2 ? 3 : 4; };
    return rank(a.quadrant) < rank(b.quadrant);
  });
  out.combined_nrmse = 0.5 * (out.overall.var[0].nrmse + out.overall.var[1].nrmse);

  struct Cand {
    double nrmse;
    std::size_t group, var;
  };
  std::vector<Cand> cands;
  for (std::size_t g = 0; g < out.segments.size(); ++g)
    for (std::size_t v = 0; v < 2; ++v) {
      const ErrorStats& s = out.segments[g].var[v];
      // Errors at rounding level are no finding (a model compared with its own record).
      if (out.segments[g].quadrant != 0 && s.n >= options.worst_min_rows && std::isfinite(s.nrmse) && s.nrmse > 1e-9)
        cands.push_back({s.nrmse, g, v});
    }
  std::stable_sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) { return a.nrmse > b.nrmse; });
  out.worst.clear();
  for (std::size_t i = 0; i < cands.size() && static_cast<int>(i) < options.worst_lines; ++i)
    out.worst.push_back(worst_line(out.segments[cands[i].group], cands[i].var, out.range[cands[i].var]));
}

Comparison align_records(const MeasurementFile& data, const Segmentation& dseg, const MeasurementFile& model,
                         const CompareOptions& options) {
  if (data.rows.empty()) throw InputError("the measurement has no data rows");
  if (model.rows.empty()) throw InputError("the model has no data rows");
  Comparison c;
  c.data_segments = dseg;
  SegmentationOptions thresholds = model_segmentation_options(dseg);
  c.model_segments = segment(model, thresholds);
  check_stage_lists(c.data_segments, c.model_segments);
  // A reversal close to the threshold may show in one record and not in the other (noise, a
  // compliant frame rounding it off). Where only the reversals differ, the stage's threshold is
  // raised step by step until both records agree; the finer reversals are still used for the
  // alignment where they match. Real differences (another cycle, a full-amplitude reversal) do
  // not vanish below half the range and are refused with the message of the default threshold.
  for (std::size_t i = 0; i < c.data_segments.stages.size(); ++i) {
    bool structural = false;
    const std::string why = stage_mismatch(c.data_segments, c.model_segments, i, options, structural);
    if (why.empty()) continue;
    if (!structural) throw InputError(why);
    const int stage = c.data_segments.stages[i].stage;
    const double base = thresholds.threshold_mm[stage];
    bool agreed = false;
    for (double f : {1.5, 2.0, 3.0, 4.0, 6.0, 8.0}) {
      thresholds.threshold_mm[stage] = f * base;
      c.data_segments = segment(data, thresholds);
      c.model_segments = segment(model, thresholds);
      if (stage_mismatch(c.data_segments, c.model_segments, i, options, structural).empty()) {
        agreed = true;
        c.notes.push_back("stage " + std::to_string(stage) + ": reversal threshold raised from " + fmt("%.3g", base) +
                          " mm to " + fmt("%.3g", f * base) + " mm so that both records show the same reversals (" +
                          why.substr(why.find("the measurement")) + " at the default)");
        break;
      }
    }
    if (!agreed) throw InputError(why);
  }
  c.alignment = align(data, c.data_segments, model, c.model_segments, options);
  return c;
}

Comparison compare(const MeasurementFile& data, const Segmentation& dseg, const MeasurementFile& model,
                   const CompareOptions& options) {
  Comparison c = align_records(data, dseg, model, options);
  summarize(data, c.data_segments, c.alignment, options, c);
  return c;
}

Comparison compare(const MeasurementFile& data, const MeasurementFile& model, const CompareOptions& options) {
  return compare(data, segment(data, options.segmentation), model, options);
}

nlohmann::json to_json(const Comparison& c) {
  nlohmann::json j;
  j["nrmse"] = {{"shear_stress", c.overall.var[0].nrmse},
                {"normal_disp", c.overall.var[1].nrmse},
                {"combined", c.combined_nrmse}};
  j["range"] = {{"shear_stress", c.range[0]}, {"normal_disp", c.range[1]}};
  j["units"] = {{"shear_stress", "MPa"}, {"normal_disp", "mm"}};
  j["overall"] = group_json(c.overall, false, false, false);
  j["stages"] = nlohmann::json::array();
  for (const auto& g : c.stages) {
    auto s = group_json(g, true, false, false);
    if (const StageInfo* st = c.data_segments.find_stage(g.stage)) {
      s["normal_stress_MPa"] = st->normal_stress_MPa;
      s["cycles"] = st->cycles;
      s["monotonic_segments"] = st->segment_count;
      s["shear_disp_min_mm"] = st->u_min;
      s["shear_disp_max_mm"] = st->u_max;
      s["reversal_threshold_mm"] = st->threshold;
    }
    j["stages"].push_back(s);
  }
  j["cycles"] = nlohmann::json::array();
  for (const auto& g : c.cycles) j["cycles"].push_back(group_json(g, true, true, false));
  j["quadrants"] = nlohmann::json::array();
  for (const auto& g : c.quadrants) j["quadrants"].push_back(group_json(g, false, false, true));
  // Flat, one entry per variable: the layout `diagnose` reports its segments in.
  j["segments"] = nlohmann::json::array();
  for (const auto& g : c.segments)
    for (std::size_t v = 0; v < 2; ++v) {
      const ErrorStats& s = g.var[v];
      j["segments"].push_back({{"variable", kCompareVariables[v].key},
                               {"stage", g.stage},
                               {"cycle", g.cycle},
                               {"quadrant", g.quadrant},
                               {"direction", g.quadrant == 1 || g.quadrant == 3   ? "forward"
                                             : g.quadrant == 2 || g.quadrant == 4 ? "reverse"
                                                                                  : "none"},
                               {"n", s.n},
                               {"rmse", s.rmse},
                               {"nrmse", s.nrmse},
                               {"bias", s.bias},
                               {"magnitude_bias", s.magnitude_bias},
                               {"mean_abs_measured", s.mean_abs_measured}});
    }
  j["worst"] = c.worst;
  j["notes"] = c.notes;
  j["alignment"] = {{"method", "shear displacement within stage and monotonic segment (first passage, linear)"},
                    {"measured_rows", c.data_segments.labels.size()},
                    {"rows_beyond_model_segment_ends", c.alignment.outside},
                    {"segments_aligned_on_finer_reversals", c.alignment.finely_aligned_segments}};
  return j;
}

std::string format_table(const Comparison& c) {
  std::string out;
  char buf[256];
  std::snprintf(buf, sizeof buf, "%-22s %7s  %-28s  %-28s\n", "", "", "shear stress [MPa]", "normal disp [mm]");
  out += buf;
  std::snprintf(buf, sizeof buf, "%-22s %7s  %8s %8s %10s  %8s %8s %10s\n", "group", "n", "RMSE", "NRMSE", "bias",
                "RMSE", "NRMSE", "bias");
  out += buf;
  auto row = [&](const std::string& name, const ErrorGroup& g) {
    std::snprintf(buf, sizeof buf, "%-22s %7zu  %8.4f %8.4f %+10.4f  %8.4f %8.4f %+10.4f\n", name.c_str(),
                  g.var[0].n, g.var[0].rmse, g.var[0].nrmse, g.var[0].bias, g.var[1].rmse, g.var[1].nrmse,
                  g.var[1].bias);
    out += buf;
  };
  row("overall", c.overall);
  for (const auto& g : c.stages) {
    const StageInfo* st = c.data_segments.find_stage(g.stage);
    row("stage " + std::to_string(g.stage) + (st ? " (" + fmt("%.3g", st->normal_stress_MPa) + " MPa)" : ""), g);
    int cycles = st ? st->cycles : 0;
    // Per-cycle rows only where a stage has several cycles, and then at most the first and last
    // few: a 40-cycle harmonic test would bury the table (all are in the JSON).
    if (cycles > 1) {
      for (const auto& cg : c.cycles) {
        if (cg.stage != g.stage) continue;
        if (cycles > 6 && cg.cycle > 3 && cg.cycle <= cycles - 2) {
          if (cg.cycle == 4) out += "    ...\n";
          continue;
        }
        row("  cycle " + std::to_string(cg.cycle), cg);
      }
    }
  }
  for (const auto& g : c.quadrants) row(g.quadrant ? "quadrant " + std::to_string(g.quadrant) : "no motion", g);
  std::snprintf(buf, sizeof buf, "combined NRMSE (mean of the two): %.4f\n", c.combined_nrmse);
  out += buf;
  return out;
}

}  // namespace rockdem
