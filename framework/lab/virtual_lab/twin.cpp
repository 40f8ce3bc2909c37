#include "framework/lab/virtual_lab/twin.hpp"

#include <chrono>
#include <filesystem>

#include <toml++/toml.h>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/io/toml_values.hpp"
#include "rockdem_version.hpp"

namespace rockdem::vlab {

std::vector<Param<TwinSettings>> TwinSettings::spec() {
  using P = TwinSettings;
  constexpr double kDeg = 3.141592653589793 / 180.0;
  return {
      integer("seed", &P::seed, 1, "seed of the profile and of the measurement noise (--seed overrides)").min(0).max(2147483647.0),
      real("top_length", &P::top_length, Dimension::length, "length of the top block's face (the joint length)")
          .positive()
          .def(0.2032),
      real("bottom_length", &P::bottom_length, Dimension::length,
           "length of the bottom block's face (longer than the top: room to shear)")
          .positive()
          .def(0.305),
      real("grid", &P::grid, Dimension::length, "sampling interval of the surfaces").positive().def(0.2e-3),
      real("jrc", &P::jrc, Dimension::dimensionless, "target JRC of the profile, through Z2 (Tse & Cruden 1979)")
          .positive()
          .max(37.9),
      real("hurst", &P::hurst, Dimension::dimensionless, "Hurst exponent of the self-affine profile").positive().max(1.0).def(0.8),
      real("min_wavelength", &P::min_wavelength, Dimension::length, "shortest wavelength of the profile")
          .positive()
          .def(1e-3),
      real("max_wavelength", &P::max_wavelength, Dimension::length, "longest wavelength of the profile")
          .positive()
          .def(0.1),
      real("mismatch_wavelength", &P::mismatch_wavelength, Dimension::length,
           "the walls match at longer wavelengths and have independent phases below (0 = matched)")
          .non_negative()
          .def(0.0),
      real("friction", &P::friction, Dimension::angle, "basic friction angle of the facets").positive().max(80 * kDeg),
      real("contact_stiffness", &P::contact_stiffness, Dimension::stiffness,
           "asperity normal stiffness per unit length of overlap (Winkler foundation)")
          .positive()
          .def(2e12),
      real("shear_stiffness", &P::shear_stiffness, Dimension::stiffness, "elastic shear stiffness of the asperities")
          .positive(),
      real("wall_strength", &P::wall_strength, Dimension::stress,
           "crushing pressure of an asperity contact and hardness in Archard's law (JCS)")
          .positive(),
      real("wear_coefficient", &P::wear_coefficient, Dimension::dimensionless,
           "Archard coefficient on frictional work: volume = k W_f / wall_strength from each surface")
          .non_negative()
          .def(0.0),
      real("max_angle", &P::max_angle, Dimension::angle,
           "largest facet inclination plus friction angle; steeper flanks shear through")
          .positive()
          .max(89 * kDeg)
          .def(75 * kDeg),
      choice("dynamics", &P::dynamics, {"quasi_static", "inertial"}, "quasi_static",
             "quasi_static: equilibrium at every drive increment; inertial: the top block's mass moves "
             "through a compliant frame in time"),
      real("frame_stiffness", &P::frame_stiffness, Dimension::stiffness,
           "loading frame stiffness per unit joint area, in series with the asperities (0 = rigid)")
          .non_negative()
          .def(0.0),
      real("density", &P::density, Dimension::density, "density of the moving block (Table 4-1)").positive().def(2418.8),
      real("moving_height", &P::moving_height, Dimension::length,
           "height of rock whose mass equals the moving mass per unit joint area (block and carriage)")
          .positive()
          .def(0.102),
      real("time_step", &P::time_step, Dimension::time, "time step of the inertial mode").positive().def(5e-5),
      flag("rate_state", &P::rate_state, false, "regularised rate-and-state friction on the facets (inertial only)"),
      real("rs_a", &P::rs_a, Dimension::dimensionless, "rate-and-state direct effect a").positive().def(0.01),
      real("rs_b", &P::rs_b, Dimension::dimensionless, "rate-and-state evolution effect b").non_negative().def(0.015),
      real("rs_dc", &P::rs_dc, Dimension::length, "rate-and-state characteristic slip distance").positive().def(10e-6),
      real("rs_v0", &P::rs_v0, Dimension::velocity, "reference velocity at which friction is tan(friction)")
          .positive()
          .def(4.2e-5),
      real("step", &P::step, Dimension::length, "largest drive increment").positive().def(0.02e-3),
      real("output_interval", &P::output_interval, Dimension::time, "time between recorded rows").positive(),
      real("noise_stress", &P::noise_stress, Dimension::stress, "standard deviation of the shear-stress noise")
          .non_negative()
          .def(0.0),
      real("noise_shear_disp", &P::noise_shear_disp, Dimension::length,
           "standard deviation of the shear-displacement noise")
          .non_negative()
          .def(0.0),
      real("noise_normal_disp", &P::noise_normal_disp, Dimension::length,
           "standard deviation of the normal-displacement noise")
          .non_negative()
          .def(0.0),
  };
}

namespace {

namespace fs = std::filesystem;

}  // namespace

TwinCase read_twin_case(const std::string& file) {
  const toml::table root = parse_toml_file(file, "virtual-lab case file");
  TwinCase c;
  c.file = file;
  for (const auto& [k, node] : root) {
    if (k.str() != "virtual_lab" && k.str() != "stage") {
      throw InputError(toml_where(node, file) + " key " + std::string(k.str()) + ": unknown table or key '" +
                       std::string(k.str()) + "'; a virtual-lab case has [virtual_lab] and [[stage]] tables");
    }
  }
  const auto* vn = root.get("virtual_lab");
  if (!vn || !vn->is_table()) {
    throw InputError(file + ": missing table [virtual_lab] (jrc, friction, shear_stiffness, wall_strength, "
                            "output_interval, ...; see docs/virtual-lab.md)");
  }
  const auto& vt = *vn->as_table();
  const std::string where = toml_where(vt, file) + " [virtual_lab]";
  if (const auto* sp = vt.get("specimen")) {
    if (!sp->is_string()) {
      throw InputError(toml_where(*sp, file) + " key virtual_lab.specimen: specimen must be a string, e.g. \"test09\"");
    }
    c.specimen = sp->as_string()->get();
  }
  if (c.specimen.empty()) c.specimen = fs::path(file).stem().string();
  c.settings = bind_params<TwinSettings>(raw_values(vt, file, "virtual_lab", {"specimen"}), "[virtual_lab]", where);
  const auto& s = c.settings;
  auto key_where = [&](const char* key) {
    const auto* n = vt.get(key);
    return (n ? toml_where(*n, file) : where) + " key virtual_lab." + key;
  };
  if (!(s.bottom_length > s.top_length + 4.0 * s.grid)) {
    throw InputError(key_where("bottom_length") + ": bottom_length must exceed top_length (the top block slides over it)");
  }
  if (s.min_wavelength < 2.0 * s.grid) {
    throw InputError(key_where("min_wavelength") + ": min_wavelength must be at least two grid steps (" +
                     format_quantity(2.0 * s.grid, Dimension::length) + ")");
  }
  if (!(s.max_wavelength > s.min_wavelength)) {
    throw InputError(key_where("max_wavelength") + ": max_wavelength must exceed min_wavelength (" +
                     format_quantity(s.min_wavelength, Dimension::length) + ")");
  }
  if (s.rate_state && s.dynamics != 1) {
    throw InputError(key_where("rate_state") + ": rate_state = true needs dynamics = \"inertial\" (rate effects act "
                                               "through the slip velocity of the moving block)");
  }
  if (s.dynamics == 1 && s.output_interval < s.time_step) {
    throw InputError(key_where("output_interval") + ": output_interval must be at least the time step (" +
                     format_quantity(s.time_step, Dimension::time) + ")");
  }

  int index = 0;
  for (const auto& node : stage_tables(root, file)) {
    ++index;
    const std::string path = "stage[" + std::to_string(index) + "]";
    ElementStage st = read_stage(*node.as_table(), file, path);
    if (st.control != NormalControl::constant_stress) {
      throw InputError(toml_where(*node.as_table(), file) + " [" + path +
                       "]: the virtual lab runs constant normal stress only; remove normal_control or set it to \"stress\"");
    }
    if (!(st.normal_stress > 0.0)) {
      throw InputError(toml_where(*node.as_table(), file) + " [" + path + "]: normal_stress must be > 0 for a shear test");
    }
    if (st.path.kind == ShearPath::Kind::table && !st.path.disp.empty() && std::abs(st.path.disp.front()) > 1e-9) {
      throw InputError(toml_where(*node.as_table(), file) + " [" + path +
                       "]: the drive must start at zero displacement (the mated position)");
    }
    c.stages.push_back(std::move(st));
  }
  return c;
}

ProfileSpec profile_spec(const TwinSettings& s, std::uint64_t seed) {
  ProfileSpec p;
  p.length = s.bottom_length;
  p.grid = s.grid;
  p.hurst = s.hurst;
  p.min_wavelength = s.min_wavelength;
  p.max_wavelength = s.max_wavelength;
  p.jrc = s.jrc;
  p.mismatch_wavelength = s.mismatch_wavelength;
  p.seed = seed;
  return p;
}

BoxParams box_params(const TwinSettings& s) {
  BoxParams b;
  b.friction = s.friction;
  b.contact_stiffness = s.contact_stiffness;
  b.shear_stiffness = s.shear_stiffness;
  b.wall_strength = s.wall_strength;
  b.wear_coefficient = s.wear_coefficient;
  b.max_angle = s.max_angle;
  b.inertial = s.dynamics == 1;
  b.frame_stiffness = s.frame_stiffness;
  b.moving_mass = s.density * s.moving_height;
  b.time_step = s.time_step;
  b.rate_state = s.rate_state;
  b.rs_a = s.rs_a;
  b.rs_b = s.rs_b;
  b.rs_dc = s.rs_dc;
  b.rs_v0 = s.rs_v0;
  b.step = s.step;
  b.output_interval = s.output_interval;
  b.noise_stress = s.noise_stress;
  b.noise_shear_disp = s.noise_shear_disp;
  b.noise_normal_disp = s.noise_normal_disp;
  return b;
}

TwinRun run_twin(const TwinCase& c, std::optional<std::uint64_t> seed) {
  TwinRun r;
  r.seed = seed ? *seed : static_cast<std::uint64_t>(c.settings.seed);
  const auto t0 = std::chrono::steady_clock::now();
  const ProfilePair walls = make_profile_pair(profile_spec(c.settings, r.seed));
  r.profile_jrc = jrc_from_z2(z2(walls.lower, c.settings.grid));
  // The noise stream is seeded apart from the profile's (splitmix64 constant) so that the two
  // random sequences do not overlap.
  ShearBox box(matched_surfaces(walls.lower, walls.upper, c.settings.grid, c.settings.top_length), box_params(c.settings),
               r.seed ^ 0x9E3779B97F4A7C15ULL);
  auto& md = r.record.metadata;
  md = {{"specimen", c.specimen},
        {"joint_length_m", round_trip_text(c.settings.top_length)},
        {"source", "synthetic"},
        // The folder named here is the one the twins in cases/direct_shear/twins/ were made from;
        // kept so that they regenerate byte for byte.
        {"generator", "rockdem virtual-lab (models/virtual_lab: rough profiles, facet friction, wear)"},
        {"note", "synthetic measurement twin made by a physically based model, not a laboratory record"},
        {"rockdem_version", ROCKDEM_VERSION},
        {"case", c.file},
        {"seed", std::to_string(r.seed)},
        {"profile_jrc", round_trip_text(r.profile_jrc)}};
  for (const auto& p : TwinSettings::spec()) {
    if (p.info.name == "seed") continue;
    std::string value;
    std::visit(
        [&](auto m) {
          using M = std::remove_cvref_t<decltype(c.settings.*m)>;
          if constexpr (std::is_same_v<M, double>) {
            const double v = c.settings.*m;
            if (p.info.dim == Dimension::dimensionless) {
              value = round_trip_text(v);
            } else if (p.info.dim == Dimension::angle) {
              value = round_trip_text(v * 180.0 / 3.141592653589793) + " deg";
            } else {
              value = round_trip_text(v) + " " + std::string(si_unit(p.info.dim));
            }
          } else if constexpr (std::is_same_v<M, bool>) {
            value = c.settings.*m ? "true" : "false";
          } else {
            value = p.info.kind == "choice" ? p.info.choices[static_cast<std::size_t>(c.settings.*m)]
                                            : std::to_string(c.settings.*m);
          }
        },
        p.member);
    md.emplace_back("vl_" + p.info.name, value);
  }
  box.run(c.stages, r.record, 1);
  r.steps = box.steps();
  r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace rockdem::vlab
