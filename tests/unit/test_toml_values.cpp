#include <gtest/gtest.h>

#include <toml++/toml.h>

#include "framework/io/toml_values.hpp"

using namespace rockdem;
using namespace std::string_view_literals;

TEST(TomlValues, ScalarsBecomeRawValuesThatRememberFileLineAndKey) {
  const auto root = toml::parse(R"(
[joint.params]
kn = "35.964 GPa/m"
jrc = 7.1
cycles = 3
flag = true
sub = { a = 1 }
)"sv, "case.toml"sv);
  const auto& t = *root["joint"]["params"].as_table();
  const RawValues v = raw_values(t, "cases/x.toml", "joint.params", {"sub"});
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(std::get<std::string>(v.at("kn").value), "35.964 GPa/m");
  EXPECT_EQ(v.at("kn").where, "cases/x.toml:3 key joint.params.kn");
  EXPECT_DOUBLE_EQ(std::get<double>(v.at("jrc").value), 7.1);
  EXPECT_EQ(std::get<std::int64_t>(v.at("cycles").value), 3);
  EXPECT_EQ(std::get<bool>(v.at("flag").value), true);
  EXPECT_EQ(v.at("flag").where, "cases/x.toml:6 key joint.params.flag");
  // Non-scalar values are errors naming the place and what is accepted.
  try {
    raw_values(t, "cases/x.toml", "joint.params");
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cases/x.toml:7 key joint.params.sub"), std::string::npos) << m;
    EXPECT_NE(m.find("a table is not a valid parameter value"), std::string::npos) << m;
  }
  const auto arr = toml::parse("x = [1, 2]\n"sv);
  EXPECT_THROW(raw_value(*arr.get("x"), "f.toml", "x"), InputError);
}
