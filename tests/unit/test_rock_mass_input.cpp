// Bad input of the rock-mass stage keys (in-situ stress, excavation, regions): each stops while
// the case is read, before running, with a message naming the key and what to change.
#include <gtest/gtest.h>

#include <string>

#include "framework/core/error.hpp"
#include "framework/io/case.hpp"

using namespace rockdem;

namespace {

// Two rigid blocks side by side (density 2650) on a fixed base, gravity, one joint.
std::string base_case(const std::string& extra, const std::string& stages) {
  return "[model]\ngravity = [\"0 m/s2\", \"-9.81 m/s2\"]\n"
         "[[joints]]\nname = \"j\"\nlaw = \"coulomb_slip\"\nbetween = [\"*\", \"*\"]\nkn = \"10 GPa/m\"\nks = \"10 GPa/m\"\n"
         "friction = \"30 deg\"\n"
         "[[blocks]]\nname = \"base\"\ntype = \"rigid\"\ndensity = \"2650 kg/m3\"\nrectangle = [\"0 m\", \"0 m\", \"3 m\", \"1 m\"]\n"
         "[[blocks]]\nname = \"rock\"\ntype = \"rigid\"\ndensity = \"2650 kg/m3\"\nrectangle = [\"0.5 m\", \"1 m\", \"1 m\", \"1 m\"]\n"
         "[[blocks]]\nname = \"plug\"\ngroup = \"opening\"\ntype = \"rigid\"\ndensity = \"2650 kg/m3\"\n"
         "rectangle = [\"1.6 m\", \"1 m\", \"0.8 m\", \"1 m\"]\n" +
         extra + stages;
}

const std::string kStages =
    "[[stages]]\nname = \"initial\"\nuntil = \"steps\"\nsteps = 10\n"
    "[[stages]]\nname = \"dig\"\nexcavate = [\"opening\"]\nuntil = \"steps\"\nsteps = 10\n";

std::string error_of(const std::string& text) {
  try {
    load_case_text(text, "case.toml", ".");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(RockMassInput, FieldDensityOtherThanTheBlocksIsRejected) {
  const std::string e = error_of(base_case("[in_situ]\ndensity = \"2000 kg/m3\"\nK = 0.5\n", kStages));
  EXPECT_NE(e.find("case.toml:27 key 'in_situ.density'"), std::string::npos) << e;
  EXPECT_NE(e.find("gravity would not be balanced"), std::string::npos) << e;
}

TEST(RockMassInput, GradientWithoutGravityIsRejected) {
  std::string text = base_case("[in_situ]\ndensity = \"2650 kg/m3\"\nK = 0.5\n", kStages);
  text.replace(text.find("\"-9.81 m/s2\""), 12, "\"0 m/s2\"");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("in_situ.density"), std::string::npos) << e;
  EXPECT_NE(e.find("no gravity"), std::string::npos) << e;
}

TEST(RockMassInput, SurfaceBelowTheModelIsRejected) {
  const std::string e = error_of(base_case("[in_situ]\nsurface = \"1.5 m\"\nK = 0.5\n", kStages));
  EXPECT_NE(e.find("in_situ.surface"), std::string::npos) << e;
  EXPECT_NE(e.find("below the top of the model (y = 2"), std::string::npos) << e;
}

TEST(RockMassInput, InSituBoundaryWithoutAFieldIsRejected) {
  const std::string e = error_of(base_case("[[boundary]]\ntype = \"in_situ\"\nbox = [\"0 m\", \"0 m\", \"0 m\", \"1 m\"]\n", kStages));
  EXPECT_NE(e.find("[boundary]"), std::string::npos) << e;
  EXPECT_NE(e.find("no [in_situ] table"), std::string::npos) << e;
}

TEST(RockMassInput, ConditionOnAnExcavatedBlockIsRejected) {
  const std::string e = error_of(base_case("[[boundary]]\ntype = \"fixed\"\nblock = \"plug\"\n", kStages));
  EXPECT_NE(e.find("[boundary]"), std::string::npos) << e;
  EXPECT_NE(e.find("block 'plug', which stage 'dig' excavates (stages.dig.excavate)"), std::string::npos) << e;
  // Limited to the stages before the excavation, it is fine.
  EXPECT_EQ(error_of(base_case("[[boundary]]\ntype = \"fixed\"\nblock = \"plug\"\nstages = [\"initial\"]\n", kStages)),
            "(no error)");
}

TEST(RockMassInput, HistoryOfAnExcavatedBlockIsRejected) {
  const std::string e = error_of(base_case("", kStages + "[[histories]]\nname = \"u\"\nquantity = \"block_displacement\"\n"
                                                         "block = \"plug\"\n"));
  EXPECT_NE(e.find("histories.u.block"), std::string::npos) << e;
  EXPECT_NE(e.find("stage 'dig' excavates"), std::string::npos) << e;
}

TEST(RockMassInput, ExcavatingAnUnknownNameIsRejected) {
  std::string stages = kStages;
  stages.replace(stages.find("[\"opening\"]"), 11, "[\"tunnel\"]");
  const std::string e = error_of(base_case("", stages));
  EXPECT_NE(e.find("stages.dig.excavate"), std::string::npos) << e;
  EXPECT_NE(e.find("'tunnel', which is neither a block nor a block group; groups: base, opening, rock"), std::string::npos) << e;
}

TEST(RockMassInput, RegionThatSelectsNothingIsRejected) {
  const std::string e = error_of(base_case("[[boundary]]\ntype = \"fixed\"\nbox = [\"10 m\", \"10 m\", \"11 m\", \"11 m\"]\n", kStages));
  EXPECT_NE(e.find("boundary.box"), std::string::npos) << e;
  EXPECT_NE(e.find("no boundary gridpoint of any block lies in the region"), std::string::npos) << e;
}
