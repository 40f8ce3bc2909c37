// Contact geometry where a block is not convex or a point is pressed deeper than the detection
// tolerance, the two ways the small drift study's second earthquake went wrong (issue 14):
//  - a point in the opening of a C-shaped block (the far field of a drift model is two of them)
//    is as far from it as its nearest face, not the distance to the line through the block's
//    back edge: it used to be taken as metres inside the block and kept as a touching contact;
//  - the same for a square in the notch of an L-shaped block, which pressed into the L's inner
//    face is as deep as it is pressed;
//  - a corner pressed into a face deeper than the tolerance still has a contact length (and so a
//    force): it used to get length 0, carry nothing and sink further. A diamond standing on its
//    tip on a soft joint, whose equilibrium penetration (about 4 mm) is twice the detection
//    distance, comes to rest on it (5.9 mm down) with the reaction equal to its weight.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>
#include <iostream>

#include "framework/contact/detection.hpp"
#include "framework/io/case.hpp"
#include "framework/simulation/run_case.hpp"
#include "polygon_case.hpp"

using namespace rockdem;
using polygon_case::translate;

namespace {

std::string header(const std::string& kn = "10 GPa/m") {
  return "title = \"deep contacts\"\n[model]\nrounding = \"1 mm\"\ndetection_tolerance = \"1 mm\"\n"
         "gravity = [\"0 m/s2\", \"-9.81 m/s2\"]\n"
         "[[joints]]\nname = \"j\"\nlaw = \"coulomb_slip\"\nbetween = [\"*\", \"*\"]\nkn = \"" +
         kn + "\"\nks = \"" + kn + "\"\nfriction = \"30 deg\"\n";
}

std::string square(const std::string& name, double x0, double y0, double w) {
  return polygon_case::rigid_block(name, {{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + w}, {x0, y0 + w}});
}

// Contacts of points of block `a` on block `b` after a detection pass.
std::vector<Contact> contacts_on(Case& c, const std::string& a, const std::string& b) {
  detect_contacts(c.model, c.settings.detection);
  const BlockId ia = polygon_case::block(c, a).id;
  const BlockId ib = polygon_case::block(c, b).id;
  std::vector<Contact> out;
  for (const Contact& k : c.model.contacts.items)
    if (k.key.point_block == ia && k.key.other_block == ib) out.push_back(k);
  return out;
}

// A C-shaped block open to the left, its back edges on the line x = 0 subdivided (flat vertices,
// as a deformable block's gridpoints or a rock-mass cut make them), and a 0.5 m square in the
// opening 0.3 m from that line and 1.2 m from the inner face.
std::vector<Vec2> c_shape() {
  return {{0, -3}, {3, -3}, {3, 3}, {0, 3}, {0, 2.5}, {0, 2}, {2, 2}, {2, -2}, {0, -2}, {0, -2.5}};
}

}  // namespace

TEST(DeepContacts, NoContactAcrossTheOpeningOfAConcaveBlock) {
  Case c = load_case_text(header() + polygon_case::rigid_block("c", c_shape()) + square("inside", 0.3, -0.25, 0.5) + polygon_case::kOneStep, "c_shape", ".");
  const auto found = contacts_on(c, "inside", "c");
  for (const Contact& k : found)
    ADD_FAILURE() << "point " << k.key.point_local << " of the inner square at (" << c.model.gp[k.point].x.transpose()
                  << ") in contact with the C-shaped block, overlap " << k.overlap << " m";
  EXPECT_TRUE(found.empty());
  EXPECT_TRUE(contacts_on(c, "c", "inside").empty());
}

TEST(DeepContacts, NoContactInTheNotchOfAnLShapedBlock) {
  // An L-shaped block whose outer edges are subdivided (flat vertices at (2, 0.5) and (0.5, 2)),
  // and a 0.4 m square in its notch, 0.3 m from its inner faces and 0.3 m from the lines of its
  // outer right and top edges, on the inside of those lines.
  const std::vector<Vec2> l = {{0, 0}, {2, 0}, {2, 0.5}, {2, 1}, {1, 1}, {1, 2}, {0.5, 2}, {0, 2}};
  Case c = load_case_text(header() + polygon_case::rigid_block("l", l) + square("sq", 1.3, 1.3, 0.4) + polygon_case::kOneStep, "l_shape", ".");
  const auto found = contacts_on(c, "sq", "l");
  for (const Contact& k : found)
    ADD_FAILURE() << "point at (" << c.model.gp[k.point].x.transpose() << ") in contact with the L, overlap " << k.overlap << " m";
  EXPECT_TRUE(found.empty());
  EXPECT_TRUE(contacts_on(c, "l", "sq").empty());
  // Pushed into the L's inner vertical face by 5 mm, its points there are 5 mm deep.
  translate(c, "sq", Vec2(-0.305, 0.0));
  int deep = 0;
  for (const Contact& k : contacts_on(c, "sq", "l")) {
    EXPECT_NEAR(k.overlap, 0.005, 1e-9) << "point at (" << c.model.gp[k.point].x.transpose() << ")";
    ++deep;
  }
  EXPECT_EQ(deep, 2);
}

TEST(DeepContacts, CornerPressedDeeperThanTheToleranceKeepsALength) {
  // A diamond whose lower tip is 10 mm into a base (detection distance 2 mm).
  const double d = 0.01;
  Case c = load_case_text(header() + square("base", -1, -2, 2) +
                              polygon_case::rigid_block("diamond", {{0, 0}, {0.5, 0.5}, {0, 1}, {-0.5, 0.5}}) + polygon_case::kOneStep,
                          "diamond", ".");
  translate(c, "diamond", Vec2(0, -d));
  const auto found = contacts_on(c, "diamond", "base");
  ASSERT_FALSE(found.empty());
  double length = 0.0;
  for (const Contact& k : found) {
    EXPECT_NEAR(k.overlap, d, 1e-9);
    length += k.length;
  }
  // The tip's two edges, at 45 degrees, inside the band from the tip to the base's face and the
  // 2 mm tolerance beyond: about 2 (d + 2 mm) = 24 mm; at least the 20 mm the tip is buried over.
  std::cout << "tip 10 mm deep: contact length " << length * 1e3 << " mm\n";
  EXPECT_GT(length, 2.0 * d);
  EXPECT_LT(length, 2.0 * (d + 2.0 * c.settings.detection.distance));
}

TEST(DeepContacts, DiamondOnItsTipComesToRestDeeperThanTheTolerance) {
  // Weight 2650 kg/m3 x 0.5 m2 x 9.81 m/s2 = 13 kN/m on a tip whose contact length grows with its
  // depth d (2 (d + 2 mm)): kn d 2 (d + 2 mm) = W gives d of about 5 mm at kn = 0.2 GPa/m (it
  // comes to rest 5.9 mm lower), more than twice the 2 mm detection distance.
  std::ostringstream os;
  os << header("0.2 GPa/m") << square("base", -1, -2, 2)
     << polygon_case::rigid_block("diamond", {{0, 0}, {0.5, 0.5}, {0, 1}, {-0.5, 0.5}})
     << "[[boundary]]\ntype = \"fixed\"\nblock = \"base\"\n"
     << "[[boundary]]\ntype = \"velocity\"\nblock = \"diamond\"\nspin = \"0 rad/s\"\nvx = \"0 m/s\"\n"
     << "[[stages]]\nname = \"settle\"\ndamping = \"local\"\nuntil = \"equilibrium\"\nratio = 1e-7\nmax_steps = 200000\n";
  Case c = load_case_text(os.str(), "diamond_rest", ".");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_deep_" + std::to_string(::getpid()));
  run_case(c, out, true);
  std::filesystem::remove_all(out);
  const Block& dia = polygon_case::block(c, "diamond");
  const double sink = -(dia.xc - dia.xc0).y();
  const double weight = 2650.0 * 0.5 * 9.81;
  double reaction = 0.0;
  for (const Contact& k : c.model.contacts.items)
    if (!k.response.open) reaction += k.response.sigma_n * k.length * std::abs(k.normal.y());
  std::cout << "diamond on its tip: sinks " << sink * 1e3 << " mm, reaction " << reaction << " N/m of " << weight << "\n";
  EXPECT_GT(sink, c.settings.detection.distance);  // deeper than the band about the point alone
  EXPECT_LT(sink, 0.01);
  EXPECT_NEAR(reaction, weight, 1e-3 * weight);
}
