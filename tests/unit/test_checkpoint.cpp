// Checkpoints: a bit-for-bit round trip of every evolving field (joint and rock state bytes
// included), contacts restored without re-initialising their law state, extra scalars, and
// InputErrors naming the file and the difference for checkpoints of another model.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/io/checkpoint.hpp"
#include "framework/io/hdf5_util.hpp"
#include "io_test_model.hpp"

namespace fs = std::filesystem;
using namespace rockdem;

namespace {

// Number of members of an aggregate, by the largest brace initialisation that compiles: a guard
// that fails when someone adds a field to a state struct without adding it to the checkpoint.
struct AnyField {
  template <class T>
  operator T() const;  // NOLINT: only used in unevaluated contexts
};
template <class T, class... A>
constexpr std::size_t field_count() {
  if constexpr (requires { T{A{}..., AnyField{}}; })
    return field_count<T, A..., AnyField>();
  else
    return sizeof...(A);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec2& a, const Vec2& b) { return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()); }
bool same_bits(const Voigt3& a, const Voigt3& b) {
  return same_bits(a[0], b[0]) && same_bits(a[1], b[1]) && same_bits(a[2], b[2]);
}

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("rockdem_test_ckpt_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string error_of(Model& m, const std::string& path) {
  try {
    read_checkpoint(m, path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

TEST(Checkpoint, StateStructsHaveTheFieldsTheCheckpointKnows) {
  // If one of these fails, a field was added or removed: update framework/io/checkpoint.cpp
  // (write and read), fill_io_test_state and the comparisons below, then the count here.
  EXPECT_EQ((field_count<GridPoint>()), 11u);
  EXPECT_EQ((field_count<Zone>()), 7u);
  // The joint-law state is not one of Contact's fields (the store's ContactStates hold it).
  EXPECT_EQ((field_count<Contact>()), 16u);
  // JointResponse has 11: `consistent` (whether the law's normal stress solve found its fixed
  // point) is not written. Each update sets it afresh and only the element driver reads it, within
  // the increment, so a restarted run's first update recomputes what it needs.
  EXPECT_EQ((field_count<JointResponse>()), 11u);
  EXPECT_EQ((field_count<ContactKey>()), 4u);
}

TEST(Checkpoint, RoundTripIsBitForBit) {
  const fs::path dir = temp_dir("roundtrip");
  const std::string path = (dir / "last_good.h5").string();
  Model a = test::make_io_test_model();
  test::fill_io_test_state(a, 1.0);
  for (auto& c : a.contacts.items) {
    c.pretouch_gap = 1e-5 * (c.point + 0.37);
    c.pending_closure = 1e-6 * (c.point + 0.73);
  }
  write_checkpoint(a, path, {{"stage", 2.0}, {"dt", 1.25e-7}});
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  Model b = test::make_io_test_model();
  test::fill_io_test_state(b, 7.0);  // different state everywhere, same topology
  ContactList fewer = b.contacts.copy();  // and a different contact list
  fewer.items.pop_back();
  fewer.states.reset(fewer.states.stride(), fewer.items.size());
  b.contacts.restore(std::move(fewer));
  const CheckpointScalars extra = read_checkpoint(b, path);
  EXPECT_EQ(extra.size(), 2u);
  EXPECT_EQ(extra.at("stage"), 2.0);
  EXPECT_EQ(extra.at("dt"), 1.25e-7);

  EXPECT_TRUE(same_bits(a.time, b.time));
  EXPECT_EQ(a.step, b.step);
  EXPECT_TRUE(same_bits(a.gravity, b.gravity));
  ASSERT_EQ(a.gp.size(), b.gp.size());
  for (std::size_t i = 0; i < a.gp.size(); ++i) {
    const GridPoint &p = a.gp[i], &q = b.gp[i];
    EXPECT_TRUE(same_bits(p.x0, q.x0)) << i;
    EXPECT_TRUE(same_bits(p.x, q.x)) << i;
    EXPECT_TRUE(same_bits(p.v, q.v)) << i;
    EXPECT_TRUE(same_bits(p.f, q.f)) << i;
    EXPECT_TRUE(same_bits(p.mass, q.mass)) << i;
    EXPECT_TRUE(same_bits(p.stiffness, q.stiffness)) << i;
    EXPECT_EQ(p.block, q.block);
    EXPECT_EQ(p.local, q.local);
    EXPECT_EQ(p.fixed_x, q.fixed_x) << i;
    EXPECT_EQ(p.fixed_y, q.fixed_y) << i;
    EXPECT_EQ(p.prescribed, q.prescribed) << i;
  }
  for (std::size_t i = 0; i < a.zones.size(); ++i) {
    const Zone &p = a.zones[i], &q = b.zones[i];
    EXPECT_EQ(p.n, q.n);
    EXPECT_TRUE(same_bits(p.area, q.area)) << i;
    EXPECT_TRUE(same_bits(p.stress, q.stress)) << i;
    EXPECT_TRUE(same_bits(p.szz, q.szz)) << i;
    EXPECT_TRUE(same_bits(p.strain, q.strain)) << i;
    EXPECT_EQ(p.material, q.material);
    EXPECT_EQ(p.material_state, q.material_state) << i;
  }
  for (std::size_t i = 0; i < a.blocks.size(); ++i) {
    const Block &p = a.blocks[i], &q = b.blocks[i];
    EXPECT_TRUE(same_bits(p.xc, q.xc)) << i;
    EXPECT_TRUE(same_bits(p.xc0, q.xc0)) << i;
    EXPECT_TRUE(same_bits(p.vc, q.vc)) << i;
    EXPECT_TRUE(same_bits(p.fc, q.fc)) << i;
    EXPECT_TRUE(same_bits(p.theta, q.theta)) << i;
    EXPECT_TRUE(same_bits(p.omega, q.omega)) << i;
    EXPECT_TRUE(same_bits(p.moment, q.moment)) << i;
    EXPECT_TRUE(same_bits(p.mass, q.mass)) << i;
    EXPECT_TRUE(same_bits(p.inertia, q.inertia)) << i;
    EXPECT_TRUE(same_bits(p.mass_scale, q.mass_scale)) << i;
    EXPECT_TRUE(same_bits(p.density, q.density)) << i;
    EXPECT_EQ(p.fixed, q.fixed) << i;
    EXPECT_EQ(p.prescribed, q.prescribed) << i;
    ASSERT_EQ(p.rest_offsets.size(), q.rest_offsets.size());
    for (std::size_t k = 0; k < p.rest_offsets.size(); ++k) EXPECT_TRUE(same_bits(p.rest_offsets[k], q.rest_offsets[k]));
  }
  ASSERT_EQ(a.contacts.items.size(), b.contacts.items.size());
  for (std::size_t i = 0; i < a.contacts.items.size(); ++i) {
    const Contact &p = a.contacts.items[i], &q = b.contacts.items[i];
    EXPECT_EQ(p.key, q.key) << i;
    EXPECT_EQ(p.point, q.point) << i;
    EXPECT_EQ(p.other, q.other) << i;
    EXPECT_EQ(p.point_loop, q.point_loop) << i;
    EXPECT_EQ(p.face_mode, q.face_mode) << i;
    EXPECT_EQ(p.edge, q.edge) << i;
    EXPECT_TRUE(same_bits(p.s, q.s)) << i;
    EXPECT_TRUE(same_bits(p.normal, q.normal)) << i;
    EXPECT_TRUE(same_bits(p.length, q.length)) << i;
    EXPECT_TRUE(same_bits(p.span, q.span)) << i;
    EXPECT_TRUE(same_bits(p.overlap, q.overlap)) << i;
    EXPECT_EQ(p.joint, q.joint) << i;
    EXPECT_TRUE(same_bits(p.pretouch_gap, q.pretouch_gap)) << i;
    EXPECT_TRUE(same_bits(p.pending_closure, q.pending_closure)) << i;
    ASSERT_EQ(a.contacts.states.stride(), b.contacts.states.stride());
    EXPECT_EQ(std::memcmp(a.contacts.states.at(i), b.contacts.states.at(i), a.contacts.states.stride()), 0) << i;
    const JointResponse &r = p.response, &s = q.response;
    EXPECT_TRUE(same_bits(r.sigma_n, s.sigma_n) && same_bits(r.tau, s.tau) && same_bits(r.kn, s.kn) &&
                same_bits(r.ks, s.ks) && same_bits(r.u_s, s.u_s) && same_bits(r.u_n, s.u_n) &&
                same_bits(r.dilation, s.dilation) && same_bits(r.dissipated, s.dissipated))
        << i;
    EXPECT_EQ(r.slipping, s.slipping) << i;
    EXPECT_EQ(r.open, s.open) << i;
    EXPECT_EQ(p.fresh, q.fresh) << i;
  }
  // The index was rebuilt: lookups by key find the restored contacts.
  const Contact* c = b.contacts.find(a.contacts.items[2].key);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->point, a.contacts.items[2].point);

  // A later merge with the same keys keeps the restored joint state (not re-initialised).
  std::vector<Contact> again(b.contacts.items);
  b.contacts.merge(std::move(again));
  EXPECT_EQ(std::memcmp(b.contacts.states.at(1), a.contacts.states.at(1), a.contacts.states.stride()), 0);
  fs::remove_all(dir);
}

TEST(Checkpoint, MismatchedModelIsAnInputErrorNamingFileAndDifference) {
  const fs::path dir = temp_dir("mismatch");
  const std::string path = (dir / "ck.h5").string();
  Model a = test::make_io_test_model();
  test::fill_io_test_state(a, 1.0);
  write_checkpoint(a, path);

  {  // one gridpoint more
    Model b = test::make_io_test_model();
    b.gp.push_back(GridPoint{});
    const std::string e = error_of(b, path);
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find("gridpoints"), std::string::npos) << e;
    EXPECT_NE(e.find("9"), std::string::npos) << e;
  }
  {  // a zone fewer
    Model b = test::make_io_test_model();
    b.zones.pop_back();
    const std::string e = error_of(b, path);
    EXPECT_NE(e.find("zones"), std::string::npos) << e;
  }
  {  // a renamed block, and the model is left untouched
    Model b = test::make_io_test_model();
    b.blocks[1].name = "lid";
    const Vec2 x_before = b.gp[5].x;
    const std::string e = error_of(b, path);
    EXPECT_NE(e.find("'lid'"), std::string::npos) << e;
    EXPECT_NE(e.find("'top'"), std::string::npos) << e;
    EXPECT_TRUE(same_bits(b.gp[5].x, x_before));
    EXPECT_EQ(b.time, 0.0);
  }
  {  // different zone connectivity
    Model b = test::make_io_test_model();
    b.zones[1].n = {4, 7, 6};
    const std::string e = error_of(b, path);
    EXPECT_NE(e.find("zone 1"), std::string::npos) << e;
  }
  {  // a different joint-model list
    Model b = test::make_io_test_model();
    b.contacts.model_names = {"other_joint"};
    const std::string e = error_of(b, path);
    EXPECT_NE(e.find("joint models"), std::string::npos) << e;
  }
  {  // not a checkpoint / missing file
    Model b = test::make_io_test_model();
    const std::string txt = (dir / "not.h5").string();
    std::ofstream(txt) << "hello\n";
    EXPECT_NE(error_of(b, txt).find("not an HDF5 file"), std::string::npos);
    EXPECT_NE(error_of(b, (dir / "missing.h5").string()).find("does not exist"), std::string::npos);
  }
  fs::remove_all(dir);
}

// Rewriting a checkpoint replaces it (the last good state is always the latest one written).
TEST(Checkpoint, OverwriteKeepsTheLatestState) {
  const fs::path dir = temp_dir("overwrite");
  const std::string path = (dir / "ck.h5").string();
  Model a = test::make_io_test_model();
  test::fill_io_test_state(a, 1.0);
  write_checkpoint(a, path);
  a.time = 99.5;
  a.step = 9950;
  write_checkpoint(a, path);
  Model b = test::make_io_test_model();
  read_checkpoint(b, path);
  EXPECT_EQ(b.time, 99.5);
  EXPECT_EQ(b.step, 9950);
  fs::remove_all(dir);
}

namespace {
// Replaces /contacts/state of the checkpoint at `path` by the same rows `width` bytes wide: the
// file's own bytes, then zeros (or cut short).
void rewrite_state_width(const std::string& path, std::size_t width) {
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(file.valid());
  h5::Handle grp(H5Gopen2(file, "contacts", H5P_DEFAULT), H5Gclose);
  std::size_t rows = 0, cols = 0;
  std::vector<std::uint8_t> old;
  {
    h5::Handle ds(H5Dopen2(grp, "state", H5P_DEFAULT), H5Dclose);
    const auto shape = h5::dataset_shape(ds);
    rows = static_cast<std::size_t>(shape.first);
    cols = static_cast<std::size_t>(shape.second);
    old.resize(rows * cols);
    ASSERT_GE(H5Dread(ds, H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, old.data()), 0);
  }
  ASSERT_GE(H5Ldelete(grp, "state", H5P_DEFAULT), 0);
  std::vector<std::uint8_t> wide(rows * width, 0);
  for (std::size_t i = 0; i < rows; ++i) std::memcpy(wide.data() + i * width, old.data() + i * cols, std::min(cols, width));
  h5::write_dataset(grp, "state", H5T_NATIVE_UINT8, wide.data(), rows, width, path);
}
}  // namespace

// A contact's joint-law state takes the bytes its joint models need, not the largest any model may
// have: the io test model's Coulomb slip its 80 (Mohr-Coulomb's state), a Continuously-Yielding
// model with directional wear more, and a store keeps the largest of its models'.
TEST(Checkpoint, JointStatesAreAsWideAsTheModelsNeed) {
  Model a = test::make_io_test_model();
  const std::size_t coulomb = a.contacts.models[0]->state_size();
  EXPECT_EQ(coulomb, sizeof(MohrCoulomb::State));
  EXPECT_EQ(a.contacts.states.stride(), (coulomb + 15) / 16 * 16);
  EXPECT_LT(a.contacts.states.stride(), kJointStateBytes);
  const auto q = [](const char* text) { return RawValue{std::string(text), "test"}; };
  std::unique_ptr<JointModel> worn = make_joint_model(
      "continuously_yielding",
      RawValues{{"kn", q("40 GPa/m")}, {"ks", q("15 GPa/m")}, {"initial_friction", q("50 deg")}, {"friction", q("32 deg")},
                {"roughness", q("3 mm")}},
      {EffectSpec{"directional_wear", {}, "test"}}, "test");
  EXPECT_GT(worn->state_size(), coulomb);
  a.contacts.models.push_back(std::shared_ptr<const JointModel>(worn.release()));
  EXPECT_EQ(a.contacts.state_stride(), (a.contacts.models[1]->state_size() + 15) / 16 * 16);
  // The next detection's merge lays the states out at the new stride, each kept.
  test::fill_io_test_state(a, 1.0);
  const ContactList before = a.contacts.copy();
  a.contacts.merge(std::vector<Contact>(a.contacts.items));
  ASSERT_EQ(a.contacts.states.stride(), a.contacts.state_stride());
  for (std::size_t i = 0; i < a.contacts.items.size(); ++i) {
    EXPECT_EQ(std::memcmp(a.contacts.states.at(i), before.states.at(i), before.states.stride()), 0) << i;
    for (std::size_t b = before.states.stride(); b < a.contacts.states.stride(); ++b)
      EXPECT_EQ(a.contacts.states.at(i)[b], std::byte{0}) << i;
  }
  // A list whose states are narrower than the models write is refused as it is.
  ContactList narrow = a.contacts.copy();
  narrow.states.reset(ContactStates::kStateAlign, narrow.items.size());
  EXPECT_THROW(a.contacts.restore(std::move(narrow)), std::logic_error);
  EXPECT_EQ(a.contacts.states.stride(), a.contacts.state_stride());
}

// Checkpoints written while every contact carried 256 bytes of state read back the same; a file
// whose states are narrower than the joint model's is refused, naming the contact.
TEST(Checkpoint, StatesOfAnyWidthTheModelsFitAreRead) {
  const fs::path dir = temp_dir("state_width");
  const std::string path = (dir / "ck.h5").string();
  Model a = test::make_io_test_model();
  test::fill_io_test_state(a, 1.0);
  // Zeros past the model's own bytes, as a contact's state has them.
  const std::size_t own = a.contacts.models[0]->state_size();
  for (std::size_t i = 0; i < a.contacts.items.size(); ++i)
    std::memset(a.contacts.states.at(i) + own, 0, a.contacts.states.stride() - own);
  write_checkpoint(a, path);
  {  // written as wide as the models need, not 256 bytes
    h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    h5::Handle ds(H5Dopen2(file, "contacts/state", H5P_DEFAULT), H5Dclose);
    ASSERT_TRUE(ds.valid());
    EXPECT_EQ(h5::dataset_shape(ds).second, a.contacts.states.stride());
  }
  ASSERT_NO_FATAL_FAILURE(rewrite_state_width(path, kJointStateBytes));
  Model b = test::make_io_test_model();
  read_checkpoint(b, path);
  ASSERT_EQ(b.contacts.states.size(), a.contacts.items.size());
  EXPECT_TRUE(b.contacts.states == a.contacts.states);

  ASSERT_NO_FATAL_FAILURE(rewrite_state_width(path, own - 8));
  Model c = test::make_io_test_model();
  const ContactList untouched = c.contacts.copy();
  const std::string e = error_of(c, path);
  EXPECT_TRUE(c.contacts.states == untouched.states);  // refused before the model is touched
  EXPECT_EQ(c.time, 0.0);
  EXPECT_NE(e.find("contact 0's joint-law state has " + std::to_string(own - 8) + " bytes"), std::string::npos) << e;
  EXPECT_NE(e.find("needs " + std::to_string(own)), std::string::npos) << e;
  fs::remove_all(dir);
}
