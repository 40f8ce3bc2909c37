// A case built from specs made in code, without a case file: what a model generator will do.
#include <gtest/gtest.h>

#include "framework/core/error.hpp"
#include "framework/io/case_builder.hpp"

using namespace rockdem;

namespace {

BlockSpec rigid_block(const std::string& name, double x0, double y0, double w, double h) {
  BlockSpec b;
  b.name = name;
  b.rectangle = BlockSpec::Rectangle{x0, y0, w, h};
  b.density = 2500.0;
  b.where = "generator: block " + name;
  return b;
}

// Two rigid blocks, one on the other, a joint between them, the base fixed, one stage.
CaseSpec two_blocks() {
  CaseSpec s;
  s.file = "generator";
  JointSpec j;
  j.name = "joint";
  j.law = "coulomb_slip";
  j.between = {"base", "top"};
  for (const auto& [k, v] : {std::pair{"kn", "10 GPa/m"}, {"ks", "10 GPa/m"}, {"friction", "30 deg"}})
    j.params[k] = RawValue{std::string(v), std::string("generator: joint ") + k};
  s.joints.push_back(j);
  s.blocks.push_back(rigid_block("base", 0.0, -1.0, 4.0, 1.0));
  s.blocks.push_back(rigid_block("top", 1.0, 0.0, 1.0, 1.0));
  BoundarySpec fixed;
  fixed.type = "fixed";
  fixed.block = "base";
  s.boundaries.push_back(fixed);
  StageInput stage;
  stage.stage.name = "settle";
  stage.stage.until = StageSpec::Until::steps;
  stage.stage.steps = 10;
  s.stages.push_back(stage);
  HistoryInput h;
  h.name = "top_y";
  h.quantity = "block_displacement";
  h.block = "top";
  h.component.emplace(1, 'y');  // not = "y": GCC 12 warns falsely (-Wrestrict) on that here
  s.histories.push_back(h);
  return s;
}

std::string error_of(const CaseSpec& s) {
  try {
    build_case(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CaseBuilder, BuildsACaseFromSpecsMadeInCode) {
  const Case c = build_case(two_blocks());
  ASSERT_EQ(c.model.blocks.size(), 2u);
  EXPECT_EQ(c.block_names[1], "top");
  ASSERT_EQ(c.conditions.size(), 1u);
  ASSERT_EQ(c.stages.size(), 1u);
  ASSERT_EQ(c.histories.size(), 1u);
  EXPECT_EQ(c.histories[0].quantity->name, "block_displacement");
  EXPECT_EQ(c.histories[0].unit, "m");  // the quantity's unit when none is given
  EXPECT_EQ(c.histories[0].target.block, 1);
  EXPECT_EQ(c.histories[0].target.component, 1);
  EXPECT_EQ(c.model.contacts.assignments.size(), 1u);
}

TEST(CaseBuilder, MistakesNameTheSpecsPlaceAndWhatIsValid) {
  CaseSpec s = two_blocks();
  s.boundaries[0].type = "glued";
  s.boundaries[0].type_where = "generator: boundary 1";
  EXPECT_EQ(error_of(s), "generator: boundary 1: unknown boundary type 'glued'; valid: fixed, velocity, traction, in_situ, quiet, seismic, free_field");

  s = two_blocks();
  s.histories[0].quantity = "stress";
  s.histories[0].quantity_where = "generator: history 1";
  EXPECT_EQ(error_of(s).rfind("generator: history 1: unknown quantity 'stress'; valid: block_displacement, ", 0), 0u);

  s = two_blocks();
  s.histories[0].component = "z";
  s.histories[0].component_where = "generator: history 1";
  EXPECT_EQ(error_of(s), "generator: history 1: unknown component 'z'; valid: x, y, rotation");
}
