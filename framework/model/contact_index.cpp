#include "framework/model/contact_index.hpp"

#include <algorithm>

#include "framework/model/contact.hpp"

namespace rockdem {

void ContactIndex::rebuild(const std::vector<Contact>& items) {
  // At most half full, so that probe sequences stay short.
  std::size_t size = 16;
  while (size < 2 * items.size()) size *= 2;
  slots_.assign(size, -1);
  const std::size_t mask = size - 1;
  for (std::size_t i = 0; i < items.size(); ++i) {
    std::size_t s = ContactKeyHash{}(items[i].key) & mask;
    while (slots_[s] >= 0) s = (s + 1) & mask;
    slots_[s] = static_cast<std::ptrdiff_t>(i);
  }
  hint_ = 0;
}

std::ptrdiff_t ContactIndex::find(const std::vector<Contact>& items, const ContactKey& k) const { return find(items, k, hint_); }

std::ptrdiff_t ContactIndex::find(const std::vector<Contact>& items, const ContactKey& k, std::size_t& hint) const {
  if (hint < items.size() && items[hint].key == k) return static_cast<std::ptrdiff_t>(hint++);
  if (slots_.empty()) return -1;
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t s = ContactKeyHash{}(k) & mask; slots_[s] >= 0; s = (s + 1) & mask) {
    const auto i = static_cast<std::size_t>(slots_[s]);
    if (i < items.size() && items[i].key == k) {
      hint = i + 1;
      return slots_[s];
    }
  }
  return -1;
}

}  // namespace rockdem
