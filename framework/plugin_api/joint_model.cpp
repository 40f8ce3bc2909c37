#include "framework/plugin_api/joint_law.hpp"

#include <cstring>

namespace rockdem {

namespace {
std::size_t align_up(std::size_t x, std::size_t a) { return (x + a - 1) / a * a; }
}  // namespace

JointModel::JointModel(std::unique_ptr<JointLawBase> law, std::vector<std::unique_ptr<EffectBase>> effects)
    : law_(std::move(law)), owned_(std::move(effects)) {
  std::size_t off = law_->state_size();
  for (const auto& e : owned_) {
    off = align_up(off, e->state_align());
    offsets_.push_back(off);
    effects_.push_back(e.get());
    off += e->state_size();
    if (e->has_normal()) normal_ = e.get();
  }
  if (off > kJointStateBytes) {
    throw InputError("joint model '" + description() + "' needs " + std::to_string(off) +
                     " bytes of state per contact; the limit is " + std::to_string(kJointStateBytes));
  }
  state_size_ = off;
}

void JointModel::init(std::byte* s) const {
  std::memset(s, 0, state_size_);
  law_->init(s);
  for (std::size_t i = 0; i < effects_.size(); ++i) effects_[i]->init(s + offsets_[i]);
}

void JointModel::update(std::byte* s, const JointKinematics& k, JointResponse& r) const {
  EffectChain chain(&effects_, &offsets_, s, normal_);
  law_->update(s, k, r, chain);
  chain.after(r);
}

std::string JointModel::description() const {
  std::string d = law_->name();
  for (const auto* e : effects_) d += std::string(" + ") + e->name();
  return d;
}

std::unique_ptr<JointModel> make_joint_model(const std::string& law, const RawValues& law_params,
                                             const std::vector<EffectSpec>& effects,
                                             const std::string& where) {
  const auto& le = JointLawRegistry::instance().get(law, "joint law", where);
  auto base = le.make(law_params, where);
  std::vector<std::unique_ptr<EffectBase>> eff;
  for (const auto& es : effects) {
    const auto& ee = EffectRegistry::instance().get(es.name, "effect", es.where);
    eff.push_back(ee.make(es.params, es.where));
  }
  return std::make_unique<JointModel>(std::move(base), std::move(eff));
}

}  // namespace rockdem
