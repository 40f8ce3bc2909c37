#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "framework/core/params.hpp"

using namespace rockdem;

TEST(Units, ParsesQuantitiesToSI) {
  EXPECT_DOUBLE_EQ(parse_quantity("16.93 GPa/m", Dimension::stiffness), 16.93e9);
  EXPECT_DOUBLE_EQ(parse_quantity("3 MPa", Dimension::stress), 3e6);
  EXPECT_DOUBLE_EQ(parse_quantity("100 mm/s", Dimension::velocity), 0.1);
  EXPECT_NEAR(parse_quantity("38 deg", Dimension::angle), 38 * std::numbers::pi / 180, 1e-15);
  EXPECT_DOUBLE_EQ(parse_quantity("2.5", Dimension::dimensionless), 2.5);
}

TEST(Units, RejectsMissingWrongOrUnknownUnits) {
  EXPECT_THROW(parse_quantity("3", Dimension::stress), InputError);
  EXPECT_THROW(parse_quantity("3 mm", Dimension::stress), InputError);
  EXPECT_THROW(parse_quantity("3 furlongs", Dimension::length), InputError);
  EXPECT_THROW(parse_quantity("abc MPa", Dimension::stress), InputError);
  try {
    parse_quantity("3 mm", Dimension::stress);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("MPa"), std::string::npos) << e.what();
  }
}

namespace {
struct Demo {
  double k;
  double phi;
  int mode;
  static std::vector<Param<Demo>> spec() {
    return {real("k", &Demo::k, Dimension::stiffness, "stiffness").positive(),
            real("phi", &Demo::phi, Dimension::angle, "friction").min(0).max(std::numbers::pi / 2, true).def(0.5),
            choice("mode", &Demo::mode, {"a", "b"}, "a", "a mode")};
  }
};
RawValues vals(std::initializer_list<std::pair<const std::string, RawValue>> l) { return RawValues(l); }
}  // namespace

TEST(Params, BindsValidatesAndNamesTheKey) {
  auto d = bind_params<Demo>(vals({{"k", {std::string("2 GPa/m"), "f.toml:3"}},
                                   {"mode", {std::string("b"), "f.toml:4"}}}),
                             "demo", "f.toml [x]");
  EXPECT_DOUBLE_EQ(d.k, 2e9);
  EXPECT_DOUBLE_EQ(d.phi, 0.5);
  EXPECT_EQ(d.mode, 1);
  // unknown key lists valid ones
  try {
    bind_params<Demo>(vals({{"k", {std::string("2 GPa/m"), "f.toml:3"}}, {"kk", {1.0, "f.toml:5"}}}), "demo", "x");
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("f.toml:5"), std::string::npos);
    EXPECT_NE(m.find("valid parameters: k, phi, mode"), std::string::npos) << m;
  }
  // negative stiffness: range in message
  try {
    bind_params<Demo>(vals({{"k", {std::string("-2 GPa/m"), "f.toml:3"}}}), "demo", "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  // friction >= 90 deg
  EXPECT_THROW(bind_params<Demo>(vals({{"k", {std::string("2 GPa/m"), "a"}}, {"phi", {std::string("90 deg"), "b"}}}),
                                 "demo", "x"),
               InputError);
  // unit-less dimensional value
  EXPECT_THROW(bind_params<Demo>(vals({{"k", {2e9, "a"}}}), "demo", "x"), InputError);
  // missing required
  EXPECT_THROW(bind_params<Demo>(vals({}), "demo", "x"), InputError);
  // bad choice
  EXPECT_THROW(bind_params<Demo>(vals({{"k", {std::string("2 GPa/m"), "a"}}, {"mode", {std::string("c"), "b"}}}),
                                 "demo", "x"),
               InputError);
}
