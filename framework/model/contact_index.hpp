#pragma once
// The contact store's index from contact key to position in the contact list: open addressing
// with linear probing in one flat array, rebuilt in place after each detection, with a
// sequential hint. Detection finds contacts in nearly the order of the last list (block pairs
// in order, each block's points along its boundary), so most look-ups are answered by the entry
// after the previous hit, without touching the table; the rest cost one probe sequence in a
// flat array instead of a hash-map node. A node-based map rebuilt every pass allocated one node
// per contact and missed the cache on every look-up once the model outgrew it.
#include <cstddef>
#include <vector>

namespace rockdem {

struct Contact;
struct ContactKey;

class ContactIndex {
 public:
  // Index the keys of `items` (positions 0..n-1). Keeps the table's storage.
  void rebuild(const std::vector<Contact>& items);
  // Position of `k` in the list last indexed, or -1.
  std::ptrdiff_t find(const std::vector<Contact>& items, const ContactKey& k) const;
  // The same with the caller's own hint (a thread of a threaded detection scans its own stretch
  // of the list): the answer does not depend on the hint, only how soon it comes.
  std::ptrdiff_t find(const std::vector<Contact>& items, const ContactKey& k, std::size_t& hint) const;

 private:
  std::vector<std::ptrdiff_t> slots_;  // positions in the list, -1 empty; size a power of two
  mutable std::size_t hint_ = 0;       // position after the last hit
};

}  // namespace rockdem
