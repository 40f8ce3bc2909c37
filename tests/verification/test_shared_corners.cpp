// Blocks that share edges and corners, as a jointed rock mass makes them, through the whole engine
// (case reader, detection, joint law, integration), against closed forms:
//  - two equal-width blocks stacked corner on corner on a fixed base (rigid and deformable), and
//    the same with the upper block shifted by 1e-9 m, 1 mm and 0.5 m: joint closures
//    sigma/kn, normals vertical, no lateral motion (a deformable upper block shifted by 0.5 m
//    overhangs by half its width and bends: its face tilts and it moves sideways, as it should, so
//    that case is rigid only);
//  - a column of ten equal blocks under gravity: the top block settles rho g h N(N+1)/2 / kn;
//  - four blocks meeting at one point, and a T-junction loaded symmetrically: the displacements
//    are mirror-symmetric;
//  - a block dropped flat onto an equal-width block bounces back to its drop height, undamped,
//    without rotating.
// Issue 10's verification items 1, 2, 4 (the drop) and 7; docs/verification.md lists them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "framework/mechanics/block_stress.hpp"
#include "framework/simulation/run_case.hpp"

using namespace rockdem;

namespace {

constexpr double kRho = 2650.0, kG = 9.81, kKn = 10e9, kTop = 5e6;

std::string header(const std::string& title, const std::string& gravity = "-9.81 m/s2") {
  std::ostringstream os;
  os << "title = \"" << title << "\"\n"
     << "[model]\nrounding = \"1 mm\"\ndetection_tolerance = \"1 mm\"\ngravity = [\"0 m/s2\", \"" << gravity << "\"]\n"
     << "[[materials]]\nname = \"rock\"\nmodel = \"elastic\"\ndensity = \"2650 kg/m3\"\nbulk = \"13.33 GPa\"\nshear = \"8 GPa\"\n"
     << "[[joints]]\nname = \"j\"\nlaw = \"coulomb_slip\"\nbetween = [\"*\", \"*\"]\nkn = \"10 GPa/m\"\nks = \"10 GPa/m\"\n"
     << "friction = \"30 deg\"\n";
  return os.str();
}

// A rectangle block: rigid with density, or deformable with nx x ny zones.
std::string block(const std::string& name, double x0, double y0, double w, double h, bool rigid, int nz = 4) {
  std::ostringstream os;
  os.precision(17);
  os << "[[blocks]]\nname = \"" << name << "\"\n";
  if (rigid) os << "type = \"rigid\"\ndensity = \"2650 kg/m3\"\n";
  else os << "type = \"deformable\"\nmaterial = \"rock\"\nzones = [" << nz << ", " << nz << "]\n";
  os << "rectangle = [\"" << x0 << " m\", \"" << y0 << " m\", \"" << w << " m\", \"" << h << " m\"]\n";
  return os.str();
}

std::string settle_stage(double ratio = 1e-9) {
  std::ostringstream os;
  os << "[[stages]]\nname = \"settle\"\ndamping = \"local\"\nuntil = \"equilibrium\"\nratio = " << ratio
     << "\nmax_steps = 400000\n";
  return os.str();
}

Case run(const std::string& text, const std::string& name) {
  Case c = load_case_text(text, name, ".");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_corners_" + name + "_" + std::to_string(::getpid()));
  run_case(c, out, true);
  std::filesystem::remove_all(out);
  return c;
}

Vec2 moved(const Case& c, const std::string& name) {
  const Block& b = c.model.blocks[static_cast<std::size_t>(c.block_index(name, "test"))];
  if (b.rigid) return b.xc - b.xc0;
  Vec2 sum = Vec2::Zero();  // deformable: mean gridpoint displacement
  for (int i = b.first_gp; i < b.first_gp + b.n_gp; ++i) sum += c.model.gp[i].x - c.model.gp[i].x0;
  return sum / b.n_gp;
}

// Length-weighted mean normal stress, largest |normal.x| and total length of the touching contacts
// between two blocks.
struct Joint {
  double sigma = 0.0, max_nx = 0.0, length = 0.0;
  int contacts = 0;
};
Joint joint(const Case& c, const std::string& a, const std::string& b) {
  const BlockId ia = c.model.blocks[static_cast<std::size_t>(c.block_index(a, "test"))].id;
  const BlockId ib = c.model.blocks[static_cast<std::size_t>(c.block_index(b, "test"))].id;
  Joint j;
  for (const Contact& k : c.model.contacts.items) {
    const bool between = (k.key.point_block == ia && k.key.other_block == ib) || (k.key.point_block == ib && k.key.other_block == ia);
    if (!between || k.response.open || k.length <= 0.0) continue;
    j.sigma += k.response.sigma_n * k.length;
    j.length += k.length;
    j.max_nx = std::max(j.max_nx, std::abs(k.normal.x()));
    ++j.contacts;
  }
  if (j.length > 0.0) j.sigma /= j.length;
  return j;
}

// Two 1 m x 1 m blocks stacked on a fixed base, 5 MPa on the upper block's top face, gravity.
std::string stack_case(double shift, bool rigid, bool hold_spin) {
  std::ostringstream os;
  os << header("equal-width stack") << block("base", -1, -1, 3, 1, true) << block("lower", 0, 0, 1, 1, rigid)
     << block("upper", shift, 1, 1, 1, rigid)
     << "[[boundary]]\ntype = \"fixed\"\nblock = \"base\"\n"
     << "[[boundary]]\ntype = \"traction\"\nblock = \"upper\"\nface = \"top\"\nnormal = \"5 MPa\"\n";
  // With the upper block shifted the load is eccentric on its support (at 0.5 m its centre of
  // gravity is right above the lower block's corner, and it tips over): rotation is held so that
  // the joint alone is tested.
  // Deformable blocks have no spin to hold: the upper block's top face is held sideways instead,
  // as a platen would.
  if (hold_spin && rigid)
    for (const char* b : {"lower", "upper"}) os << "[[boundary]]\ntype = \"velocity\"\nblock = \"" << b << "\"\nspin = \"0 rad/s\"\n";
  if (hold_spin && !rigid) os << "[[boundary]]\ntype = \"velocity\"\nblock = \"upper\"\nface = \"top\"\nvx = \"0 m/s\"\n";
  os << settle_stage();
  return os.str();
}

struct StackCase {
  double shift;
  bool rigid, hold_spin;
};

class EqualWidthStack : public ::testing::TestWithParam<StackCase> {};

TEST_P(EqualWidthStack, ClosuresNormalsAndNoLateralMotion) {
  const StackCase p = GetParam();
  Case c = run(stack_case(p.shift, p.rigid, p.hold_spin), "stack");
  const double support = 1.0 - std::abs(p.shift);  // length of the upper joint
  const double upper_sigma = (kTop + kRho * kG * 1.0) / support, lower_sigma = kTop + 2.0 * kRho * kG;
  const Joint up = joint(c, "upper", "lower"), lo = joint(c, "lower", "base");
  // Deformable blocks widen under load (Poisson) by about 1e-4, and their faces tilt by about
  // 1e-6 near the corners where the friction of the joint holds the widening back.
  const double length_tol = p.rigid ? 1e-6 : 2e-4, normal_tol = p.rigid ? 1e-6 : 1e-5;
  EXPECT_NEAR(up.length, support, length_tol * support);
  EXPECT_NEAR(lo.length, 1.0, length_tol);
  EXPECT_LT(up.max_nx, normal_tol);
  EXPECT_LT(lo.max_nx, normal_tol);
  EXPECT_NEAR(up.sigma, upper_sigma, 0.01 * upper_sigma);
  EXPECT_NEAR(lo.sigma, lower_sigma, 0.01 * lower_sigma);
  const Vec2 du = moved(c, "upper"), dl = moved(c, "lower");
  std::cout << "stack shift " << p.shift << (p.rigid ? " rigid" : " deformable") << ": upper joint sigma " << up.sigma
            << " Pa over " << up.length << " m (" << up.contacts << " contacts), lower " << lo.sigma << " Pa; max |nx| "
            << std::max(up.max_nx, lo.max_nx) << "; closures " << (dl.y() - du.y()) * 1e3 << " mm, " << -dl.y() * 1e3
            << " mm; lateral " << du.x() << ", " << dl.x() << " m\n";
  EXPECT_LT(std::abs(du.x()), 1e-6);
  EXPECT_LT(std::abs(dl.x()), 1e-6);
  if (p.rigid) {
    // Joint closures from the block displacements: 0.50260 mm (upper joint at full contact) and
    // 0.50520 mm (lower, on the rigid base), issue 10 item 1.
    EXPECT_NEAR(-dl.y(), lower_sigma / kKn, 0.01 * lower_sigma / kKn);
    EXPECT_NEAR(dl.y() - du.y(), upper_sigma / kKn, 0.01 * upper_sigma / kKn);
  }
  if (p.rigid && !p.hold_spin) {
    // The rigid blocks' mean stresses (block_stress.hpp; what the VTK fields show for them): the
    // top load plus the weight above the centroid, vertical; nothing horizontal, no shear.
    const auto mean = block_mean_stress(c.model);
    const Voigt3 su = mean[static_cast<std::size_t>(c.block_index("upper", "test"))];
    const Voigt3 sl = mean[static_cast<std::size_t>(c.block_index("lower", "test"))];
    const double want_u = kTop + 0.5 * kRho * kG, want_l = kTop + 1.5 * kRho * kG;
    std::cout << "  mean stresses: upper (" << su.transpose() << ") Pa, lower (" << sl.transpose() << ") Pa; closed form syy "
              << -want_u << ", " << -want_l << "\n";
    EXPECT_NEAR(su[1], -want_u, 1e-4 * want_u);
    EXPECT_NEAR(sl[1], -want_l, 1e-4 * want_l);
    for (int k : {0, 2}) {
      EXPECT_LT(std::abs(su[k]), 1e-6 * kTop);
      EXPECT_LT(std::abs(sl[k]), 1e-6 * kTop);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shifts, EqualWidthStack,
                         ::testing::Values(StackCase{0.0, true, false}, StackCase{1e-9, true, false},
                                           StackCase{1e-3, true, true}, StackCase{0.5, true, true},
                                           StackCase{0.0, false, false}, StackCase{1e-9, false, false},
                                           StackCase{1e-3, false, true}),
                         [](const auto& param_info) {
                           const StackCase& p = param_info.param;
                           std::string s = p.shift == 0.0 ? "0" : p.shift == 1e-9 ? "1nm" : p.shift == 1e-3 ? "1mm" : "half_m";
                           return std::string(p.rigid ? "Rigid" : "Deformable") + "Shift" + s;
                         });

// The deformable equal-width stack, at rest, stays at rest undamped (it used to gain kinetic
// energy from a diagonal corner contact).
TEST(SharedCorners, DeformableStackStaysAtRestUndamped) {
  std::string text = stack_case(0.0, false, false);
  text += "[[stages]]\nname = \"free\"\ndamping = \"none\"\nuntil = \"steps\"\nsteps = 20000\n"
          "[[histories]]\nname = \"ke\"\nquantity = \"kinetic_energy\"\n[output]\nhistory_interval = 100\n";
  Case c = load_case_text(text, "stack_free", ".");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_corners_free_" + std::to_string(::getpid()));
  const RunResult r = run_case(c, out, true);
  std::filesystem::remove_all(out);
  const auto stage = r.history.values(r.history.id("stage"));
  const auto ke = r.history.values(r.history.id("ke"));
  double settled = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < ke.size(); ++i) (stage[i] < 2.0 ? settled : worst) = std::max(stage[i] < 2.0 ? settled : worst, ke[i]);
  // Strain energy stored in the stack is about sigma^2 / (2E) per m^2 x 2 m^2 = 1.3 kJ/m; a
  // millionth of it is the bound.
  EXPECT_LT(worst, 1e-3) << "kinetic energy at the end of settling: " << settled;
  EXPECT_GT(ke.size(), 10u);
}

// Ten equal rigid 1 m blocks on a fixed base, gravity only: the top block settles by
// sum_{i=1..N} i rho g h / kn = rho g h N(N+1)/2 / kn = 0.142981 mm (issue 10 item 2).
std::string nth(int i) {  // block name b<i> (a stream: GCC 12 warns falsely on "b" + to_string)
  std::ostringstream o;
  o << 'b' << i;
  return o.str();
}

TEST(SharedCorners, ColumnOfTenBlocksSettles) {
  std::ostringstream os;
  os << header("column of ten") << block("base", -1, -1, 3, 1, true);
  for (int i = 0; i < 10; ++i) os << block(nth(i), 0, i, 1, 1, true);
  os << "[[boundary]]\ntype = \"fixed\"\nblock = \"base\"\n" << settle_stage(1e-10);
  Case c = run(os.str(), "column");
  const double expected = kRho * kG * 1.0 * 10 * 11 / 2 / kKn;
  EXPECT_NEAR(expected, 0.142981e-3, 1e-9);
  std::cout << "column of ten: top block settles " << -moved(c, "b9").y() * 1e3 << " mm (closed form " << expected * 1e3 << " mm)\n";
  EXPECT_NEAR(-moved(c, "b9").y(), expected, 0.01 * expected);
  for (int i = 0; i < 10; ++i) EXPECT_LT(std::abs(moved(c, nth(i)).x()), 1e-6) << i;
}

// Four blocks meeting at one point, loaded from the top on a fixed base: left and right columns
// mirror each other, the joints close by sigma/kn, and the diagonal pairs carry nothing.
TEST(SharedCorners, FourBlocksAtOnePointAreSymmetric) {
  std::ostringstream os;
  os << header("four at a point") << block("base", -2, -1, 4, 1, true) << block("bl", -1, 0, 1, 1, true)
     << block("br", 0, 0, 1, 1, true) << block("tl", -1, 1, 1, 1, true) << block("tr", 0, 1, 1, 1, true)
     << "[[boundary]]\ntype = \"fixed\"\nblock = \"base\"\n";
  for (const char* b : {"tl", "tr"}) os << "[[boundary]]\ntype = \"traction\"\nblock = \"" << b << "\"\nface = \"top\"\nnormal = \"5 MPa\"\n";
  os << settle_stage();
  Case c = run(os.str(), "four");
  const double scale = std::abs(moved(c, "tl").y());
  EXPECT_GT(scale, 0.5e-3);
  for (const auto& [l, r] : {std::pair{"tl", "tr"}, std::pair{"bl", "br"}}) {
    const Vec2 a = moved(c, l), b = moved(c, r);
    EXPECT_NEAR(a.x(), -b.x(), 1e-9 * scale) << l;
    EXPECT_NEAR(a.y(), b.y(), 1e-9 * scale) << l;
    EXPECT_LT(std::abs(a.x()), 1e-6) << l;
  }
  const Joint tl_bl = joint(c, "tl", "bl");
  EXPECT_NEAR(tl_bl.sigma, kTop + kRho * kG, 0.01 * kTop);
  EXPECT_LT(tl_bl.max_nx, 1e-6);
  // The diagonal pairs touch at most along the vertical joint, where nothing presses them together.
  EXPECT_LT(std::abs(joint(c, "tl", "br").sigma), 1.0);
  EXPECT_LT(std::abs(joint(c, "tr", "bl").sigma), 1.0);
}

// A T-junction: one block centred on two, rigid and deformable; mirror symmetry to 1e-9 relative
// (issue 10 item 7). The structured meshes of deformable blocks alternate their diagonals the same
// way in every block, so they are not mirror images of each other and symmetry holds only to the
// mesh's asymmetry there (1e-5 relative, measured 3e-6 sideways and 1.4e-8 vertically).
TEST(SharedCorners, TJunctionIsSymmetric) {
  for (bool rigid : {true, false}) {
    const double tol = rigid ? 1e-9 : 1e-5;
    std::ostringstream os;
    os << header("T junction") << block("base", -2, -1, 4, 1, true) << block("left", -1, 0, 1, 1, rigid)
       << block("right", 0, 0, 1, 1, rigid) << block("top", -1, 1, 2, 1, rigid, 8)
       << "[[boundary]]\ntype = \"fixed\"\nblock = \"base\"\n"
       << "[[boundary]]\ntype = \"traction\"\nblock = \"top\"\nface = \"top\"\nnormal = \"5 MPa\"\n" << settle_stage();
    Case c = run(os.str(), rigid ? "t_rigid" : "t_deformable");
    const double scale = std::abs(moved(c, "top").y());
    EXPECT_GT(scale, 0.5e-3);
    const Vec2 a = moved(c, "left"), b = moved(c, "right");
    EXPECT_NEAR(a.x(), -b.x(), tol * scale) << rigid;
    EXPECT_NEAR(a.y(), b.y(), tol * scale) << rigid;
    EXPECT_LT(std::abs(moved(c, "top").x()), tol * scale) << rigid;
  }
}

// A rigid block dropped flat from 10 mm onto an equal-width block, undamped, elastic joint with a
// high friction: it bounces back to its drop height within 0.5 % without rotating (issue 10
// item 4, first part). The step is a fiftieth of the critical one: the first and last steps of
// the impact switch the contact force on and off within a step, an energy error of up to
// (v dt / max closure)^2; at dt_safety = 0.1 the rebound fell 0.87 % short.
TEST(SharedCorners, BlockDroppedFlatBouncesBackToItsHeight) {
  const double gap = 0.01;
  std::ostringstream os;
  os << header("drop") << "[time]\ndt_safety = 0.02\n" << block("lower", 0, 0, 1, 1, true) << block("upper", 0, 1 + gap, 1, 1, true)
     << "[[boundary]]\ntype = \"fixed\"\nblock = \"lower\"\n"
     << "[[stages]]\nname = \"drop\"\ndamping = \"none\"\nuntil = \"duration\"\nduration = \"0.12 s\"\n"
     << "[[histories]]\nname = \"upper_y\"\nquantity = \"block_displacement\"\nblock = \"upper\"\ncomponent = \"y\"\n"
     << "[[histories]]\nname = \"upper_x\"\nquantity = \"block_displacement\"\nblock = \"upper\"\ncomponent = \"x\"\n"
     << "[output]\nhistory_interval = 1\n";
  Case c = load_case_text(os.str(), "drop", ".");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_corners_drop_" + std::to_string(::getpid()));
  const RunResult r = run_case(c, out, true);
  std::filesystem::remove_all(out);
  const auto t = r.history.times();
  const auto y = r.history.values(r.history.id("upper_y"));
  const auto x = r.history.values(r.history.id("upper_x"));
  // Free fall over 10 mm takes sqrt(2 gap / g) = 45 ms; the flight back up as long again.
  double lowest = 0.0, rebound = -1.0;
  std::size_t i_low = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (y[i] < lowest) { lowest = y[i]; i_low = i; }
  for (std::size_t i = i_low; i < y.size(); ++i) rebound = std::max(rebound, y[i]);
  std::cout << "drop: rebound to " << rebound << " m of the drop height (gap " << gap << " m)\n";
  EXPECT_LT(lowest, -gap);  // it did reach the lower block
  EXPECT_NEAR(rebound, 0.0, 0.005 * gap) << "lowest " << lowest << " at t = " << t[i_low];
  for (double v : x) EXPECT_LT(std::abs(v), 1e-9);
  const Block& up = c.model.blocks[static_cast<std::size_t>(c.block_index("upper", "test"))];
  EXPECT_LT(std::abs(up.theta), 1e-9);
}

}  // namespace
