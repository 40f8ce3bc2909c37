#include "framework/simulation/recorder.hpp"

#include <cmath>

#include "framework/core/error.hpp"

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
  ContactList local;
  const bool collected = m.part.decomposed() && needs_state_;
  if (collected) comm.collect(m, 0, &local, state_parts_);
  h_.set(stage_id_, stage_);
  for (std::size_t i = 0; i < c_.histories.size(); ++i) h_.set(static_cast<int>(i) + 1, value(c_.histories[i]) * c_.histories[i].scale);
  if (direct_shear_) direct_shear_->sample(h_);
  h_.commit(m.time, m.step);
  if (collected && comm.root() && (state_parts_ & kContactState)) m.contacts.restore(std::move(local));
}

std::map<std::string, std::vector<double>> Recorder::saved_state() const {
  std::map<std::string, std::vector<double>> a;
  a["history.time"].assign(h_.times().begin(), h_.times().end());
  a["history.step"].assign(h_.steps().begin(), h_.steps().end());
  for (std::size_t i = 0; i < h_.series_count(); ++i) {
    const auto v = h_.values(static_cast<int>(i));
    a["history." + h_.info(static_cast<int>(i)).name].assign(v.begin(), v.end());
  }
  if (direct_shear_) a.merge(direct_shear_->saved_state());
  return a;
}

void Recorder::restore_state(const std::map<std::string, std::vector<double>>& a, const std::string& file) {
  const auto t = a.find("history.time");
  const auto st = a.find("history.step");
  if (t == a.end() || st == a.end()) return;  // a checkpoint written before histories travelled in them
  std::vector<const std::vector<double>*> cols;
  for (std::size_t i = 0; i < h_.series_count(); ++i) {
    const std::string& name = h_.info(static_cast<int>(i)).name;
    const auto it = a.find("history." + name);
    if (it == a.end())
      throw InputError(file + ": the checkpoint's history has no series '" + name + "' (its case recorded other histories)");
    if (it->second.size() != t->second.size())
      throw InputError(file + ": the checkpoint's history series '" + name + "' has " + std::to_string(it->second.size()) +
                       " samples, its times " + std::to_string(t->second.size()) + " (a damaged checkpoint)");
    cols.push_back(&it->second);
  }
  std::vector<double> row(cols.size());
  for (std::size_t k = 0; k < t->second.size(); ++k) {
    for (std::size_t i = 0; i < cols.size(); ++i) row[i] = (*cols[i])[k];
    h_.sample(t->second[k], static_cast<long>(st->second[k]), row);
  }
  if (direct_shear_) direct_shear_->restore_state(a, file);
}

double Recorder::value(const HistorySpec& s) const {
  const Model& m = c_.model;
  if (!m.part.decomposed()) return s.quantity->measure(m, e_, s.target);
  Communication& comm = e_.communication();
  switch (s.quantity->reduction) {
    case Reduction::global: return s.quantity->measure(m, e_, s.target);
    case Reduction::owner: {
      double v = m.part.owns(s.target.block) ? s.quantity->measure(m, e_, s.target) : 0.0;
      comm.sum_held(&v, 1);
      return v;
    }
    case Reduction::state: break;
  }
  return comm.root() ? s.quantity->measure(m, e_, s.target) : std::nan("");
}

}  // namespace rockdem
