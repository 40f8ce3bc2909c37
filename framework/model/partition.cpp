#include "framework/model/partition.hpp"

#include "framework/model/model.hpp"

namespace rockdem {
namespace {
// Appends [first, first + n) to `ranges`, merged with the last range when they touch.
void add_range(std::vector<std::array<int, 2>>& ranges, int first, int n) {
  if (n <= 0) return;
  if (!ranges.empty() && ranges.back()[1] == first) ranges.back()[1] += n;
  else ranges.push_back({first, first + n});
}
}  // namespace

void assign_owners(Model& m, std::vector<int> owner, int rank) {
  Partition& p = m.part;
  p = Partition{};
  if (owner.empty()) return;
  p.owner = std::move(owner);
  p.rank = rank;
  p.role.assign(m.blocks.size(), Partition::elsewhere);
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    if (p.owner[b] != rank) continue;
    p.role[b] = Partition::owned;
    p.owned_blocks.push_back(static_cast<int>(b));
    add_range(p.block_ranges, static_cast<int>(b), 1);
    add_range(p.gp_ranges, m.blocks[b].first_gp, m.blocks[b].n_gp);
    add_range(p.zone_ranges, m.blocks[b].first_zone, m.blocks[b].n_zone);
  }
}

}  // namespace rockdem

