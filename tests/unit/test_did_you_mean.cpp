// The did-you-mean of unknown names (framework/core/did_you_mean.hpp): Levenshtein distances
// against hand-counted values, and the nearest name offered only when it is a likely typo.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "framework/core/did_you_mean.hpp"

using rockdem::did_you_mean;
using rockdem::edit_distance;
using rockdem::nearest_name;

TEST(DidYouMean, EditDistanceCountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("run", ""), 3u);
  EXPECT_EQ(edit_distance("runn", "run"), 1u);            // one deletion
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);      // k->s, e->i, +g
  EXPECT_EQ(edit_distance("--ovewrite", "--overwrite"), 1u);
  EXPECT_EQ(edit_distance("flaw", "lawn"), 2u);
}

TEST(DidYouMean, OffersTheNearestNameOnlyWhenClose) {
  const std::vector<std::string> commands{"calibrate", "compare", "describe", "diagnose", "element", "ground-motion",
                                          "laws", "run", "virtual-lab"};
  EXPECT_EQ(nearest_name("runn", commands), "run");
  EXPECT_EQ(nearest_name("comapre", commands), "compare");
  EXPECT_EQ(nearest_name("blocks", commands), "");  // nothing within a third of the length
  EXPECT_EQ(did_you_mean("law", commands), " (did you mean 'laws'?)");
  EXPECT_EQ(did_you_mean("xyz", commands), "");
  const std::vector<std::string> keys{"rounding", "detection_tolerance", "gravity"};
  EXPECT_EQ(did_you_mean("roundin", keys), " (did you mean 'rounding'?)");
}
