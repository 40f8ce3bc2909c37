// A contact keeps its joint-law state across a detection when only its key's side changes: a
// corner's key names the own edge that faces the other block best, and that can pass to the
// other edge while the point stays where it was (ContactStore::merge). Before, the contact
// started afresh and the stress it carried vanished: 3,950 J/m of the drift study's first
// earthquake, 3.7 % of its boundary work, went out of the contacts that way.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "tests/unit/io_test_model.hpp"

using namespace rockdem;

namespace {

// The io test model's corner contact (base block corner 2 against the top block, side 1) with a
// law state and response that are not a fresh contact's.
Model loaded_corner() {
  Model m = test::make_io_test_model();
  std::vector<std::byte> state(m.contacts.states.stride());
  for (std::size_t i = 0; i < state.size(); ++i) state[i] = static_cast<std::byte>(i * 7 + 3);
  std::memcpy(m.contacts.states.at(2), state.data(), state.size());
  Contact& c = m.contacts.items[2];
  c.response.sigma_n = 2.5e6;
  c.response.tau = 1.1e6;
  c.fresh = false;
  return m;
}

// The same contacts found again, the corner's with `side` and `normal`.
std::vector<Contact> found_again(const Model& m, int side, Vec2 normal) {
  std::vector<Contact> found(m.contacts.items);
  for (Contact& c : found) c.response = JointResponse{};
  found[2].key.side = side;
  found[2].normal = normal;
  // What detection gives a contact it does not know: pressed in, to be closed on its first update.
  found[2].pending_closure = 3e-4;
  return found;
}

}  // namespace

TEST(ContactContinuity, CornerWhoseKeyPassesToItsOtherSideKeepsItsState) {
  Model m = loaded_corner();
  const std::vector<std::byte> before(m.contacts.states.at(2), m.contacts.states.at(2) + m.contacts.states.stride());
  const std::size_t created = m.contacts.merge(found_again(m, 0, Vec2(0.0, -1.0)));
  EXPECT_EQ(created, 0u);
  const Contact* c = m.contacts.find({BlockId{0}, 2, BlockId{1}, 0});
  ASSERT_NE(c, nullptr);
  EXPECT_FALSE(c->fresh);
  EXPECT_EQ(c->response.sigma_n, 2.5e6);
  EXPECT_EQ(c->response.tau, 1.1e6);
  const auto at = static_cast<std::size_t>(c - m.contacts.items.data());
  EXPECT_EQ(std::memcmp(m.contacts.states.at(at), before.data(), before.size()), 0);
  // The closure is the old contact's (none pending): its state already holds the joint's.
  EXPECT_EQ(c->pending_closure, 0.0);
  EXPECT_EQ(m.contacts.find({BlockId{0}, 2, BlockId{1}, 1}), nullptr);
}

TEST(ContactContinuity, CornerTurnedToAnotherPlaneStartsAfresh) {
  // 45 degrees from the old contact's normal: another plane of the other block, another contact.
  Model m = loaded_corner();
  const double r = 0.5 * std::sqrt(2.0);
  EXPECT_EQ(m.contacts.merge(found_again(m, 0, Vec2(r, -r))), 1u);
  const Contact* c = m.contacts.find({BlockId{0}, 2, BlockId{1}, 0});
  ASSERT_NE(c, nullptr);
  EXPECT_TRUE(c->fresh);
  EXPECT_EQ(c->response.sigma_n, 0.0);
}

TEST(ContactContinuity, CornerWithBothSidesTouchingKeepsTheOldOnOneOnly) {
  // A corner nested in a concave corner: the old side still has its contact, and the other
  // side's new one starts afresh (the state is not copied into two contacts).
  Model m = loaded_corner();
  std::vector<Contact> found = found_again(m, 1, Vec2(0.0, -1.0));
  Contact second = found[2];
  second.key.side = 0;
  // Found before the contact with the old key, so that an order-dependent merge would hand it
  // the state first.
  found.insert(found.begin(), second);
  EXPECT_EQ(m.contacts.merge(std::move(found)), 1u);
  const Contact* kept = m.contacts.find({BlockId{0}, 2, BlockId{1}, 1});
  const Contact* added = m.contacts.find({BlockId{0}, 2, BlockId{1}, 0});
  ASSERT_NE(kept, nullptr);
  ASSERT_NE(added, nullptr);
  EXPECT_FALSE(kept->fresh);
  EXPECT_EQ(kept->response.sigma_n, 2.5e6);
  EXPECT_TRUE(added->fresh);
}

TEST(ContactContinuity, CornerAgainstAnotherJointModelStartsAfresh) {
  // The state of one law is not another's.
  Model m = loaded_corner();
  m.contacts.models.push_back(m.contacts.models[0]);
  std::vector<Contact> found = found_again(m, 0, Vec2(0.0, -1.0));
  found[2].joint = 1;
  EXPECT_EQ(m.contacts.merge(std::move(found)), 1u);
  EXPECT_TRUE(m.contacts.find({BlockId{0}, 2, BlockId{1}, 0})->fresh);
}
