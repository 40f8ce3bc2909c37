// Joint-law updates per second (Google Benchmark): one contact point cycling through a
// +-10 mm path at 0.01 mm increments (the DEM situation: the engine gives du_n and du_s, the law
// returns stresses), for each law, and for laws with two effects. The normal increment gives
// back the previous increment's dilation, as a block free to move normally would, so the joint
// stays near 3 MPa instead of locking up or opening.
// Also the element driver's cost per increment (constant normal stress solved each increment),
// and each catalogue effect composed with mohr_coulomb (`effect_updates`: the same path with a
// time step, 0.01 mm in 0.1 s, so that rate_and_state sees a velocity).
//   build-laws/scripts/bench/rockdem_bench_laws --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "framework/lab/element_driver.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace {

using namespace rockdem;

RawValues vals(std::initializer_list<std::pair<std::string, std::string>> kv) {
  RawValues out;
  for (const auto& [k, v] : kv) out[k] = RawValue{v, "bench"};
  return out;
}

RawValues params_for(const std::string& law) {
  if (law == "mohr_coulomb")
    return vals({{"kn", "35.964 GPa/m"}, {"ks", "16.93 GPa/m"}, {"friction", "38 deg"}, {"dilation_angle", "2.4 deg"},
                 {"dilation", "reversible"}});
  if (law == "barton_bandis")
    return vals({{"kn", "35.964 GPa/m"}, {"ks", "16.929 GPa/m"}, {"jrc", "7.1"}, {"jcs", "170.5 MPa"},
                 {"residual_friction", "28.4 deg"}, {"lab_length", "0.2032 m"}, {"dilation", "reversible"}});
  if (law == "continuously_yielding")
    return vals({{"kn", "29.361 GPa/m"}, {"kn_min", "29.361 GPa/m"}, {"kn_max", "46.109 GPa/m"},
                 {"kn_exponent", "0.6783"}, {"ks", "29.312 GPa/m"}, {"initial_friction", "39.3 deg"},
                 {"friction", "33.5 deg"}, {"roughness", "0.0175 m"}, {"dilation", "reversible"}});
  return vals({{"kn", "35.964 GPa/m"}, {"ks", "16.93 GPa/m"}, {"friction", "38 deg"}});  // coulomb_slip
}

std::unique_ptr<JointModel> make(const std::string& law, int effects) {
  std::vector<EffectSpec> e;
  // Enabled effects with factor 1 run their full code but leave the physics (and so the path
  // through the law) unchanged, so the difference to the plain law is the cost of the chain.
  for (int i = 0; i < effects; ++i) e.push_back(EffectSpec{"strength_reduction", vals({{"factor", "1.0"}}), "bench"});
  return make_joint_model(law, params_for(law), e, "bench");
}

void run_updates(benchmark::State& state, const JointModel& model, double dt);

void law_updates(benchmark::State& state, const std::string& law, int effects) {
  auto m = make(law, effects);
  run_updates(state, *m, 0.0);
}

// One catalogue effect (default parameters unless given) on a base law.
void effect_updates(benchmark::State& state, const std::string& law, const std::string& effect, RawValues params) {
  std::vector<EffectSpec> e;
  if (!effect.empty()) e.push_back(EffectSpec{effect, std::move(params), "bench"});
  auto m = make_joint_model(law, params_for(law), e, "bench");
  run_updates(state, *m, 0.1);
}

void run_updates(benchmark::State& state, const JointModel& model, double dt) {
  const JointModel* m = &model;
  JointStateBlock s;
  m->init(s);
  JointResponse r;
  JointKinematics k;
  k.du_n = -3e6 / m->initial_kn();  // close to about 3 MPa once
  m->update(s, k, r);
  k.du_n = 0.0;
  k.dt = dt;
  long i = 0;
  double last_dilation = r.dilation;
  for (auto _ : state) {
    // 1000 increments forward, 2000 back, 1000 forward: a closed +-10 mm cycle. Every two cycles
    // the joint starts afresh, so that the wearing laws are timed while their roughness is
    // active (a worn-flat joint is cheaper) - the restart is 1 update in 8000.
    const long phase = i % 4000;
    if (i % 8000 == 0 && i > 0) {
      m->init(s);
      k.du_s = 0.0;
      k.du_n = -3e6 / m->initial_kn();
      m->update(s, k, r);
      k.du_n = 0.0;  // closed once only (it used to close twice, to about 6 MPa)
      last_dilation = r.dilation;
    }
    k.du_s = (phase < 1000 || phase >= 3000) ? 1e-5 : -1e-5;
    m->update(s, k, r);
    k.du_n = r.dilation - last_dilation;
    last_dilation = r.dilation;
    benchmark::DoNotOptimize(r);
    ++i;
  }
  if (r.open || r.sigma_n < 1e6 || r.sigma_n > 1e7) state.SkipWithError("the joint left the 1-10 MPa range");
  state.SetItemsProcessed(state.iterations());
}

void driver_increments(benchmark::State& state, const std::string& law) {
  auto m = make(law, 0);
  ElementDriver d(*m);
  ElementStage st;
  st.normal_stress = 3e6;
  d.begin_stage(st);
  long i = 0;
  for (auto _ : state) {
    const long phase = i % 4000;
    if (i % 8000 == 0 && i > 0) {  // a fresh specimen every two cycles, as above
      d.reset();
      d.begin_stage(st);
    }
    d.step(st, (phase < 1000 || phase >= 3000) ? 1e-5 : -1e-5, 0.0);
    benchmark::DoNotOptimize(d.response());
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}

void full_cycle(benchmark::State& state, const std::string& law) {
  auto m = make(law, 0);
  for (auto _ : state) {
    ElementDriver d(*m);
    auto f = d.run({ElementStage{3e6, NormalControl::constant_stress, 0.0, ShearPath::cycles(0.02, 1, 4.2e-5), nullptr}});
    benchmark::DoNotOptimize(f);
  }
}

}  // namespace

BENCHMARK_CAPTURE(law_updates, coulomb_slip, std::string("coulomb_slip"), 0);
BENCHMARK_CAPTURE(law_updates, mohr_coulomb, std::string("mohr_coulomb"), 0);
BENCHMARK_CAPTURE(law_updates, barton_bandis, std::string("barton_bandis"), 0);
BENCHMARK_CAPTURE(law_updates, continuously_yielding, std::string("continuously_yielding"), 0);
BENCHMARK_CAPTURE(law_updates, continuously_yielding_plus_2_effects, std::string("continuously_yielding"), 2);
BENCHMARK_CAPTURE(law_updates, mohr_coulomb_plus_2_effects, std::string("mohr_coulomb"), 2);
BENCHMARK_CAPTURE(effect_updates, mohr_coulomb_dt, std::string("mohr_coulomb"), std::string(), RawValues{});
BENCHMARK_CAPTURE(effect_updates, mc_reverse_shear_degradation, std::string("mohr_coulomb"),
                  std::string("reverse_shear_degradation"), RawValues{});
BENCHMARK_CAPTURE(effect_updates, mc_dilation_recovery, std::string("mohr_coulomb"), std::string("dilation_recovery"),
                  RawValues{});
BENCHMARK_CAPTURE(effect_updates, mc_directional_wear_16, std::string("mohr_coulomb"), std::string("directional_wear"),
                  RawValues{{"bins", RawValue{std::int64_t{16}, "bench"}}});
BENCHMARK_CAPTURE(effect_updates, mc_two_order_roughness, std::string("mohr_coulomb"), std::string("two_order_roughness"),
                  RawValues{});
BENCHMARK_CAPTURE(effect_updates, mc_rate_and_state, std::string("mohr_coulomb"), std::string("rate_and_state"),
                  RawValues{});
// A closure curve that puts the joint near 3 MPa from the bench's initial closure 3 MPa/Kni.
BENCHMARK_CAPTURE(effect_updates, mc_hyperbolic_normal_closure, std::string("mohr_coulomb"),
                  std::string("hyperbolic_normal_closure"), vals({{"max_closure", "0.5 mm"}}));
BENCHMARK_CAPTURE(effect_updates, continuously_yielding_dt, std::string("continuously_yielding"), std::string(),
                  RawValues{});
BENCHMARK_CAPTURE(effect_updates, cy_directional_wear_16, std::string("continuously_yielding"),
                  std::string("directional_wear"), RawValues{{"bins", RawValue{std::int64_t{16}, "bench"}}});
BENCHMARK_CAPTURE(driver_increments, mohr_coulomb_cnl, std::string("mohr_coulomb"));
BENCHMARK_CAPTURE(driver_increments, barton_bandis_cnl, std::string("barton_bandis"));
BENCHMARK_CAPTURE(driver_increments, continuously_yielding_cnl, std::string("continuously_yielding"));
BENCHMARK_CAPTURE(full_cycle, mohr_coulomb_40mm_cycle, std::string("mohr_coulomb"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(full_cycle, barton_bandis_40mm_cycle, std::string("barton_bandis"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(full_cycle, continuously_yielding_40mm_cycle, std::string("continuously_yielding"))
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
