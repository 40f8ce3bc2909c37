#include "framework/analysis/diagnosis.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "framework/core/error.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {
namespace {

// fn(i) for i in [0, n) on up to `threads` threads; exceptions stay inside fn.
template <class Fn>
void for_each_parallel(std::size_t n, int threads, Fn&& fn) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    while (true) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n) return;
      fn(i);
    }
  };
  std::vector<std::thread> extra;
  for (int t = 1; t < threads && static_cast<std::size_t>(t) < n; ++t) extra.emplace_back(worker);
  worker();
  for (auto& t : extra) t.join();
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  return v[i];
}

// The base law's free parameter names of a fit.
std::vector<std::string> free_names(const CalibrationResult& r, const std::string& owner) {
  std::vector<std::string> out;
  for (const auto& p : r.params)
    if (p.free && p.owner == owner) out.push_back(p.name);
  return out;
}

// Real parameters of an effect, qualified ("effect.param").
std::vector<std::string> effect_params(const std::string& effect) {
  std::vector<std::string> out;
  for (const auto& info : EffectRegistry::instance().get(effect, "effect", "diagnose").params)
    if (info.kind == "real") out.push_back(effect + "." + info.name);
  return out;
}

// Residuals (model - measured) / range per variable; shear stress signed by the direction of
// motion, so that a positive value means "too strong" whichever way the joint moves.
std::array<std::vector<double>, 2> signed_residuals(const MeasurementFile& data, const Segmentation& seg,
                                                    const Comparison& c) {
  std::array<std::vector<double>, 2> r;
  for (std::size_t v = 0; v < 2; ++v) {
    r[v].resize(data.rows.size(), 0.0);
    const double range = c.range[v] > 0.0 ? c.range[v] : 1.0;
    for (std::size_t i = 0; i < data.rows.size(); ++i) {
      const double meas = compared_value(data.rows[i], v);
      double d = (c.alignment.model[v][i] - meas) / range;
      if (v == 0) {
        const int m = seg.labels[i].motion;
        d *= m != 0 ? m : (meas < 0.0 ? -1.0 : 1.0);
      }
      r[v][i] = d;
    }
  }
  return r;
}

// BIC with k = every parameter the chain has taken from the data (the base law's free ones and
// each effect's free ones), not only those refitted in the last step, so that ladder steps compare.
void count_parameters(CalibrationResult& r, std::size_t law_free, const std::vector<std::string>& chain) {
  std::size_t k = law_free;
  for (const auto& e : chain) {
    const auto& entry = EffectRegistry::instance().get(e, "effect", "diagnose");
    const auto& fixed = entry.declared.fixed_by_default;
    for (const auto& info : entry.params)
      if (info.kind == "real") k += std::find(fixed.begin(), fixed.end(), info.name) == fixed.end() ? 1 : 0;
  }
  const double nd = static_cast<double>(r.n);
  r.k = static_cast<int>(k);
  r.bic = nd * std::log(std::max(r.rss, 1e-300) / nd) + static_cast<double>(k) * std::log(nd);
}

nlohmann::json nrmse_json(const std::array<double, 3>& a) {
  return {{"shear_stress", a[0]}, {"normal_disp", a[1]}, {"combined", a[2]}};
}

nlohmann::json params_json(const CalibrationResult& r) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& p : r.params) j[p.name] = p.value;
  return j;
}

}  // namespace

std::vector<std::string> non_physical_effects() {
  std::vector<std::string> out;
  for (const auto& [name, entry] : EffectRegistry::instance().entries())
    if (!entry.declared.physical) out.push_back(name);
  return out;
}

Covariates row_covariates(const MeasurementFile& data, const Segmentation& seg) {
  const std::size_t n = data.rows.size();
  Covariates c;
  c.names = {"offset", "toward_origin", "cumulative_slip", "cycle", "velocity", "normal_stress", "fresh_surface"};
  c.values.assign(c.names.size(), std::vector<double>(n, 0.0));
  double slip = 0.0, reach_pos = 0.0, reach_neg = 0.0;
  // Fresh surface: the offset goes beyond the farthest point reached before on that side (by
  // more than noise: 1 % of the record's largest offset), over the whole record, since the
  // specimen and its wear carry from stage to stage.
  double umax = 0.0;
  for (const auto& r : data.rows) umax = std::max(umax, std::abs(r.shear_disp_mm));
  const double tol = 0.01 * umax;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& r = data.rows[i];
    const RowLabel& l = seg.labels[i];
    if (i > 0 && data.rows[i - 1].stage == r.stage) slip += std::abs(r.shear_disp_mm - data.rows[i - 1].shear_disp_mm);
    // Central difference over +-2 rows in the stage: measurement noise on one row cancels.
    std::size_t a = i, b = i;
    for (int k = 0; k < 2; ++k) {
      if (a > 0 && data.rows[a - 1].stage == r.stage) --a;
      if (b + 1 < n && data.rows[b + 1].stage == r.stage) ++b;
    }
    const double dt = data.rows[b].time_s - data.rows[a].time_s;
    const double vel = dt > 0.0 ? std::abs(data.rows[b].shear_disp_mm - data.rows[a].shear_disp_mm) / dt : 0.0;
    const double u = r.shear_disp_mm;
    double fresh = 0.0;
    if (u > reach_pos + tol) fresh = 1.0, reach_pos = u;
    if (-u > reach_neg + tol) fresh = 1.0, reach_neg = -u;
    c.values[0][i] = std::abs(u);
    c.values[1][i] = l.direction < 0 ? 1.0 : 0.0;
    c.values[2][i] = slip;
    c.values[3][i] = l.cycle;
    c.values[4][i] = vel;
    c.values[5][i] = r.normal_stress_MPa;
    c.values[6][i] = fresh;
  }
  return c;
}

std::vector<CovariateScore> score_covariates(const Covariates& cov, const std::array<std::vector<double>, 2>& residual,
                                             int bins) {
  std::vector<CovariateScore> out;
  for (std::size_t v = 0; v < 2; ++v) {
    const auto& r = residual[v];
    const std::size_t n = r.size();
    for (std::size_t c = 0; c < cov.names.size(); ++c) {
      CovariateScore s{kCompareVariables[v].key, cov.names[c], 0.0};
      const auto& x = cov.values[c];
      // Bin edges: the distinct values when there are few, else quantiles.
      std::vector<double> sorted(x.begin(), x.end());
      std::sort(sorted.begin(), sorted.end());
      sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
      std::vector<double> edges;  // upper edges, ascending
      if (sorted.size() <= static_cast<std::size_t>(bins)) {
        edges = sorted;
      } else {
        for (int b = 1; b <= bins; ++b) edges.push_back(percentile(x, static_cast<double>(b) / bins));
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
      }
      if (edges.size() < 2 || n < edges.size() + 2) {
        out.push_back(s);
        continue;
      }
      std::vector<double> sum(edges.size(), 0.0), cnt(edges.size(), 0.0);
      double mean = 0.0;
      for (std::size_t i = 0; i < n; ++i) mean += r[i];
      mean /= static_cast<double>(n);
      std::vector<std::size_t> bin(n);
      for (std::size_t i = 0; i < n; ++i) {
        const auto it = std::lower_bound(edges.begin(), edges.end(), x[i]);
        bin[i] = std::min<std::size_t>(static_cast<std::size_t>(it - edges.begin()), edges.size() - 1);
        sum[bin[i]] += r[i];
        cnt[bin[i]] += 1.0;
      }
      double sst = 0.0, ssw = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double m = sum[bin[i]] / cnt[bin[i]];
        sst += (r[i] - mean) * (r[i] - mean);
        ssw += (r[i] - m) * (r[i] - m);
      }
      std::size_t used = 0;
      for (double k : cnt) used += k > 0.0 ? 1 : 0;
      const double nd = static_cast<double>(n);
      if (sst > 0.0 && nd > static_cast<double>(used)) {
        s.score = std::max(0.0, 1.0 - (ssw / (nd - static_cast<double>(used))) / (sst / (nd - 1.0)));
      }
      out.push_back(s);
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.score > b.score; });
  return out;
}

namespace {

// The record's features, with its row covariates already computed (diagnose has them).
RecordFeatures features_of(const MeasurementFile& data, const Segmentation& seg, const Covariates& c) {
  RecordFeatures f;
  for (const auto& l : seg.labels) {
    f.reverse_rows += l.direction < 0 ? 1 : 0;
    f.negative_side_rows += (l.quadrant == 3 || l.quadrant == 2) ? 1 : 0;
    f.positive_side_rows += (l.quadrant == 1 || l.quadrant == 4) ? 1 : 0;
  }
  for (const auto& s : seg.stages) f.cycles += s.cycles;
  std::vector<double> moving;
  for (double v : c.values[4])
    if (v > 0.0) moving.push_back(v);
  f.rate_low = percentile(moving, 0.1);
  f.rate_high = percentile(moving, 0.9);
  for (const auto& s : seg.stages) {
    RecordFeatures::Stage st;
    st.normal_stress_MPa = s.normal_stress_MPa;
    st.min_normal_stress_MPa = kInf;
    st.max_normal_stress_MPa = -kInf;
    for (std::size_t i = s.begin; i < s.end; ++i) {
      st.min_normal_stress_MPa = std::min(st.min_normal_stress_MPa, data.rows[i].normal_stress_MPa);
      st.max_normal_stress_MPa = std::max(st.max_normal_stress_MPa, data.rows[i].normal_stress_MPa);
    }
    f.stages.push_back(st);
  }
  return f;
}

}  // namespace

RecordFeatures record_features(const MeasurementFile& data, const Segmentation& seg) {
  return features_of(data, seg, row_covariates(data, seg));
}

std::string unjudgeable_reason(const std::string& effect, const RecordFeatures& features) {
  const auto* entry = EffectRegistry::instance().find(effect);
  if (!entry || !entry->declared.unjudgeable) return {};
  return entry->declared.unjudgeable(features);
}

std::string unjudgeable_reason(const std::string& effect, const MeasurementFile& data, const Segmentation& seg) {
  return unjudgeable_reason(effect, record_features(data, seg));
}

namespace {

// One diagnosis, step by step: the base law, the residual's covariates, every effect tried alone,
// the ranking, then the ladder of added effects. The steps share the record, the options and the
// base law's free parameters, so they are members of one object rather than arguments.
class DiagnosisRun {
 public:
  DiagnosisRun(const MeasurementFile& data, const Segmentation& seg, const DiagnosisOptions& options)
      : data_(data), seg_(seg), options_(options) {}

  Diagnosis run() {
    const auto t0 = std::chrono::steady_clock::now();
    d_.law = options_.base.law;
    check_record_length();
    fit_baseline();
    // Covariates of the baseline's residual.
    const Covariates covariates = row_covariates(data_, seg_);
    d_.covariates = score_covariates(covariates, signed_residuals(data_, seg_, d_.baseline.comparison), options_.bins);
    try_each_effect(features_of(data_, seg_, covariates));
    mark_insensitive_effects();
    rank_effects();
    climb_ladder();
    d_.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return std::move(d_);
  }

 private:
  void check_record_length() {
    std::size_t moving_segments = 0;
    for (const auto& s : seg_.segments) moving_segments += s.motion != 0 ? 1 : 0;
    short_record_ = data_.rows.size() < 50 || moving_segments < 2;
    if (short_record_) {
      d_.warnings.push_back("the record is short (" + std::to_string(data_.rows.size()) + " rows, " +
                            std::to_string(moving_segments) + " shear stroke(s)): effects cannot be told apart; no confident answer");
      d_.confident = false;
    }
  }

  void fit_baseline() {
    CalibrationOptions base = options_.base;
    base.effects.clear();
    base.threads = options_.threads;
    base.starts = 2;
    d_.baseline = calibrate(data_, seg_, base);
    for (const auto& w : d_.baseline.warnings) d_.warnings.push_back("baseline: " + w);
    law_free_ = free_names(d_.baseline, d_.law);
  }

  // Calibration options for the base law with `chain` of effects, started from `from`'s values;
  // only the base law's free parameters and the last effect's are fitted.
  CalibrationOptions options_for(const std::vector<std::string>& chain, const CalibrationResult& from, int threads) const {
    CalibrationOptions o = options_.base;
    o.effects = chain;
    o.threads = threads;
    // Effect fits stay at the fitting step (no fine-step polish): their NRMSE and BIC are still
    // evaluated at the fine step, and a few per cent in a parameter does not change a ranking.
    o.polish = false;
    for (const auto& p : from.params)
      if (std::isfinite(p.value)) o.start[p.name] = p.value;
    for (const auto& [k, v] : options_.base.fix) o.start.erase(k);
    o.only_free = law_free_;
    for (const auto& n : effect_params(chain.back())) o.only_free.push_back(n);
    return o;
  }

  // Every effect, added alone and refitted with the base law's free parameters.
  void try_each_effect(const RecordFeatures& features) {
    std::vector<std::string> effects = options_.effects;
    if (effects.empty()) {
      for (const auto& [name, entry] : EffectRegistry::instance().entries())
        if (entry.declared.physical) effects.push_back(name);
    }
    // Two effects at a time on two cores, each fit single-threaded (nested threads would oversubscribe).
    const int outer = std::max(1, std::min<int>(options_.threads, static_cast<int>(effects.size())));
    const int inner = std::max(1, options_.threads / outer);
    d_.ranking.resize(effects.size());
    for_each_parallel(effects.size(), outer, [&](std::size_t i) {
      EffectTrial& t = d_.ranking[i];
      t.effect = effects[i];
      t.reason = unjudgeable_reason(t.effect, features);
      t.judged = t.reason.empty() && !short_record_;
      if (short_record_ && t.reason.empty()) t.reason = "the record is too short";
      if (!t.judged && !options_.fit_unjudged) return;
      fit_trial(t, inner);
    });
  }

  void fit_trial(EffectTrial& t, int threads) const {
    try {
      // Two starts: warm (the baseline's values, which may have bent to make up for the missing
      // effect) and cold (the data estimates); the lower RSS wins (same parameters, so the same
      // ranking as by BIC). Either start may fail outright (the model joint lifting off at the baseline's values, as
      // Continuously-Yielding's did on test 14): the other is still tried, and a fit that came
      // only from the second start says why the first gave none.
      const CalibrationOptions warm = options_for({t.effect}, d_.baseline, threads);
      CalibrationOptions cold = warm;
      cold.start.clear();
      std::optional<CalibrationResult> best;
      std::string warm_error, cold_error;
      try {
        best = calibrate(data_, seg_, warm);
      } catch (const std::exception& e) {
        warm_error = e.what();
      }
      try {
        CalibrationResult other = calibrate(data_, seg_, cold);
        if (!best || other.rss < best->rss) best = std::move(other);
      } catch (const std::exception& e) {
        cold_error = e.what();
      }
      if (!best)
        throw InputError("from the baseline's values: " + warm_error + "; from the record's estimates: " + cold_error);
      t.fit = std::move(*best);
      if (!warm_error.empty()) t.fit.warnings.push_back("the start from the baseline's values failed (" + warm_error + "); fitted from the record's estimates");
      count_parameters(t.fit, law_free_.size(), {t.effect});
      t.delta_bic = t.fit.bic - d_.baseline.bic;
      t.fitted = t.fit.status != "failed" || t.fit.rss < d_.baseline.rss;
      if (!t.fitted) {
        t.failed = true;
        t.judged = false;
        t.reason = "fit failed: " + (t.fit.warnings.empty() ? t.fit.status : t.fit.warnings.front());
      }
    } catch (const std::exception& e) {
      t.failed = true;
      t.judged = false;
      t.reason = std::string("fit failed: ") + e.what();
    }
  }

  // An effect none of whose parameters changes the model on this record (and that did not lower
  // the error) cannot be judged either.
  void mark_insensitive_effects() {
    for (auto& t : d_.ranking) {
      if (!t.fitted || !t.judged) continue;
      bool any_free = false, any_sensitive = false;
      for (const auto& p : t.fit.params) {
        if (p.owner != t.effect || !p.free) continue;
        any_free = true;
        any_sensitive = any_sensitive || std::isfinite(p.se);
      }
      if (any_free && !any_sensitive && !(t.fit.rss < 0.999 * d_.baseline.rss)) {
        t.judged = false;
        t.reason = "its parameters do not change the model on this record";
      }
    }
  }

  void rank_effects() {
    std::stable_sort(d_.ranking.begin(), d_.ranking.end(), [](const EffectTrial& a, const EffectTrial& b) {
      const bool ja = a.judged && !a.failed, jb = b.judged && !b.failed;
      if (ja != jb) return ja;
      if (a.fitted != b.fitted) return a.fitted;
      return a.fitted && a.fit.bic < b.fit.bic;
    });
    std::vector<std::string> unjudged;
    for (const auto& t : d_.ranking) {
      if (t.failed) {
        d_.warnings.push_back("effect " + t.effect + ": " + t.reason);
      } else if (!t.judged) {
        unjudged.push_back(t.effect);
        d_.warnings.push_back("effect " + t.effect + " cannot be judged from this record: " + t.reason);
      } else {
        for (const auto& w : t.fit.warnings) d_.warnings.push_back("effect " + t.effect + ": " + w);
      }
    }
    if (!unjudged.empty()) d_.confident = false;
  }

  // The ladder: the best single effect, then the best addition to the current chain, while that
  // lowers both the BIC and the combined NRMSE the report shows. Only effects that improved the
  // BIC alone are candidates. Every candidate tried is recorded with why it was or was not added.
  void climb_ladder() {
    d_.ladder.push_back({{}, d_.baseline});
    std::vector<const EffectTrial*> candidates;
    for (const auto& t : d_.ranking)
      if (t.judged && !t.failed && t.delta_bic < 0.0) candidates.push_back(&t);
    std::set<std::string> used;
    for (const auto* c : candidates) {  // the first rung: the best by BIC that also lowers the error
      if (decide(1, c->effect, c->fit, d_.baseline)) {
        d_.ladder.push_back({{c->effect}, c->fit});
        used.insert(c->effect);
        break;
      }
    }
    while (!used.empty() && used.size() < candidates.size()) {
      std::vector<const EffectTrial*> next;
      for (const auto* c : candidates)
        if (!used.count(c->effect)) next.push_back(c);
      if (!add_rung(next, used)) break;
    }
  }

  // Records the decision on `effect` for rung `step` (judge_rung) and returns whether it is added.
  bool decide(std::size_t step, const std::string& effect, const CalibrationResult& fit, const CalibrationResult& before) {
    d_.decisions.push_back(judge_rung(step, effect, fit, before));
    return d_.decisions.back().added;
  }

  // Fits the current chain plus each of `next`; adds the best by BIC among those that lower both
  // the BIC and the combined NRMSE.
  bool add_rung(const std::vector<const EffectTrial*>& next, std::set<std::string>& used) {
    const LadderStep& cur = d_.ladder.back();
    std::vector<CalibrationResult> fits(next.size());
    std::vector<bool> ok(next.size(), false);
    const int o2 = std::max(1, std::min<int>(options_.threads, static_cast<int>(next.size())));
    for_each_parallel(next.size(), o2, [&](std::size_t i) {
      std::vector<std::string> chain = cur.effects;
      chain.push_back(next[i]->effect);
      CalibrationOptions o = options_for(chain, cur.fit, std::max(1, options_.threads / o2));
      for (const auto& p : next[i]->fit.params)
        if (p.owner == next[i]->effect) o.start[p.name] = p.value;
      try {
        fits[i] = calibrate(data_, seg_, o);
        count_parameters(fits[i], law_free_.size(), chain);
        ok[i] = true;
      } catch (const std::exception&) {
        ok[i] = false;
      }
    });
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < next.size(); ++i)
      if (ok[i]) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return fits[a].bic < fits[b].bic; });
    const std::size_t step = d_.ladder.size();
    for (const std::size_t i : order) {
      if (!decide(step, next[i]->effect, fits[i], cur.fit)) {
        if (!(fits[i].bic < cur.fit.bic)) return false;  // the rest lower the BIC even less
        continue;
      }
      LadderStep rung{cur.effects, std::move(fits[i])};
      rung.effects.push_back(next[i]->effect);
      used.insert(next[i]->effect);
      d_.ladder.push_back(std::move(rung));
      return true;
    }
    return false;
  }

  const MeasurementFile& data_;
  const Segmentation& seg_;
  const DiagnosisOptions& options_;
  Diagnosis d_;
  bool short_record_ = false;
  std::vector<std::string> law_free_;
};

}  // namespace

LadderDecision judge_rung(std::size_t step, const std::string& effect, const CalibrationResult& fit,
                          const CalibrationResult& before) {
  LadderDecision dec{step, effect, false, fit.bic - before.bic, before.nrmse[2], fit.nrmse[2], ""};
  char buf[200];
  if (!(fit.bic < before.bic)) {
    std::snprintf(buf, sizeof buf, "does not lower the BIC (%+.1f)", dec.delta_bic);
  } else if (!(fit.nrmse[2] < before.nrmse[2])) {
    std::snprintf(buf, sizeof buf, "lowers the BIC (%+.1f) but raises the combined NRMSE from %.4f to %.4f: not added",
                  dec.delta_bic, dec.nrmse_before, dec.nrmse_after);
  } else {
    dec.added = true;
    std::snprintf(buf, sizeof buf, "lowers the BIC (%+.1f) and the combined NRMSE from %.4f to %.4f", dec.delta_bic,
                  dec.nrmse_before, dec.nrmse_after);
  }
  dec.reason = buf;
  return dec;
}

Diagnosis diagnose(const MeasurementFile& data, const Segmentation& seg, const DiagnosisOptions& options) {
  return DiagnosisRun(data, seg, options).run();
}

nlohmann::json to_json(const Diagnosis& d, const std::string& data_file) {
  nlohmann::json j;
  j["data"] = data_file;
  j["base_law"] = d.law;
  j["baseline"] = {{"params", params_json(d.baseline)}, {"nrmse", nrmse_json(d.baseline.nrmse)}, {"bic", d.baseline.bic},
                   {"status", d.baseline.status}, {"calibration", to_json(d.baseline)}};
  j["segments"] = nlohmann::json::array();
  for (const auto& g : d.baseline.comparison.segments) {
    for (std::size_t v = 0; v < 2; ++v) {
      j["segments"].push_back({{"variable", kCompareVariables[v].key}, {"stage", g.stage}, {"cycle", g.cycle},
                               {"quadrant", g.quadrant}, {"n", g.var[v].n}, {"nrmse", g.var[v].nrmse},
                               {"bias", g.var[v].bias}, {"magnitude_bias", g.var[v].magnitude_bias}});
    }
  }
  j["worst"] = d.baseline.comparison.worst;
  j["covariates"] = nlohmann::json::array();
  for (const auto& c : d.covariates) j["covariates"].push_back({{"variable", c.variable}, {"name", c.name}, {"score", c.score}});
  j["ranking"] = nlohmann::json::array();
  for (const auto& t : d.ranking) {
    nlohmann::json e{{"effect", t.effect}, {"judged", t.judged}, {"failed", t.failed}};
    if (!t.reason.empty()) e["reason"] = t.reason;
    e["fitted"] = t.fitted;
    if (!t.fitted) {
      e["nrmse"] = nullptr;
      e["bic"] = nullptr;
      e["delta_bic"] = nullptr;
    } else {
      e["nrmse"] = nrmse_json(t.fit.nrmse);
      e["bic"] = t.fit.bic;
      e["delta_bic"] = t.delta_bic;
      e["k"] = t.fit.k;
      e["status"] = t.fit.status;
      e["params"] = params_json(t.fit);
      e["wall_ms"] = t.fit.wall_ms;
      e["evaluations"] = t.fit.evaluations;
    }
    j["ranking"].push_back(e);
  }
  j["ladder"] = nlohmann::json::array();
  for (const auto& s : d.ladder) {
    j["ladder"].push_back({{"effects", s.effects}, {"nrmse", nrmse_json(s.fit.nrmse)}, {"bic", s.fit.bic}, {"k", s.fit.k}});
  }
  j["ladder_decisions"] = nlohmann::json::array();
  for (const auto& c : d.decisions)
    j["ladder_decisions"].push_back({{"step", c.step}, {"effect", c.effect}, {"added", c.added}, {"delta_bic", c.delta_bic},
                                     {"nrmse_before", c.nrmse_before}, {"nrmse_after", c.nrmse_after}, {"reason", c.reason}});
  j["final"] = {{"effects", d.ladder.back().effects}, {"params", params_json(d.ladder.back().fit)},
                {"settings", d.ladder.back().fit.settings}, {"nrmse", nrmse_json(d.ladder.back().fit.nrmse)}};
  j["warnings"] = d.warnings;
  j["confident"] = d.confident;
  j["wall_ms"] = d.wall_ms;
  return j;
}

std::string format_report(const Diagnosis& d) {
  std::ostringstream os;
  char buf[512];
  const auto& b = d.baseline;
  std::snprintf(buf, sizeof buf, "1. baseline %s: NRMSE shear stress %.4f, normal displacement %.4f, combined %.4f (%s)\n",
                d.law.c_str(), b.nrmse[0], b.nrmse[1], b.nrmse[2], b.status.c_str());
  os << buf;
  os << "2. where it fails:\n";
  for (const auto& w : b.comparison.worst) os << "   " << w << "\n";
  os << "3. what the residual follows (adjusted eta^2, best first):\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(6, d.covariates.size()); ++i) {
    std::snprintf(buf, sizeof buf, "   %-20s %-16s %.3f\n", kCompareVariables[d.covariates[i].variable == "shear_stress" ? 0 : 1].name,
                  d.covariates[i].name.c_str(), d.covariates[i].score);
    os << buf;
  }
  os << "4. effects, best first:        combined NRMSE   delta BIC   k\n";
  for (const auto& t : d.ranking) {
    if (t.failed) {
      std::snprintf(buf, sizeof buf, "   %-28s failed\n", t.effect.c_str());
    } else if (!t.fitted) {
      std::snprintf(buf, sizeof buf, "   %-28s not fitted: cannot be judged from this record\n", t.effect.c_str());
    } else {
      std::snprintf(buf, sizeof buf, "   %-28s %.4f         %+10.1f  %d%s\n", t.effect.c_str(), t.fit.nrmse[2], t.delta_bic, t.fit.k,
                    t.judged ? "" : "   (cannot be judged here)");
    }
    os << buf;
  }
  os << "   ladder:\n";
  for (const auto& s : d.ladder) {
    std::string name;
    for (const auto& e : s.effects) name += (name.empty() ? "" : " + ") + e;
    std::snprintf(buf, sizeof buf, "   %-44s combined NRMSE %.4f, BIC %.1f\n", (d.law + (name.empty() ? "" : " + " + name)).c_str(),
                  s.fit.nrmse[2], s.fit.bic);
    os << buf;
  }
  // Effects the BIC favoured that the ladder left out because the error would have risen.
  for (const auto& c : d.decisions)
    if (!c.added && c.delta_bic < 0.0) os << "   not added at step " << c.step << ": " << c.effect << " " << c.reason << "\n";
  for (const auto& w : d.warnings) os << "warning: " << w << "\n";
  if (!d.confident) os << "note: not a confident answer: see the warnings above\n";
  return os.str();
}

void write_report_data(const Diagnosis& d, const MeasurementFile& data, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::string path = (std::filesystem::path(dir) / "aligned.csv").string();
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  const Segmentation& seg = d.baseline.comparison.data_segments;
  out << "stage,cycle,quadrant,shear_disp_mm,shear_stress_MPa,normal_disp_mm";
  for (std::size_t k = 0; k < d.ladder.size(); ++k) out << ",shear_stress_" << k << ",normal_disp_" << k;
  out << "\n";
  char buf[64];
  for (std::size_t i = 0; i < data.rows.size(); ++i) {
    const auto& r = data.rows[i];
    out << r.stage << ',' << seg.labels[i].cycle << ',' << seg.labels[i].quadrant;
    for (double v : {r.shear_disp_mm, r.shear_stress_MPa, r.normal_disp_mm}) {
      std::snprintf(buf, sizeof buf, ",%.8g", v);
      out << buf;
    }
    for (const auto& s : d.ladder) {
      for (std::size_t v = 0; v < 2; ++v) {
        std::snprintf(buf, sizeof buf, ",%.8g", s.fit.comparison.alignment.model[v][i]);
        out << buf;
      }
    }
    out << "\n";
  }
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace rockdem
