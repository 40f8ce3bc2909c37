#pragma once
// Zone (rock matrix) materials for deformable blocks. Same shape as joint laws: typed Params, a
// trivially copyable per-zone State (at most 64 bytes), registered by name next to the definition.
// Sign convention: continuum mechanics, tension positive; plane strain.
#include <cstring>

#include "framework/core/types.hpp"
#include "framework/core/registry.hpp"

namespace rockdem {

class RockMaterialBase {
 public:
  virtual ~RockMaterialBase() = default;
  virtual const char* name() const = 0;
  virtual double density() const = 0;       // [kg/m^3]
  virtual double bulk_modulus() const = 0;  // [Pa] (for the stable time step)
  virtual double shear_modulus() const = 0; // [Pa]
  virtual void init(std::byte* state) const = 0;
  // Update the stress with a strain increment (engineering shear strain in component 2).
  virtual void update(std::byte* state, const Voigt3& dstrain, Voigt3& stress, double& szz) const = 0;
};

using RockMaterialRegistry = Registry<RockMaterialBase>;

template <class M>
class RockMaterialAdapter final : public RockMaterialBase {
 public:
  using Params = typename M::Params;
  using State = typename M::State;
  static_assert(std::is_trivially_copyable_v<State> && sizeof(State) <= 64, "rock State must fit 64 bytes");
  explicit RockMaterialAdapter(Params p) : p_(p) {}
  const char* name() const override { return M::name; }
  double density() const override { return p_.density; }
  double bulk_modulus() const override { return p_.bulk; }
  double shear_modulus() const override { return p_.shear; }
  void init(std::byte* s) const override {
    State st{};
    std::memcpy(s, &st, sizeof(State));
  }
  void update(std::byte* s, const Voigt3& de, Voigt3& sig, double& szz) const override {
    State st;
    std::memcpy(&st, s, sizeof(State));
    M::update(p_, st, de, sig, szz);
    std::memcpy(s, &st, sizeof(State));
  }
  const Params& params() const { return p_; }

 private:
  Params p_;
};

namespace detail {
template <class M>
struct RockMaterialRegistrar {
  RockMaterialRegistrar(const char* summary, const char* reference) {
    RockMaterialRegistry::Entry e;
    e.name = M::name;
    e.summary = summary;
    e.reference = reference;
    e.params = param_infos<typename M::Params>();
    e.make = [](const RawValues& v, const std::string& where) -> std::unique_ptr<RockMaterialBase> {
      return std::make_unique<RockMaterialAdapter<M>>(
          bind_params<typename M::Params>(v, std::string("rock material '") + M::name + "'", where));
    };
    RockMaterialRegistry::instance().add(std::move(e));
  }
};
}  // namespace detail

#define ROCKDEM_REGISTER_ROCK_MATERIAL(M, summary, reference)                                     \
  namespace {                                                                                     \
  const ::rockdem::detail::RockMaterialRegistrar<M> ROCKDEM_CONCAT(rockdem_rock_registrar_, \
                                                                   __LINE__){summary, reference}; \
  }

}  // namespace rockdem
