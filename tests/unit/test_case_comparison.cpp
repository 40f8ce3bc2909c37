// What a restart may change in its case (framework/io/case_comparison.hpp): the stages still to
// run and what only they use; anything the completed stages ran with is named when it differs.
#include <gtest/gtest.h>

#include <string>

#include "framework/core/error.hpp"
#include "framework/io/case_comparison.hpp"

using namespace rockdem;

namespace {

const std::string kBase = R"(
title = "t"
[[joints]]
name = "j"
kn = "10 GPa/m"
[[boundary]]
type = "fixed"
block = "base"
[[boundary]]
type = "traction"
block = "top"
stages = ["load"]
[[stages]]
name = "load"
[[stages]]
name = "shear"
duration = "1 s"
)";

std::string with(const std::string& extra) { return kBase + extra; }

}  // namespace

TEST(CaseComparison, StagesStillToRunMayChange) {
  std::string later = kBase;
  later.replace(later.find("\"1 s\""), 5, "\"2 s\"");
  EXPECT_TRUE(restart_differences(kBase, later, 1).empty());
  // ... but not once they have run
  const auto d = restart_differences(kBase, later, 2);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0], "stages[1].duration: '1 s' in the checkpoint's case, '2 s' in this one");
}

TEST(CaseComparison, AChangedStiffnessIsNamed) {
  std::string soft = kBase;
  soft.replace(soft.find("10 GPa/m"), 8, "1 GPa/m");
  const auto d = restart_differences(kBase, soft, 1);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0], "joints[0].kn: '10 GPa/m' in the checkpoint's case, '1 GPa/m' in this one");
}

TEST(CaseComparison, AddedStagesMayBringTheirOwnConditionsAndMotions) {
  // An earthquake added after the static stages: a motion no completed stage played, a base
  // condition active only in the new stage, appended after the others.
  const std::string quake = with(R"(
[[motions]]
name = "elcentro"
file = "x.csv"
[[boundary]]
type = "seismic"
block = "base"
stages = ["event"]
[[stages]]
name = "event"
motion = "elcentro"
)");
  EXPECT_TRUE(restart_differences(kBase, quake, 2).empty());
  // A motion the completed stages played may not change.
  std::string other = quake;
  other.replace(other.find("x.csv"), 5, "y.csv");
  const auto d = restart_differences(quake, other, 3);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d[0].find("motions[0].file"), std::string::npos) << d[0];
}

TEST(CaseComparison, AConditionOfEveryStageMayNotChange) {
  // No `stages`, or an empty list, is every stage: the completed ones used it.
  for (const char* stages : {"", "stages = []\n"}) {
    const std::string a = with(std::string("[[boundary]]\ntype = \"traction\"\nblock = \"side\"\nnormal = \"1 MPa\"\n") + stages);
    std::string b = a;
    b.replace(b.find("1 MPa"), 5, "2 MPa");
    const auto d = restart_differences(a, b, 1);
    ASSERT_EQ(d.size(), 1u) << stages;
    EXPECT_NE(d[0].find("boundary[2].normal"), std::string::npos) << d[0];
  }
}

TEST(CaseComparison, DirectShearTestStagesStillToRunMayBeAdded) {
  const std::string one = with("[direct_shear]\nshear_stages = [\"shear\"]\nnormal_stresses = [\"3 MPa\"]\n");
  const std::string two = with("[direct_shear]\nshear_stages = [\"shear\", \"shear_2\"]\nnormal_stresses = [\"3 MPa\", \"4 MPa\"]\n"
                               "[[stages]]\nname = \"shear_2\"\n");
  EXPECT_TRUE(restart_differences(one, two, 2).empty());
  std::string changed = two;
  changed.replace(changed.find("\"3 MPa\""), 7, "\"5 MPa\"");
  EXPECT_FALSE(restart_differences(one, changed, 2).empty());
}

TEST(CaseComparison, AnUnreadableRecordIsAnInputError) {
  EXPECT_THROW(restart_differences("title = ", kBase, 1), InputError);
}
