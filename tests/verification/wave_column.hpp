#pragma once
// A one-zone-wide elastic column of two deformable blocks (or one, the reference without the
// joint) carrying a plane wave along y at normal incidence on the joint between them; shared by the
// joint-wave benchmarks (test_linear_slip_joint.cpp, test_frictional_joint_wave.cpp).
// P: the sides on rollers (x fixed), so the column is laterally confined and carries
// Cp = sqrt((K + 4G/3)/rho); S: y fixed at every gridpoint (plane shear; the sides then need no
// shear traction). Both ends quiet; the incident wave v0 sin(omega t) enters as the stress
// 2 rho c v0 sin(omega t) on the quiet base: the dashpot takes rho c v and the wave sent up
// carries rho c v, so v = v0 sin(omega t) goes up and the joint's reflection leaves the same way.
#include <sstream>
#include <string>

namespace rockdem::wave_column {

struct Column {
  bool shear = false;        // S wave (else P)
  double f = 100.0;          // Hz
  double c = 5000.0;         // wave speed, m/s (P confined, or S)
  double rho = 2650.0;       // kg/m3
  double v0 = 0.01;          // incident velocity amplitude, m/s
  int zones_per_wave = 40;
  double periods = 16.0;     // duration in periods
  bool joint = true;         // two blocks and a joint, else one block (the reference)
  int nx_upper = 1;          // zones across the upper block (the lower block has one)
  double dt_per_zone = 0.2;  // fixed_dt = this x zone size / c (the same in both runs)
  std::string joint_table;   // [[joints]] between "lower" and "upper"
  std::string extra;         // more tables (e.g. [in_situ])
  std::string comment;       // first lines of the file
};

inline std::string num(double v) {
  std::ostringstream os;
  os.precision(15);
  os << v;
  return os.str();
}

// Wavelength L = c / f, zone size L / zones_per_wave, each block 2 L long, the joint at y = 2 L;
// histories of the displacement along the wave ("below" at y = L, "above" at y = 3 L).
inline std::string column_case(const Column& c) {
  const double L = c.c / c.f, dz = L / c.zones_per_wave, w = dz;
  // Elastic constants with nu = 0.25 (K = 5G/3) whose P (confined) or S speed is exactly c.
  const double M = c.rho * c.c * c.c;  // K + 4G/3 (P) or G (S)
  const double G = c.shear ? M : M / 3.0, K = 5.0 * G / 3.0;
  std::ostringstream os;
  os << c.comment << "title = \"" << (c.shear ? "S" : "P") << " wave across a joint, " << num(c.f) << " Hz\"\n"
     << "[time]\nfixed_dt = \"" << num(c.dt_per_zone * dz / c.c) << " s\"\n"
     << "[model]\nrounding = \"" << num(dz / 100) << " m\"\ndetection_tolerance = \"" << num(dz / 100) << " m\"\n"
     << "[[materials]]\nname = \"rock\"\nmodel = \"elastic\"\ndensity = \"" << num(c.rho) << " kg/m3\"\n"
     << "bulk = \"" << num(K) << " Pa\"\nshear = \"" << num(G) << " Pa\"\n";
  if (c.joint) os << c.joint_table;
  os << c.extra;
  const auto block = [&](const std::string& name, double y0, double h, int nx) {
    os << "[[blocks]]\nname = \"" << name << "\"\ntype = \"deformable\"\nmaterial = \"rock\"\n"
       << "rectangle = [\"0 m\", \"" << num(y0) << " m\", \"" << num(w) << " m\", \"" << num(h) << " m\"]\n"
       << "zones = [" << nx << ", " << static_cast<int>(h / dz + 0.5) << "]\n";
    if (c.shear)
      os << "[[boundary]]\ntype = \"fixed\"\nblock = \"" << name << "\"\ncomponents = [\"y\"]\n";
    else
      for (const char* face : {"left", "right"})
        os << "[[boundary]]\ntype = \"fixed\"\nblock = \"" << name << "\"\nface = \"" << face << "\"\ncomponents = [\"x\"]\n";
  };
  const std::string lower = c.joint ? "lower" : "column", upper = c.joint ? "upper" : "column";
  if (c.joint) {
    block("lower", 0.0, 2 * L, 1);
    block("upper", 2 * L, 2 * L, c.nx_upper);
  } else {
    block("column", 0.0, 4 * L, 1);
  }
  const double amp = 2 * c.rho * c.c * c.v0;  // Pa
  os << "[[boundary]]\ntype = \"quiet\"\nblock = \"" << lower << "\"\nface = \"bottom\"\n"
     << "[[boundary]]\ntype = \"quiet\"\nblock = \"" << upper << "\"\nface = \"top\"\n"
     << "# The incident wave v0 sin(omega t), v0 = " << num(c.v0) << " m/s, as the stress 2 rho c v0 sin(omega t) on the quiet base.\n"
     << "[[boundary]]\ntype = \"traction\"\nblock = \"" << lower << "\"\nface = \"bottom\"\n"
     << (c.shear ? "shear" : "normal") << " = { expression = { value = \"" << num(amp) << " * sin(2 * pi * " << num(c.f)
     << " * t)\", unit = \"Pa\" } }\n"
     << "[[stages]]\nname = \"wave\"\ndamping = \"none\"\nuntil = \"duration\"\nduration = \"" << num(c.periods / c.f) << " s\"\n";
  for (const auto& [name, y] : {std::pair{"below", L}, std::pair{"above", 3 * L}})
    os << "[[histories]]\nname = \"" << name << "\"\nquantity = \"displacement_at\"\nat = [\"" << num(w / 2) << " m\", \""
       << num(y) << " m\"]\ncomponent = \"" << (c.shear ? "x" : "y") << "\"\n";
  os << "[output]\nhistory_interval = 10\n";
  return os.str();
}

}  // namespace rockdem::wave_column
