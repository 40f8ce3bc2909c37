// The broad blind test of the validation loop (issue 15): per seed it draws a base law (all three
// standard laws), a laboratory protocol (one-sided multi-stage, two-sided cycles, harmonic,
// velocity steps, slide-hold-slide) and zero, one or two hidden effects among those the protocol
// can reveal, makes the record with the element driver plus seeded noise, and runs `diagnose`
// told the base law, its dilation mode and what a user measures apart (every physical effect of
// the catalogue is tried).
// A hit: every hidden effect is judged, and with no hidden effect nothing is added; with one, it
// is ranked first and is the only rung; with two, one of them is ranked first, the first rung is
// one of them and the other is the only rung after it. Each draw also
// prints the combined NRMSE before and after the first rung and the ceiling (the noisy record
// against the noise-free one), from which docs/validation.md's table is made:
//   ROCKDEM_BLIND_SEEDS=61-200 tests/rockdem_tests --gtest_filter='BlindBroad.*'
// (ROCKDEM_BLIND_SEED=N runs one draw; ROCKDEM_BLIND_REPORT=1 prints diagnose's report of each
// draw; ROCKDEM_BLIND_KEEP=FOLDER writes each draw's record there as blind_SEED.csv, and the record
// without noise as blind_SEED_clean.csv). The suite
// runs seeds 1-60 and holds them to today's counts (kGate*).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "tests/unit/noisy_record.hpp"
#include "framework/analysis/compare.hpp"
#include "framework/analysis/diagnosis.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/plugin_api/joint_law.hpp"

using namespace rockdem;

namespace {

RawValue q(const char* text) { return RawValue{std::string(text), "blind"}; }
RawValue num(double v) { return RawValue{v, "blind"}; }

struct Law {
  const char* name;
  RawValues values;
};

// Parameters of tuff-like joints; dilation modes that leave something for the effects to change
// (Mohr-Coulomb's dilation monotonic at 8 deg, as in the first blind test).
const std::vector<Law>& laws() {
  static const std::vector<Law> l{
      {"mohr_coulomb",
       {{"kn", q("40 GPa/m")}, {"ks", q("12 GPa/m")}, {"friction", q("36 deg")}, {"dilation_angle", q("8 deg")},
        {"dilation", q("monotonic")}}},
      {"barton_bandis", testutil::barton_bandis_joint()},
      {"continuously_yielding", testutil::continuously_yielding_joint()},
  };
  return l;
}

// What each effect is set to when hidden: values away from its defaults, large enough to matter
// against the noise (the fit starts from the defaults).
EffectSpec hidden(const std::string& effect) {
  if (effect == "reverse_shear_degradation") return {effect, {{"weight", num(2.5)}}, "blind"};
  if (effect == "dilation_recovery") return {effect, {{"residual_fraction", num(0.4)}, {"hysteresis", num(0.8)}}, "blind"};
  if (effect == "directional_wear") return {effect, {}, "blind"};
  if (effect == "two_order_roughness")
    return {effect, {{"second_order_angle", q("15 deg")}, {"second_order_slip", q("1 mm")}, {"first_order_loss", q("4 deg")},
                     {"first_order_work", q("1e5 J/m^2")}}, "blind"};
  if (effect == "rate_and_state") return {effect, {{"a", num(0.01)}, {"b", num(0.03)}, {"critical_slip", q("100 um")}}, "blind"};
  ADD_FAILURE() << "no hidden values for " << effect;
  return {effect, {}, "blind"};
}

struct Protocol {
  const char* name;
  // Effects this protocol can reveal: every physical effect but hyperbolic_normal_closure (all
  // five protocols hold the normal stress constant within a stage, so the closure curve cannot
  // show; diagnose says so itself), and only what the shear path exercises: reverse-shear
  // effects need a return stroke, directional wear a passage past the origin, two-order roughness
  // two cycles (drawn with the two-sided and harmonic paths only; diagnose also judges it on the
  // one-sided stages, not drawn there: a gap), rate-and-state a change of rate or a hold, and
  // directional wear a base law that wears (not Mohr-Coulomb: see the draw).
  std::vector<std::string> revealable;
};

const std::vector<Protocol>& protocols() {
  static const std::vector<Protocol> p{
      {"one_sided_stages", {"reverse_shear_degradation", "dilation_recovery"}},
      {"two_sided_cycles", {"reverse_shear_degradation", "dilation_recovery", "directional_wear", "two_order_roughness"}},
      {"harmonic", {"reverse_shear_degradation", "dilation_recovery", "directional_wear", "two_order_roughness", "rate_and_state"}},
      {"velocity_steps", {"rate_and_state"}},
      {"slide_hold_slide", {"rate_and_state"}},
  };
  return p;
}

// Today's measurement over seeds 1-60 (the gate below): hits, clean records left alone, one- and two-effect hits, first rungs
// that cut the error 3x or to the noise, last rungs at the noise (within twice the ceiling). The
// draws come from libstdc++'s distributions (their sequences are the implementation's): another
// standard library draws other records, and these counts would need measuring again.
// Cut and floor went from 37 and 41 to 36 and 40 on 2026-11-28 (third session), when
// rate_and_state's strength came to be evaluated at the final normal stress: the records with
// that effect changed with it. Seed 12's (Mohr-Coulomb, harmonic, rate_and_state +
// reverse_shear_degradation) now gets an empty ladder: reverse_shear_degradation alone stops at
// the iteration limit above the baseline's error, its model missing 32 of 5,076 increments.
// Seed 27 stays a hit; the hits stay 59.
// On 2026-11-28 (fourth session) the element driver came to hand the law the stage's normal stress
// (the strength and the effects evaluated there, no jump with the driver's normal displacement)
// and the fit's bounded steps stopped asking for a Jacobian at each line-search point: every draw
// is a hit (60; seed 12 too, two of two), the first rung cuts 37 and the last rung is at the
// noise in all 41; the test's time fell from about 250 s to 73 s.
constexpr std::size_t kGateHits = 60, kGateClean = 19, kGateOne = 29, kGateTwo = 12, kGateCut = 37, kGateFloor = 41;

constexpr double kStep = 2.5e-5;  // element increment [m]
constexpr double kV = 4.2e-5;     // the report's pseudostatic rate [m/s]

// The noise-free record of `model` under `protocol`.
MeasurementFile run_protocol(const JointModel& model, const std::string& protocol) {
  ElementOptions eo;
  eo.max_step = kStep;
  eo.output_every = 4;
  eo.length = 0.2;
  std::vector<ElementStage> stages;
  auto stage = [&](double sigma, ShearPath path) {
    stages.push_back(ElementStage{});
    stages.back().normal_stress = sigma;
    stages.back().path = std::move(path);
  };
  if (protocol == "one_sided_stages") {  // three stages, 0 -> +8 mm -> 0 each
    for (double s : {1e6, 2e6, 4e6}) stage(s, ShearPath::cycles(0.008, 1, kV, true));
  } else if (protocol == "two_sided_cycles") {  // two full cycles of +-8 mm at 3 MPa
    stage(3e6, ShearPath::cycles(0.008, 2, kV, false));
  } else if (protocol == "harmonic") {  // 4 cycles of +-5 mm at 0.05 Hz (peak rate 1.6 mm/s) at 3 MPa
    // Every increment kept: the sine's increments are equal in time, so they shrink toward its
    // turning points, and a fit walking every 4th row takes one increment where the record took
    // four there. The laws' answers depend on the step (Continuously-Yielding's normal displacement
    // by 0.46 % of its range between 25 and 10 um), so the fitted model would differ from the
    // generating one by about the noise, a difference the ladder can take for an effect.
    eo.output_every = 1;
    stage(3e6, ShearPath::sinusoid(0.005, 0.05, 4));
  } else if (protocol == "velocity_steps") {  // 1.5 mm at each rate, one direction, 2 MPa
    std::vector<double> t{0.0}, u{0.0};
    for (double v : {kV, 10 * kV, kV / 10, 10 * kV, kV}) {
      t.push_back(t.back() + 1.5e-3 / v);
      u.push_back(u.back() + 1.5e-3);
    }
    stage(2e6, ShearPath::table(t, u));
  } else if (protocol == "slide_hold_slide") {  // 2 mm slides, holds of 10, 100 and 1000 s, 2 MPa
    eo.output_every = 1;  // every increment kept, as in the slide-hold-slide records of test_diagnosis.cpp
    stage(2e6, testutil::slide_hold_slide_path(kV, 2e-3, {10.0, 100.0, 1000.0}));
  } else {
    ADD_FAILURE() << "unknown protocol " << protocol;
  }
  ElementDriver d(model, eo);
  MeasurementFile f = d.run(stages);
  f.metadata.push_back({"joint_length_m", "0.2"});
  return f;
}

std::vector<unsigned> seeds_to_run() {
  std::vector<unsigned> s;
  if (const char* one = std::getenv("ROCKDEM_BLIND_SEED")) return {static_cast<unsigned>(std::stoul(one))};
  if (const char* range = std::getenv("ROCKDEM_BLIND_SEEDS")) {  // "a-b"
    const std::string r(range);
    const auto dash = r.find('-');
    const unsigned a = static_cast<unsigned>(std::stoul(r.substr(0, dash)));
    const unsigned b = dash == std::string::npos ? a : static_cast<unsigned>(std::stoul(r.substr(dash + 1)));
    for (unsigned k = a; k <= b; ++k) s.push_back(k);
    return s;
  }
  for (unsigned k = 1; k <= 60; ++k) s.push_back(k);
  return s;
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& e : v) out += (out.empty() ? "" : "+") + e;
  return out.empty() ? "(none)" : out;
}

bool contains(const std::vector<std::string>& v, const std::string& e) {
  for (const auto& x : v)
    if (x == e) return true;
  return false;
}

struct Outcome {
  std::size_t hidden = 0;     // effects hidden in the record
  bool hit = false;           // see the file's head
  bool first_ranked = false;  // a hidden effect ranked first
  bool cut = false;           // the first rung's cut (see below)
  bool floor = false;         // the last rung within twice the ceiling
};

}  // namespace

TEST(BlindBroad, DrawnLawProtocolAndEffectsAreFound) {
  std::vector<Outcome> outcomes;
  for (const unsigned seed : seeds_to_run()) {
    std::mt19937 rng(seed);
    auto pick = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
    const Law& law = laws()[pick(laws().size())];
    const Protocol& protocol = protocols()[pick(protocols().size())];
    std::vector<std::string> pool = protocol.revealable;
    // Directional wear redistributes the base law's wear of its roughness; Mohr-Coulomb has none
    // (constant friction and dilation angles), so hidden with it the effect changes nothing.
    if (std::string(law.name) == "mohr_coulomb") std::erase(pool, std::string("directional_wear"));
    const std::size_t count = std::min(pick(3), pool.size());
    std::vector<std::string> effects;
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = pick(pool.size());
      effects.push_back(pool[i]);
      pool.erase(pool.begin() + static_cast<std::ptrdiff_t>(i));
    }
    std::vector<EffectSpec> specs;
    for (const auto& e : effects) specs.push_back(hidden(e));
    const std::string what = "seed " + std::to_string(seed) + " (ROCKDEM_BLIND_SEED=" + std::to_string(seed) + " repeats it): " +
                             law.name + ", " + protocol.name + ", hidden " + joined(effects);
    std::printf("blind broad: %s\n", what.c_str());
    std::fflush(stdout);

    auto model = make_joint_model(law.name, law.values, specs, "blind");
    const MeasurementFile clean = run_protocol(*model, protocol.name);
    MeasurementFile f = clean;
    std::normal_distribution<double> g(0.0, 1.0);
    for (auto& r : f.rows) {
      r.shear_stress_MPa += 0.005 * g(rng);
      r.normal_disp_mm += 0.002 * g(rng);
    }
    const double ceiling = compare(f, clean).combined_nrmse;
    if (const char* keep = std::getenv("ROCKDEM_BLIND_KEEP")) {  // the record, for `rockdem diagnose` by hand
      write_measurement_csv(std::string(keep) + "/blind_" + std::to_string(seed) + ".csv", f);
      write_measurement_csv(std::string(keep) + "/blind_" + std::to_string(seed) + "_clean.csv", clean);  // without noise
    }
    const Segmentation seg = segment(f);

    DiagnosisOptions o;
    o.base.law = law.name;
    o.base.law_values["dilation"] = law.values.at("dilation");
    // What a user measures apart and gives (the law fixes them by default): kn from a normal loading
    // test, Barton-Bandis's JCS (Schmidt hammer) and the specimen's length.
    for (const char* measured : {"kn", "jcs", "lab_length"})
      if (law.values.count(measured)) o.base.law_values[measured] = law.values.at(measured);
    o.base.element.max_step = kStep;
    o.base.element.length = 0.2;
    o.base.fit_step = kStep;
    o.check_base_laws = false;  // the user names the law; the base-law check has its own test
    // The catalogue: every physical effect registered but the test binary's own plug-in for the
    // second blind test (tests/plugins/), which a user's rockdem does not have.
    for (const auto& e : physical_effects())
      if (e != "mismatch_hardening") o.effects.push_back(e);
    const Diagnosis d = diagnose(f, seg, o);

    bool judged = true;
    for (const auto& e : effects) {
      for (const auto& t : d.ranking) {
        if (t.effect != e || (t.revealable && t.judged)) continue;
        judged = false;
        std::printf("  hidden %s not judged: %s\n", e.c_str(), t.reason.c_str());
      }
    }
    std::vector<std::string> added;
    for (std::size_t k = 1; k < d.ladder.size(); ++k) added.push_back(d.ladder[k].added);
    const double before = d.baseline.nrmse[2];
    const double after = d.ladder.size() >= 2 ? d.ladder[1].fit.nrmse[2] : before;
    const std::string first = d.ranking.empty() ? "(none)" : d.ranking.front().effect;
    Outcome o1;
    o1.hidden = effects.size();
    o1.first_ranked = !effects.empty() && contains(effects, first);
    bool all_added = added.size() == effects.size();
    for (const auto& e : effects) all_added = all_added && contains(added, e);
    o1.hit = judged && (effects.empty() ? added.empty() : o1.first_ranked && !added.empty() && contains(effects, added.front()) && all_added);
    // The cut: the first rung divides the combined NRMSE by 3 or more, unless the noise
    // leaves less to cut (first rung within twice the ceiling).
    o1.cut = !effects.empty() && (after <= before / 3.0 || after <= 2.0 * ceiling);
    o1.floor = !effects.empty() && d.ladder.back().fit.nrmse[2] <= 2.0 * ceiling;
    outcomes.push_back(o1);
    std::printf("  %s: ranked first %s; ladder %s; combined NRMSE %.4f, first rung %.4f, last %.4f, ceiling %.4f, %.1f s\n",
                o1.hit ? "hit" : "MISS", first.c_str(), joined(added).c_str(), before, after, d.ladder.back().fit.nrmse[2], ceiling,
                d.wall_ms / 1e3);
    if (std::getenv("ROCKDEM_BLIND_REPORT")) {
      std::printf("%s\n  parameters of the last rung:", format_report(d).c_str());
      for (const auto& p : d.ladder.back().fit.params) std::printf(" %s=%.6g", p.name.c_str(), p.value);
      std::printf("\n");
      for (const auto& c : d.decisions)
        if (c.added) std::printf("  step %zu, %s: %s\n", c.step, c.effect.c_str(), c.reason.c_str());
    }
    std::fflush(stdout);
  }
  std::array<std::size_t, 3> draws{}, hits{};
  std::size_t first_ranked = 0, cut = 0, floor = 0;
  for (const auto& o : outcomes) {
    ++draws[o.hidden];
    hits[o.hidden] += o.hit;
    first_ranked += o.first_ranked;
    cut += o.cut;
    floor += o.floor;
  }
  const std::size_t with_effect = draws[1] + draws[2], total_hits = hits[0] + hits[1] + hits[2];
  std::printf("blind broad, %zu draws: hits %zu; clean records left alone %zu of %zu; one hidden effect found %zu of %zu; "
              "two found %zu of %zu; a hidden effect ranked first %zu of %zu; first rung cut 3x (or to the noise) %zu of %zu; "
              "last rung within twice the ceiling %zu of %zu\n",
              outcomes.size(), total_hits, hits[0], draws[0], hits[1], draws[1], hits[2], draws[2], first_ranked, with_effect,
              cut, with_effect, floor, with_effect);
  // The suite's gate is today's measurement over its 60 draws (docs/validation.md, section 3, lists
  // the misses; the targets of 95 % are not all met). A change that loses a hit fails here;
  // one that gains hits should raise these numbers. Other seeds (ROCKDEM_BLIND_SEED[S]) are a
  // measurement and only print.
  if (!std::getenv("ROCKDEM_BLIND_SEED") && !std::getenv("ROCKDEM_BLIND_SEEDS")) {
    ASSERT_EQ(outcomes.size(), 60u);
    EXPECT_GE(total_hits, kGateHits);
    EXPECT_GE(hits[0], kGateClean);
    EXPECT_GE(hits[1], kGateOne);  // by category too: a gain in one must not hide a loss in another
    EXPECT_GE(hits[2], kGateTwo);
    EXPECT_EQ(first_ranked, with_effect);
    EXPECT_GE(cut, kGateCut);
    EXPECT_GE(floor, kGateFloor);
  }
}

// Effects that do not commute (rate_and_state replaces the friction part of the strength it is
// handed; directional_wear re-angles it), hidden in either order in a harmonic Barton-Bandis
// record (broad draw 27's): the ladder meets them in the order of their misfits, so in one of
// the two records it must put the second effect first in the chain. The final chain is the
// record's, in the record's order, and reaches its noise. Before rungs tried both ends of the
// chain, the record with rate_and_state first ended at 0.0035 against a ceiling of 0.0013, in
// the other order. Only the two effects are tried, to keep the test short.
TEST(BlindBroad, EffectsThatDoNotCommuteAreComposedInTheRecordsOrder) {
  const Law& law = laws()[1];
  ASSERT_EQ(std::string(law.name), "barton_bandis");
  const std::vector<std::vector<std::string>> orders{{"rate_and_state", "directional_wear"},
                                                     {"directional_wear", "rate_and_state"}};
  for (const auto& order : orders) {
    std::vector<EffectSpec> specs;
    for (const auto& e : order) specs.push_back(hidden(e));
    auto model = make_joint_model(law.name, law.values, specs, "blind");
    const MeasurementFile clean = run_protocol(*model, "harmonic");
    MeasurementFile f = clean;
    std::mt19937 rng(27);
    std::normal_distribution<double> g(0.0, 1.0);
    for (auto& r : f.rows) {
      r.shear_stress_MPa += 0.005 * g(rng);
      r.normal_disp_mm += 0.002 * g(rng);
    }
    const double ceiling = compare(f, clean).combined_nrmse;
    const Segmentation seg = segment(f);
    DiagnosisOptions o;
    o.base.law = law.name;
    for (const char* given : {"dilation", "kn", "jcs", "lab_length"}) o.base.law_values[given] = law.values.at(given);
    o.base.element.max_step = kStep;
    o.base.element.length = 0.2;
    o.base.fit_step = kStep;
    o.check_base_laws = false;
    o.effects = order;
    const Diagnosis d = diagnose(f, seg, o);
    const std::string what = "hidden " + joined(order) + "\n" + format_report(d);
    ASSERT_EQ(d.ladder.size(), 3u) << what;
    EXPECT_EQ(d.ladder.back().effects, order) << what;
    EXPECT_LE(d.ladder.back().fit.nrmse[2], 1.5 * ceiling) << what;
    // The rung that put its effect first says so, with the other order's error.
    for (const auto& c : d.decisions)
      if (c.added && c.composed_first) {
        EXPECT_EQ(c.effect, order.front()) << what;
        EXPECT_GT(c.nrmse_other_order, c.nrmse_after) << what;
      }
  }
}
