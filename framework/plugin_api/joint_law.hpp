#pragma once
// The joint-law interface: one call per contact point per step, the same for the DEM engine and
// the element driver. A law sees only the contact's kinematic increment and its own state; it
// returns stresses (compression positive) and what it dissipated. Effects (models/effects/)
// adjust the strength and dilation a base law uses, through the ShearContext hook, and keep
// their own state beside the base state in one fixed-size block per contact.
//
// A law is a small struct:
//   struct MyLaw {
//     static constexpr const char* name = "my_law";
//     struct Params { double kn; ...; static std::vector<Param<Params>> spec(); };
//     struct State  { ... };                                // trivially copyable, fixed size
//     static void init(const Params&, State&);
//     static void update(const Params&, State&, const JointKinematics&, JointResponse&,
//                        EffectChain&);                     // call chain.modify(ctx) once
//   };
//   ROCKDEM_REGISTER_JOINT_LAW(MyLaw, "summary", "reference");
// Optionally, values computed from the parameters alone (tangents of fixed angles, scale
// corrections), made once when the law is built instead of on every update:
//     struct Derived { ... };
//     static Derived derive(const Params&);
//     static void update(const Params&, const Derived&, State&, const JointKinematics&,
//                        JointResponse&, EffectChain&);     // instead of the form above
// Optionally, what `rockdem calibrate` should know of it:
//     static std::vector<std::string> fixed_by_default();  // parameters kept fixed unless freed
#include <array>
#include <concepts>
#include <cstddef>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "framework/core/registry.hpp"
#include "framework/plugin_api/record_features.hpp"

namespace rockdem {

// Kinematic input to one joint-point update.
struct JointKinematics {
  double du_n = 0.0;    // normal displacement increment, opening positive [m]
  double du_s = 0.0;    // shear displacement increment, relative (top minus bottom) [m]
  double dt = 0.0;      // time increment [s] (0 in pseudo-static element paths)
  double length = 1.0;  // contact length [m] (for laws that need it; stresses are per area)
  // The normal stress the increment is to end at, where the caller prescribes it (the element
  // driver solving for a stage's normal condition; NaN: not prescribed, as in the DEM engine).
  // A law whose strength depends on the normal stress evaluates it there instead of solving for
  // the normal stress consistent with its dilation (law_support::solve_increment): the caller's
  // normal displacement then meets the condition where the law's response says it does, and
  // under a constant normal stress that response falls with du_n at the closure curve's slope
  // even past the fold of a contracting joint, where the consistent stress of a given du_n may
  // not exist (under a constant normal stiffness K too, unless K is of the order of
  // ks/(|dilation rate| tan(phi)), far stiffer than a laboratory's).
  double sigma_n_given = std::numeric_limits<double>::quiet_NaN();
};

// Output of one update (stresses are the state after the increment).
struct JointResponse {
  double sigma_n = 0.0;     // normal stress, compression positive [Pa]
  double tau = 0.0;         // shear stress, sign of the shear direction [Pa]
  double kn = 0.0;          // current normal stiffness, for the stable time step [Pa/m]
  double ks = 0.0;          // current shear stiffness [Pa/m]
  double u_s = 0.0;         // shear offset from the mated position [m]
  double u_n = 0.0;         // normal displacement from the initial contact, opening positive [m]
  double dilation = 0.0;    // accumulated shear dilation [m]
  double dissipated = 0.0;  // energy dissipated in this increment, per unit area [J/m^2]
  bool slipping = false;
  bool open = false;
  // False where the law's strength could not be made consistent with the normal stress it ends
  // at (law_support::consistent_sigma found no fixed point: none exists, as for a contracting
  // joint past the fold, kn |dilation rate| tan(phi) > ks, or its secant did not converge) and
  // the explicit update at the trial stress was kept, as UDEC does. The DEM engine takes such an
  // update as it is; the element driver, solving for a normal stress, does not accept it as
  // meeting the stage's normal condition. Handed a prescribed stress (JointKinematics::
  // sigma_n_given) the published laws evaluate their strength there and report true, whether or
  // not the increment ends there (meeting it is the caller's check): the driver's rejection then
  // concerns laws that do not read the prescribed stress. Set afresh by every update: not
  // checkpointed or packed.
  bool consistent = true;

  // Back to the values above. Laws call it at the start of every update: `r = JointResponse{}`
  // makes GCC 12 build the defaults on the stack and read the three flags back as one word across
  // their byte stores, a store-forwarding stall that was a quarter of Mohr-Coulomb's update;
  // copying a constant has none.
  void reset() {
    static constexpr JointResponse kDefaults{};
    *this = kDefaults;
  }
};

// What a base law exposes to effects at the point where it evaluates its shear strength and
// dilation. Effects read the kinematics and may change `strength` and `dilation_rate`.
struct ShearContext {
  double sigma_n = 0.0;          // normal stress used for the strength [Pa]
  double u_s = 0.0;              // shear offset from the mated position before the increment [m]
  double du_s = 0.0;             // shear increment [m]
  double plastic_slip = 0.0;     // accumulated plastic shear displacement [m]
  double basic_friction = 0.0;   // basic/residual friction angle [rad]
  double roughness_angle = 0.0;  // current roughness (dilation) angle the base law uses [rad]
  double strength = 0.0;         // bounding shear strength, magnitude [Pa]; effects may change it
  // An effect whose strength is not a fixed multiple of the one it is handed (rate_and_state:
  // the slip rate, and with it the friction, follows the normal stress within the increment)
  // gives it as a function: strength_at(strength_args, handed, sigma) is what the effect returns
  // when handed the strength `handed` at normal stress `sigma`, all else as read at the trial
  // stress (the trial shear stress, the effect's state). The law then evaluates it at each normal
  // stress of its consistency solve instead of scaling the change it made at the trial stress
  // (law_support::StrengthChange); the effects before it in the chain are carried as the factor
  // strength_handed / the law's own strength, those after it as strength / strength_returned,
  // both at the trial stress. Null: every effect's change is a factor (or an offset).
  double (*strength_at)(const double* args, double handed, double sigma) = nullptr;
  // Not zeroed: read only through strength_at, by the effect that wrote them (zeroing them on
  // every update was a `rep stos`, a tenth of Mohr-Coulomb's update).
  std::array<double, 8> strength_args;
  double strength_handed = 0.0, strength_returned = 0.0;
  double dilation_rate = 0.0;    // d(dilation)/d|du_s^p| with its sign; effects may change it
  // The law derives its dilation from the shear stress it carries (Continuously-Yielding, eq.
  // 3-16: tan(atan(tau/sigma_n) - phi)), so an effect that raises the strength raises the
  // dilation through the stress, in the increments that follow; scaling dilation_rate for the
  // same cause as well would count it twice.
  bool dilation_follows_stress = false;
  bool toward_origin = false;    // the increment moves back toward the mated position
  double dt = 0.0;               // time increment [s] (0: pseudo-static)
  double tau = 0.0;              // shear stress before the increment [Pa]
  double shear_stiffness = 0.0;  // elastic shear stiffness of the increment [Pa/m]
  // The base law's roughness angle [rad] at a given value of its own wear measure (the
  // `plastic_slip` above) and normal stress, as on a virgin surface: lets an effect ask what a
  // surface worn less than the law's single history would offer (directional_wear). Optional.
  double (*roughness_at)(const void* law, double slip, double sigma_n) = nullptr;
  const void* law = nullptr;  // first argument of roughness_at
  double roughness(double slip, double sigma) const {
    return roughness_at ? roughness_at(law, slip, sigma) : roughness_angle;
  }
};

// Type-erased effect (see framework/plugin_api/effect.hpp for the typed form).
class EffectBase {
 public:
  virtual ~EffectBase() = default;
  virtual const char* name() const = 0;
  virtual std::size_t state_size() const = 0;
  virtual std::size_t state_align() const = 0;
  virtual void init(std::byte* state) const = 0;
  virtual void modify(std::byte* state, ShearContext& ctx) const = 0;
  virtual void after(std::byte* state, const ShearContext& ctx, const JointResponse& r) const = 0;
  // Optional normal-response hook: an effect that replaces the base law's normal stress-closure
  // relation returns true here and defines the three functions (closure v > 0 compresses,
  // sigma compression positive; pure functions of the parameters). Laws reach it through
  // EffectChain::normal(), which is null unless such an effect is present and enabled, so laws
  // and effects without it are untouched and pay no virtual call.
  virtual bool has_normal() const { return false; }
  virtual double normal_stress(double /*closure*/) const { return 0.0; }
  virtual double normal_closure(double /*sigma_n*/) const { return 0.0; }
  virtual double normal_tangent(double /*closure*/) const { return 0.0; }
};

// Ordered list of effects with the offsets of their state in the contact's state block. A base
// law calls modify() once per update, where it has computed its own strength and dilation rate,
// and after() is called by the composed law once the response is known.
class EffectChain {
 public:
  EffectChain() = default;
  EffectChain(const std::vector<const EffectBase*>* effects, const std::vector<std::size_t>* offsets,
              std::byte* block, const EffectBase* normal = nullptr)
      : effects_(effects), offsets_(offsets), block_(block), normal_(normal) {}
  // The effect that defines the normal response, or null (the law's own relation applies).
  const EffectBase* normal() const { return normal_; }
  void modify(ShearContext& ctx) {
    // Kept for after(), which does nothing without effects: no copy then (the context, 200
    // bytes, was copied twice per update, once right after the law wrote it: a load stalled on
    // those stores).
    if (!effects_ || effects_->empty()) return;
    for (std::size_t i = 0; i < effects_->size(); ++i) (*effects_)[i]->modify(block_ + (*offsets_)[i], ctx);
    last_ = ctx;
  }
  void after(const JointResponse& r) const {
    if (!effects_ || effects_->empty()) return;
    for (std::size_t i = 0; i < effects_->size(); ++i) (*effects_)[i]->after(block_ + (*offsets_)[i], last_, r);
  }

 private:
  const std::vector<const EffectBase*>* effects_ = nullptr;
  const std::vector<std::size_t>* offsets_ = nullptr;
  std::byte* block_ = nullptr;
  const EffectBase* normal_ = nullptr;
  ShearContext last_{};
};

// The most state a joint model (base law + effects) may have, bytes. A contact carries only what
// its store's models need (JointModel::state_size(), in the store's ContactStates, contact.hpp);
// a JointStateBlock holds any model's, for one joint (the element driver) or a trial update.
// States are trivially copyable, so they migrate and are checkpointed as raw bytes.
inline constexpr std::size_t kJointStateBytes = 256;
struct alignas(16) JointStateBlock {
  std::array<std::byte, kJointStateBytes> bytes{};
};

// Type-erased base law.
class JointLawBase {
 public:
  virtual ~JointLawBase() = default;
  virtual const char* name() const = 0;
  virtual std::size_t state_size() const = 0;
  virtual std::size_t state_align() const = 0;
  virtual void init(std::byte* state) const = 0;
  virtual void update(std::byte* state, const JointKinematics& k, JointResponse& r,
                      EffectChain& chain) const = 0;
  // Stiffnesses used for the stable time step before the first update [Pa/m].
  virtual double initial_kn() const = 0;
  virtual double initial_ks() const = 0;
};

namespace detail {
// A law's Derived values (see the top of this file), or nothing.
template <class Law>
concept HasDerived = requires(const typename Law::Params& p) {
  { Law::derive(p) } -> std::same_as<typename Law::Derived>;
};
struct NoDerived {};
template <class Law>
struct DerivedOf {
  using type = NoDerived;
};
template <HasDerived Law>
struct DerivedOf<Law> {
  using type = typename Law::Derived;
};
}  // namespace detail

template <class Law>
class JointLawAdapter final : public JointLawBase {
 public:
  using Params = typename Law::Params;
  using State = typename Law::State;
  using Derived = typename detail::DerivedOf<Law>::type;
  static_assert(std::is_trivially_copyable_v<State>, "joint-law State must be trivially copyable");
  explicit JointLawAdapter(Params p) : p_(p) {
    if constexpr (detail::HasDerived<Law>) d_ = Law::derive(p_);
  }
  const char* name() const override { return Law::name; }
  std::size_t state_size() const override { return sizeof(State); }
  std::size_t state_align() const override { return alignof(State); }
  void init(std::byte* s) const override {
    State st{};
    Law::init(p_, st);
    std::memcpy(s, &st, sizeof(State));
  }
  void update(std::byte* s, const JointKinematics& k, JointResponse& r, EffectChain& chain) const override {
    State st;
    std::memcpy(&st, s, sizeof(State));
    if constexpr (detail::HasDerived<Law>) Law::update(p_, d_, st, k, r, chain);
    else Law::update(p_, st, k, r, chain);
    std::memcpy(s, &st, sizeof(State));
  }
  double initial_kn() const override { return Law::initial_kn(p_); }
  double initial_ks() const override { return Law::initial_ks(p_); }
  const Params& params() const { return p_; }

 private:
  Params p_;
  [[no_unique_address]] Derived d_{};
};

// What a law or an effect declares for calibration, in its own file (optional; the defaults are
// what a plug-in that declares nothing gets).
struct CalibrationDeclarations {
  // Real parameters (unqualified names, of the plug-in's own Params) that `rockdem calibrate`
  // keeps at their written or default value unless freed: those a shear record cannot identify.
  std::vector<std::string> fixed_by_default;
};
// An effect declares besides what `rockdem diagnose` needs to try it.
struct EffectDeclarations : CalibrationDeclarations {
  // false: not a physical effect of rock joints (a modelling device such as a strength
  // reduction factor); diagnose leaves it out of its catalogue.
  bool physical = true;
  // Why a record cannot reveal the effect ("" if it can); null: any record can.
  std::string (*unjudgeable)(const RecordFeatures&) = nullptr;
};

using JointLawRegistry = Registry<JointLawBase, CalibrationDeclarations>;
using EffectRegistry = Registry<EffectBase, EffectDeclarations>;

namespace detail {
// A law's or effect's `static std::vector<std::string> fixed_by_default()`, if it has one.
template <class T>
std::vector<std::string> declared_fixed_by_default() {
  if constexpr (requires { { T::fixed_by_default() } -> std::convertible_to<std::vector<std::string>>; }) {
    return T::fixed_by_default();
  } else {
    return {};
  }
}
}  // namespace detail

// A base law with its ordered effects: what a contact (or the element driver) actually calls.
class JointModel {
 public:
  JointModel(std::unique_ptr<JointLawBase> law, std::vector<std::unique_ptr<EffectBase>> effects);
  JointModel(const JointModel&) = delete;
  JointModel& operator=(const JointModel&) = delete;

  // The state of one contact (or of the element driver's joint): state_size() bytes, aligned as
  // JointStateBlock, which holds any model's.
  std::size_t state_size() const { return state_size_; }
  void init(std::byte* s) const;
  void update(std::byte* s, const JointKinematics& k, JointResponse& r) const;
  void init(JointStateBlock& s) const {
    s = JointStateBlock{};
    init(s.bytes.data());
  }
  void update(JointStateBlock& s, const JointKinematics& k, JointResponse& r) const { update(s.bytes.data(), k, r); }
  const JointLawBase& law() const { return *law_; }
  std::size_t effect_count() const { return effects_.size(); }
  std::string description() const;  // "continuously_yielding + a + b"
  // The law's, or the normal-response effect's tangent at zero closure.
  double initial_kn() const { return normal_ ? normal_->normal_tangent(0.0) : law_->initial_kn(); }
  double initial_ks() const { return law_->initial_ks(); }

 private:
  std::unique_ptr<JointLawBase> law_;
  std::vector<std::unique_ptr<EffectBase>> owned_;
  std::vector<const EffectBase*> effects_;
  std::vector<std::size_t> offsets_;
  std::size_t state_size_ = 0;          // the law's state, then each effect's at its offset
  const EffectBase* normal_ = nullptr;  // last enabled effect with a normal hook
};

// Build a joint model from a law name, its parameter values, and effects (name + values), each in
// the order given. Unknown names and parameters are InputErrors that list the valid ones.
struct EffectSpec {
  std::string name;
  RawValues params;
  std::string where;
};
std::unique_ptr<JointModel> make_joint_model(const std::string& law, const RawValues& law_params,
                                             const std::vector<EffectSpec>& effects,
                                             const std::string& where);

namespace detail {
template <class Law>
struct JointLawRegistrar {
  JointLawRegistrar(const char* summary, const char* reference) {
    JointLawRegistry::Entry e;
    e.name = Law::name;
    e.summary = summary;
    e.reference = reference;
    e.params = param_infos<typename Law::Params>();
    e.make = [](const RawValues& v, const std::string& where) -> std::unique_ptr<JointLawBase> {
      return std::make_unique<JointLawAdapter<Law>>(
          bind_params<typename Law::Params>(v, std::string("joint law '") + Law::name + "'", where));
    };
    e.declared.fixed_by_default = declared_fixed_by_default<Law>();
    JointLawRegistry::instance().add(std::move(e));
  }
};
}  // namespace detail

#define ROCKDEM_REGISTER_JOINT_LAW(Law, summary, reference)                                  \
  namespace {                                                                                \
  const ::rockdem::detail::JointLawRegistrar<Law> ROCKDEM_CONCAT(rockdem_law_registrar_, \
                                                                 __LINE__){summary, reference}; \
  }

}  // namespace rockdem
