#pragma once
// Typed effects. An effect is a small struct of the same shape as a joint law:
//   struct MyEffect {
//     static constexpr const char* name = "my_effect";
//     struct Params { bool enabled; ...; static std::vector<Param<Params>> spec(); };
//     struct State { ... };                                   // trivially copyable
//     static void init(const Params&, State&);
//     static void modify(const Params&, State&, ShearContext&); // before the base law's yield check
//     static void after(const Params&, State&, const ShearContext&, const JointResponse&);
//     // optional, replaces the base law's normal stress-closure relation (closure v > 0 closes):
//     static double normal_stress(const Params&, double v);
//     static double normal_closure(const Params&, double sigma_n);
//     static double normal_tangent(const Params&, double v);
//   };
//   ROCKDEM_REGISTER_EFFECT(MyEffect, "summary", "reference");
// Optionally, what `rockdem calibrate` and `rockdem diagnose` should know of it (absent: the
// default in brackets):
//     static constexpr bool physical = false;              // [true] in diagnose's catalogue?
//     static std::vector<std::string> fixed_by_default();  // [none] parameters kept fixed unless freed
//     static std::string unjudgeable(const RecordFeatures&); // [any record can reveal it] why a
//                                                         // record cannot reveal it, "" if it can
// An effect with enabled = false must leave the base law's results identical, bit for bit.
#include <concepts>
#include <cstring>

#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

template <class Effect>
class EffectAdapter final : public EffectBase {
 public:
  using Params = typename Effect::Params;
  using State = typename Effect::State;
  static_assert(std::is_trivially_copyable_v<State>, "effect State must be trivially copyable");
  explicit EffectAdapter(Params p) : p_(p) {}
  const char* name() const override { return Effect::name; }
  std::size_t state_size() const override { return sizeof(State); }
  std::size_t state_align() const override { return alignof(State); }
  void init(std::byte* s) const override {
    State st{};
    Effect::init(p_, st);
    std::memcpy(s, &st, sizeof(State));
  }
  void modify(std::byte* s, ShearContext& ctx) const override {
    if (!p_.enabled) return;
    State st;
    std::memcpy(&st, s, sizeof(State));
    Effect::modify(p_, st, ctx);
    std::memcpy(s, &st, sizeof(State));
  }
  void after(std::byte* s, const ShearContext& ctx, const JointResponse& r) const override {
    if (!p_.enabled) return;
    State st;
    std::memcpy(&st, s, sizeof(State));
    Effect::after(p_, st, ctx, r);
    std::memcpy(s, &st, sizeof(State));
  }
  static constexpr bool kHasNormal = requires(const Params& q) { Effect::normal_stress(q, 0.0); };
  bool has_normal() const override { return kHasNormal && p_.enabled; }
  double normal_stress(double v) const override {
    if constexpr (kHasNormal) return Effect::normal_stress(p_, v);
    return 0.0;
  }
  double normal_closure(double sigma) const override {
    if constexpr (kHasNormal) return Effect::normal_closure(p_, sigma);
    return 0.0;
  }
  double normal_tangent(double v) const override {
    if constexpr (kHasNormal) return Effect::normal_tangent(p_, v);
    return 0.0;
  }

 private:
  Params p_;
};

namespace detail {
template <class Effect>
struct EffectRegistrar {
  EffectRegistrar(const char* summary, const char* reference) {
    EffectRegistry::Entry e;
    e.name = Effect::name;
    e.summary = summary;
    e.reference = reference;
    e.params = param_infos<typename Effect::Params>();
    e.make = [](const RawValues& v, const std::string& where) -> std::unique_ptr<EffectBase> {
      return std::make_unique<EffectAdapter<Effect>>(
          bind_params<typename Effect::Params>(v, std::string("effect '") + Effect::name + "'", where));
    };
    e.declared.fixed_by_default = declared_fixed_by_default<Effect>();
    if constexpr (requires { { Effect::physical } -> std::convertible_to<bool>; }) e.declared.physical = Effect::physical;
    if constexpr (requires(const RecordFeatures& f) { { Effect::unjudgeable(f) } -> std::convertible_to<std::string>; }) {
      e.declared.unjudgeable = [](const RecordFeatures& f) -> std::string { return Effect::unjudgeable(f); };
    }
    EffectRegistry::instance().add(std::move(e));
  }
};
}  // namespace detail

#define ROCKDEM_REGISTER_EFFECT(Effect, summary, reference)                                   \
  namespace {                                                                                 \
  const ::rockdem::detail::EffectRegistrar<Effect> ROCKDEM_CONCAT(rockdem_effect_registrar_, \
                                                                  __LINE__){summary, reference}; \
  }

}  // namespace rockdem
