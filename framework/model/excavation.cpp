#include "framework/model/excavation.hpp"

namespace rockdem {

bool Renumbering::points(std::vector<int>& list) const {
  bool all = true;
  std::vector<int> out;
  out.reserve(list.size());
  for (int g : list) {
    const int n = gp[static_cast<std::size_t>(g)];
    if (n < 0) all = false;
    else out.push_back(n);
  }
  list = std::move(out);
  return all;
}

Renumbering remove_blocks(Model& m, const std::vector<int>& blocks) {
  Renumbering r;
  std::vector<char> gone(m.blocks.size(), 0);
  for (int b : blocks) gone[static_cast<std::size_t>(b)] = 1;
  r.block.assign(m.blocks.size(), -1);
  r.gp.assign(m.gp.size(), -1);
  r.zone.assign(m.zones.size(), -1);
  int nb = 0, ng = 0, nz = 0;
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    if (gone[b]) continue;
    const Block& B = m.blocks[b];
    r.block[b] = nb++;
    for (int i = 0; i < B.n_gp; ++i) r.gp[static_cast<std::size_t>(B.first_gp + i)] = ng++;
    for (int i = 0; i < B.n_zone; ++i) r.zone[static_cast<std::size_t>(B.first_zone + i)] = nz++;
  }
  std::vector<GridPoint> gp(static_cast<std::size_t>(ng));
  for (std::size_t i = 0; i < m.gp.size(); ++i)
    if (r.gp[i] >= 0) {
      GridPoint g = m.gp[i];
      g.block = r.block[static_cast<std::size_t>(g.block)];
      gp[static_cast<std::size_t>(r.gp[i])] = g;
    }
  std::vector<Zone> zones(static_cast<std::size_t>(nz));
  for (std::size_t i = 0; i < m.zones.size(); ++i)
    if (r.zone[i] >= 0) {
      Zone z = m.zones[i];
      for (int& n : z.n) n = r.gp[static_cast<std::size_t>(n)];
      zones[static_cast<std::size_t>(r.zone[i])] = z;
    }
  std::vector<Block> kept;
  kept.reserve(static_cast<std::size_t>(nb));
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    if (gone[b]) continue;
    Block B = std::move(m.blocks[b]);
    if (B.n_gp > 0) B.first_gp = r.gp[static_cast<std::size_t>(B.first_gp)];
    else B.first_gp = ng;
    if (B.n_zone > 0) B.first_zone = r.zone[static_cast<std::size_t>(B.first_zone)];
    else B.first_zone = nz;
    for (int& g : B.boundary) g = r.gp[static_cast<std::size_t>(g)];
    kept.push_back(std::move(B));
  }
  // Contacts with a removed block on either side go; the others point at the new positions.
  ContactList contacts;
  contacts.states.reset(m.contacts.states.stride(), 0);
  for (std::size_t i = 0; i < m.contacts.items.size(); ++i) {
    const Contact& c = m.contacts.items[i];
    const int point = r.gp[static_cast<std::size_t>(c.point)], other = r.block[static_cast<std::size_t>(c.other)];
    if (point < 0 || other < 0) continue;
    Contact n = c;
    n.point = point;
    n.other = other;
    contacts.items.push_back(n);
    contacts.states.push_back(m.contacts.states.at(i));
  }
  m.gp = std::move(gp);
  m.zones = std::move(zones);
  m.blocks = std::move(kept);
  m.contacts.restore(std::move(contacts));
  // A decomposed model keeps each remaining block's owner; ghosts are found again at the next
  // contact detection.
  if (m.part.decomposed()) {
    std::vector<int> owner;
    for (std::size_t b = 0; b < gone.size(); ++b)
      if (!gone[b]) owner.push_back(m.part.owner[b]);
    assign_owners(m, std::move(owner), m.part.rank);
  }
  return r;
}

}  // namespace rockdem
