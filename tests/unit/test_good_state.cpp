// The last good state (ModelSnapshot): it puts back exactly what evolves, and taking it again
// reuses its arrays instead of allocating new ones.
#include <gtest/gtest.h>

#include "framework/boundary/fixed_condition.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "models/rock/elastic.hpp"

using namespace rockdem;

namespace {

// A deformable block falling onto a rigid block that falls freely too: gridpoints, zones,
// rigid-block motion and contacts all change from step to step.
void build(Model& m) {
  m.gravity = Vec2(0.0, -9.81);
  RawValues v;
  v["kn"] = RawValue{std::string("10 GPa/m"), "test"};
  v["ks"] = RawValue{std::string("10 GPa/m"), "test"};
  v["friction"] = RawValue{std::string("30 deg"), "test"};
  m.contacts.models.push_back(make_joint_model("coulomb_slip", v, {}, "test"));
  m.contacts.model_names.push_back("joint");
  m.contacts.assignments.push_back({-1, -1, 0});
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{2500.0, 2e9, 1.5e9}));
  add_rigid_block(m, Polygon{Vec2(-1, -0.5), Vec2(1, -0.5), Vec2(1, 0), Vec2(-1, 0)}, 2500.0, "base", 0);
  add_deformable_block(m, mesh_rectangle(-0.3, 2e-4, 0.6, 0.3, 6, 3), 0, "block", 0);
}

}  // namespace

TEST(GoodState, PutsBackWhatEvolvedAndReusesItsArrays) {
  Model m;
  build(m);
  EngineSettings s;
  s.detection.distance = 2e-3;
  Engine e(m, s);
  e.begin_stage("fall", Damping{});
  for (int i = 0; i < 200; ++i) e.step();
  ASSERT_FALSE(m.contacts.items.empty());
  ModelSnapshot snap;
  snap.take(m);
  const GridPoint* gp_storage = snap.gp.data();
  const Contact* contact_storage = snap.contacts.items.data();
  const Vec2 x = m.gp[5].x, xc = m.blocks[0].xc;
  const Voigt3 stress = m.zones[3].stress;
  const double sigma_n = m.contacts.items[0].response.sigma_n, time = m.time;
  const long step = m.step;
  const std::size_t contacts = m.contacts.items.size();

  for (int i = 0; i < 200; ++i) e.step();
  ASSERT_NE(m.gp[5].x, x);
  ASSERT_NE(m.blocks[0].xc, xc);
  ASSERT_TRUE(snap.put(m));
  EXPECT_EQ(m.gp[5].x, x);
  EXPECT_EQ(m.blocks[0].xc, xc);
  EXPECT_EQ(m.zones[3].stress, stress);
  EXPECT_EQ(m.contacts.items.size(), contacts);
  EXPECT_EQ(m.contacts.items[0].response.sigma_n, sigma_n);
  EXPECT_EQ(m.time, time);
  EXPECT_EQ(m.step, step);
  // The contact index is rebuilt with the list.
  EXPECT_EQ(m.contacts.find(m.contacts.items[contacts - 1].key), &m.contacts.items[contacts - 1]);

  // Taken again at the same size: the same storage, no new arrays.
  snap.take(m);
  EXPECT_EQ(snap.gp.data(), gp_storage);
  EXPECT_EQ(snap.contacts.items.data(), contact_storage);
}

TEST(GoodState, IsNotAppliedToAModelWhoseArraysChanged) {
  Model m;
  build(m);
  ModelSnapshot snap;
  snap.take(m);
  m.blocks.pop_back();
  EXPECT_FALSE(snap.put(m));
}
