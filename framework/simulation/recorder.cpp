#include "framework/simulation/recorder.hpp"

namespace rockdem {

Recorder::Recorder(const Case& c, const Engine& e, const std::filesystem::path& history_file) : c_(c), e_(e) {
  stage_id_ = h_.define("stage", "", "index of the stage (1-based)");
  for (const auto& s : c.histories) h_.define(s.name, s.unit, s.description);
  // Its columns follow the case's histories.
  if (c.direct_shear.enabled) direct_shear_.emplace(c, e, h_);
  h_.open(history_file.string());
}

void Recorder::stage_started(int index, const std::string& name) {
  stage_ = index;
  if (direct_shear_) direct_shear_->stage_started(name);
}

void Recorder::sample() {
  const Model& m = c_.model;
  h_.set(stage_id_, stage_);
  for (std::size_t i = 0; i < c_.histories.size(); ++i) h_.set(static_cast<int>(i) + 1, value(c_.histories[i]) * c_.histories[i].scale);
  if (direct_shear_) direct_shear_->sample(h_);
  h_.commit(m.time, m.step);
}

double Recorder::value(const HistorySpec& s) const {
  return s.quantity->measure(c_.model, e_, s.target);
}

}  // namespace rockdem
