#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "framework/model/contact.hpp"
#include "framework/core/error.hpp"

namespace rockdem {

int ContactStore::model_for(int group_a, int group_b, int edge_label) const {
  const auto groups_match = [&](const JointAssignment& a) {
    const bool direct = (a.group_a < 0 || a.group_a == group_a) && (a.group_b < 0 || a.group_b == group_b);
    const bool swapped = (a.group_a < 0 || a.group_a == group_b) && (a.group_b < 0 || a.group_b == group_a);
    return direct || swapped;
  };
  if (edge_label >= 0)
    for (const auto& a : assignments)
      if (std::find(a.labels.begin(), a.labels.end(), edge_label) != a.labels.end() && groups_match(a)) return a.model;
  for (const auto& a : assignments)
    if (a.labels.empty() && groups_match(a)) return a.model;
  auto name = [&](int g) {
    return g >= 0 && g < static_cast<int>(group_names.size()) ? "'" + group_names[static_cast<std::size_t>(g)] + "'"
                                                              : std::to_string(g);
  };
  throw InputError("blocks of groups " + name(group_a) + " and " + name(group_b) +
                   " came into contact, but no joint model is assigned between them; add a [[joints]] entry with "
                   "between = [" + name(group_a) + ", " + name(group_b) + "] (or \"*\" for any group)");
}

std::size_t ContactStore::state_stride() const {
  std::size_t most = 1;
  for (const auto& jm : models) most = std::max(most, jm->state_size());
  constexpr std::size_t a = ContactStates::kStateAlign;
  return (most + a - 1) / a * a;
}

std::size_t ContactStore::merge(std::vector<Contact>&& found) {
  std::size_t created = 0;
  ContactStates& next = spare_states_;
  next.reset(state_stride(), found.size());
  // Within both lists' strides (a stage's models may differ from the last's, not their states).
  const std::size_t kept_bytes = std::min(next.stride(), states.stride());
  // Which old contact each found one continues: the one with its key and joint model; else, for a
  // corner, the one of its other side against the same block that nothing continues any more, if
  // it acts along the same plane. A corner's key names the own edge that faces the other block
  // best, and as the block turns or slides that can pass to the other edge with the point where
  // it was; starting that contact afresh dropped the stress it carried (3,950 J/m of the drift
  // study's first earthquake, 3.7 % of its boundary work) and the joint's slip and wear with it.
  continues_.assign(found.size(), -1);
  claimed_.assign(items.size(), 0);
  constexpr std::ptrdiff_t kOtherModel = -2;  // its key goes on, under another joint model
  for (std::size_t i = 0; i < found.size(); ++i) {
    const std::ptrdiff_t at = index_.find(items, found[i].key);
    if (at < 0) continue;
    claimed_[static_cast<std::size_t>(at)] = 1;
    continues_[i] = items[static_cast<std::size_t>(at)].joint == found[i].joint ? at : kOtherModel;
  }
  for (std::size_t i = 0; i < found.size(); ++i) {
    Contact& c = found[i];
    if (continues_[i] != -1) continue;
    ContactKey other_side = c.key;
    other_side.side = 1 - other_side.side;
    const std::ptrdiff_t at = index_.find(items, other_side);
    if (at < 0 || claimed_[static_cast<std::size_t>(at)]) continue;
    const Contact& old = items[static_cast<std::size_t>(at)];
    if (old.joint != c.joint || old.normal.dot(c.normal) <= kSamePlaneCos) continue;
    claimed_[static_cast<std::size_t>(at)] = 1;
    continues_[i] = at;
    c.pretouch_gap = old.pretouch_gap;
    c.pending_closure = old.pending_closure;
  }
  for (std::size_t i = 0; i < found.size(); ++i) {
    Contact& c = found[i];
    if (continues_[i] >= 0) {
      const auto at = static_cast<std::size_t>(continues_[i]);
      std::memcpy(next.at(i), states.at(at), kept_bytes);
      c.response = items[at].response;
      c.fresh = false;
    } else {
      models[static_cast<std::size_t>(c.joint)]->init(next.at(i));
      c.response = JointResponse{};
      c.fresh = true;
      ++created;
    }
  }
  // Swapped, not moved: the caller gets the old list's storage back to fill on its next pass,
  // and the old states' storage is the next merge's.
  items.swap(found);
  states.swap(next);
  index_.rebuild(items);
  return created;
}

void ContactStore::restore(ContactList&& all) {
  if (all.states.size() != all.items.size())
    throw std::logic_error("ContactStore::restore: " + std::to_string(all.items.size()) + " contacts with " +
                           std::to_string(all.states.size()) + " states");
  // Narrower states than the joint models write would be overrun by the next update.
  if (!all.items.empty() && all.states.stride() < state_stride())
    throw std::logic_error("ContactStore::restore: states of " + std::to_string(all.states.stride()) +
                           " bytes, the joint models need " + std::to_string(state_stride()));
  items = std::move(all.items);
  states = std::move(all.states);
  index_.rebuild(items);
}

ContactList ContactStore::take() {
  ContactList out{std::move(items), std::move(states)};
  items.clear();
  states = ContactStates{};
  index_.rebuild(items);
  return out;
}

const Contact* ContactStore::find(const ContactKey& k) const {
  const std::ptrdiff_t at = index_.find(items, k);
  return at < 0 ? nullptr : &items[static_cast<std::size_t>(at)];
}

const Contact* ContactStore::find(const ContactKey& k, std::size_t& hint) const {
  const std::ptrdiff_t at = index_.find(items, k, hint);
  return at < 0 ? nullptr : &items[static_cast<std::size_t>(at)];
}

}  // namespace rockdem
