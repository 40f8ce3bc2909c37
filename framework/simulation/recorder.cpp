#include "framework/simulation/recorder.hpp"

#include <cmath>

namespace rockdem {

Recorder::Recorder(Case& c, const Engine& e, const std::filesystem::path& history_file) : c_(c), e_(e) {
  stage_id_ = h_.define("stage", "", "index of the stage (1-based)");
  needs_state_ = c.direct_shear.enabled;
  for (const auto& s : c.histories)
    if (s.quantity->reduction == Reduction::state) {
      needs_state_ = true;
      state_parts_ |= s.quantity->state_parts;
    }
  for (const auto& s : c.histories) h_.define(s.name, s.unit, s.description);
  // Its columns follow the case's histories.
  if (c.direct_shear.enabled) direct_shear_.emplace(c, e, h_);
  // In a decomposed run process 0 writes; the others take part in forming the values.
  if (e.communication().root()) h_.open(history_file.string());
}

void Recorder::stage_started(int index, const std::string& name) {
  stage_ = index;
  if (direct_shear_) direct_shear_->stage_started(name);
}

void Recorder::sample() {
  Model& m = c_.model;
  Communication& comm = e_.communication();
  // A decomposed run first makes the model's state current on process 0 (quantities read from
  // the state are measured there), then goes on stepping with its own contacts.
  std::vector<Contact> local;
  const bool collected = m.part.decomposed() && needs_state_;
  if (collected) comm.collect(m, 0, &local, state_parts_);
  h_.set(stage_id_, stage_);
  for (std::size_t i = 0; i < c_.histories.size(); ++i) h_.set(static_cast<int>(i) + 1, value(c_.histories[i]) * c_.histories[i].scale);
  if (direct_shear_) direct_shear_->sample(h_);
  h_.commit(m.time, m.step);
  if (collected && comm.root() && (state_parts_ & kContactState)) m.contacts.restore(std::move(local));
}

double Recorder::value(const HistorySpec& s) const {
  const Model& m = c_.model;
  if (!m.part.decomposed()) return s.quantity->measure(m, e_, s.target);
  Communication& comm = e_.communication();
  switch (s.quantity->reduction) {
    case Reduction::global: return s.quantity->measure(m, e_, s.target);
    case Reduction::owner: {
      double v = m.part.owns(s.target.block) ? s.quantity->measure(m, e_, s.target) : 0.0;
      comm.sum(&v, 1);
      return v;
    }
    case Reduction::state: break;
  }
  return comm.root() ? s.quantity->measure(m, e_, s.target) : std::nan("");
}

}  // namespace rockdem
