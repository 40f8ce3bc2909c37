// DEM specimen of a laboratory direct-shear test (see direct_shear_specimen.hpp). The case is built
// as an ordinary case-file table and loaded by the case reader, so it is checked like a hand-written
// case and can be printed for the user to inspect or modify.
#include "framework/lab/direct_shear_specimen.hpp"

#include <algorithm>
#include <filesystem>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"

namespace rockdem {
namespace {

// A quantity as the case reader wants it: a string with its unit, full precision.
std::string q(double v, const char* unit) { return round_trip_text(v) + " " + unit; }

toml::array rectangle(double x0, double y0, double w, double h) {
  return toml::array{q(x0, "m"), q(y0, "m"), q(w, "m"), q(h, "m")};
}

// The loading block's velocity for a stage's shear path.
toml::table path_velocity(const ShearPath& p, double shear_velocity, const std::string& where) {
  switch (p.kind) {
    case ShearPath::Kind::cycles:
      return toml::table{{"cycles", toml::table{{"amplitude", q(p.amplitude, "m")},
                                                {"speed", q(shear_velocity > 0.0 ? shear_velocity : p.velocity, "m/s")},
                                                {"number", p.count},
                                                {"one_sided", p.one_sided}}}};
    case ShearPath::Kind::sinusoid:
      return toml::table{{"sine", toml::table{{"amplitude", q(p.amplitude, "m")},
                                              {"frequency", q(p.frequency, "Hz")},
                                              {"cycles", p.count}}}};
    case ShearPath::Kind::table:
      if (p.source.empty())
        throw InputError(where + ": the DEM specimen follows a drive file only as a whole, starting at time 0 (no "
                                 "file_stage, first time_s = 0); make a drive table (time_s, shear_disp_mm) for it");
      return toml::table{{"file", toml::table{{"path", std::filesystem::absolute(p.source).string()},
                                              {"holds", "displacement"},
                                              {"time_column", "time_s"},
                                              {"value_column", "shear_disp_mm"},
                                              {"time_unit", "s"},
                                              {"value_unit", "mm"}}}};
  }
  return {};
}

// The number of test stages the specimen runs (all, or the first options.stages), each of which
// must hold the normal stress constant.
std::size_t stage_count(const LabTest& test, const DirectShearOptions& options) {
  const std::size_t nstages =
      options.stages > 0 ? std::min<std::size_t>(static_cast<std::size_t>(options.stages), test.stages.size()) : test.stages.size();
  for (std::size_t k = 0; k < nstages; ++k)
    if (test.stages[k].control != NormalControl::constant_stress)
      throw InputError(test.file + ": stage " + std::to_string(k + 1) +
                       " uses constant normal stiffness; the DEM specimen applies a constant normal stress (run it with "
                       "`rockdem element`)");
  return nstages;
}

// Figure 4-7 geometry: 102 mm high blocks, the top one as long as the joint and 51 mm from the
// bottom block's left end, the bottom one 305 mm long (longer if the joint is), loading block
// 20 mm wide against the top block's left face.
struct SpecimenGeometry {
  double L, H, offset, bottom_length, clearance;
};

SpecimenGeometry specimen_geometry(const LabTest& test) {
  const double L = test.joint_length, H = 0.102, offset = 0.051;
  const double bottom_length = std::max(0.305, L + 2.0 * offset);
  // The loading blocks are centred on the top block's mid-height (no moment at the start), their
  // lower edges above the joint by more than it can dilate (the detection distance): a dilating
  // top block rising past a loader's lower edge would let that loader run in under it.
  // 5 mm more than the detection distance keeps the loaders out of the bottom block's reach: a
  // loader corner found at exactly the detection distance from the bottom block was seen to blow
  // up (test 24, Barton-Bandis, at 36 s).
  const double clearance = std::max(0.06 * H, test.dem.detection_tolerance + test.dem.rounding + 0.005);
  return {L, H, offset, bottom_length, clearance};
}

// [[joints]]: the specimen's joint as the test file gives it, and the loaders' interfaces.
toml::array specimen_joints(const LabTest& test) {
  toml::table joint = test.joint_params;
  joint.insert_or_assign("name", "specimen_joint");
  joint.insert_or_assign("law", test.law);
  joint.insert_or_assign("between", toml::array{"bottom", "top"});
  if (!test.effects.empty()) joint.insert_or_assign("effects", test.effects);
  // Frictionless and stiff against the rock, as the report's interface (section 4), but pushing
  // only: a loading block on each side of the top block, driven together, pushes it either way.
  // The report's single block held the top block in tension to pull it back; once a dilating
  // joint lifted the top block's corner past the loader's, that tension tore the corner (seen in
  // test 14 with Mohr-Coulomb dilation). Contacts with the bottom block are frictionless too.
  toml::table interface{{"name", "loading_interface"}, {"law", "coulomb_slip"}, {"between", toml::array{"loaders", "top"}},
                        {"kn", "200000 MPa/m"},        {"ks", "20000 MPa/m"},   {"friction", "0 deg"}};
  // With a large detection distance (a strongly dilating joint) the loading block may be found
  // near the bottom block: a frictionless contact, as the loader against the shear box.
  toml::table loader_bottom{{"name", "loader_bottom"}, {"law", "coulomb_slip"}, {"between", toml::array{"loaders", "bottom"}},
                            {"kn", "200000 MPa/m"},     {"ks", "20000 MPa/m"},    {"friction", "0 deg"}};
  return toml::array{std::move(joint), std::move(interface), std::move(loader_bottom)};
}

// [[blocks]]: the two rock blocks and the two rigid loaders.
toml::array specimen_blocks(const SpecimenGeometry& g, const DemSettings& dem) {
  return toml::array{
      toml::table{{"name", "bottom"}, {"type", "deformable"}, {"material", "rock"},
                  {"rectangle", rectangle(0.0, -g.H, g.bottom_length, g.H)}, {"zone_size", q(dem.zone_size, "m")}},
      toml::table{{"name", "top"}, {"type", "deformable"}, {"material", "rock"},
                  {"rectangle", rectangle(g.offset, 0.0, g.L, g.H)}, {"zone_size", q(dem.zone_size, "m")}},
      toml::table{{"name", "loader"}, {"group", "loaders"}, {"type", "rigid"}, {"density", "2420 kg/m3"},
                  {"rectangle", rectangle(g.offset - 0.02, g.clearance, 0.02, g.H - 2.0 * g.clearance)}},
      toml::table{{"name", "loader_back"}, {"group", "loaders"}, {"type", "rigid"}, {"density", "2420 kg/m3"},
                  {"rectangle", rectangle(g.offset + g.L, g.clearance, 0.02, g.H - 2.0 * g.clearance)}},
  };
}

// Per test stage, a load stage and a shear stage, with the boundary conditions active in them.
struct SpecimenStages {
  toml::array boundary, stages, shear_stages, normal_stresses;
};

SpecimenStages specimen_stages(const LabTest& test, std::size_t nstages, double shear_velocity) {
  SpecimenStages out;
  out.boundary = toml::array{
      toml::table{{"type", "fixed"}, {"block", "bottom"}, {"face", "bottom"}, {"components", toml::array{"y"}}},
      toml::table{{"type", "fixed"}, {"block", "bottom"}, {"face", "left"}, {"components", toml::array{"x"}}},
      toml::table{{"type", "fixed"}, {"block", "bottom"}, {"face", "right"}, {"components", toml::array{"x"}}},
  };
  for (std::size_t k = 0; k < nstages; ++k) {
    const ElementStage& st = test.stages[k];
    const std::string n = std::to_string(k + 1), load = "load_" + n, shear = "shear_" + n;
    out.boundary.push_back(toml::table{{"type", "traction"}, {"block", "top"}, {"face", "top"},
                                       {"normal", q(st.normal_stress, "Pa")}, {"stages", toml::array{load, shear}}});
    for (const char* loader : {"loader", "loader_back"}) {
      out.boundary.push_back(toml::table{{"type", "velocity"}, {"block", loader}, {"vx", "0 m/s"}, {"vy", "0 m/s"},
                                         {"spin", "0 rad/s"}, {"stages", toml::array{load}}});
      out.boundary.push_back(toml::table{{"type", "velocity"}, {"block", loader},
                                         {"vx", path_velocity(st.path, shear_velocity, test.file + " stage " + n)},
                                         {"vy", "0 m/s"}, {"spin", "0 rad/s"}, {"stages", toml::array{shear}}});
    }
    toml::table load_stage{{"name", load}, {"damping", "local"}, {"until", "equilibrium"}, {"ratio", 1e-4}};
    if (!test.stage_params[k].empty()) load_stage.insert("joints", toml::table{{"specimen_joint", test.stage_params[k]}});
    out.stages.push_back(std::move(load_stage));
    out.stages.push_back(toml::table{{"name", shear}, {"damping", "local"}, {"until", "duration"}, {"duration", "auto"}});
    out.shear_stages.push_back(shear);
    out.normal_stresses.push_back(q(st.normal_stress, "Pa"));
  }
  return out;
}

}  // namespace

toml::table direct_shear_case_table(const LabTest& test, const DirectShearOptions& options) {
  if (!test.rock) {
    throw InputError(test.file + ": the DEM specimen needs the rock matrix: add density, bulk and shear to [specimen] "
                                 "(the report's Table 4-1), e.g. density = \"2418.8 kg/m3\", bulk = \"20.96 GPa\", "
                                 "shear = \"14.41 GPa\"");
  }
  const DemSettings& dem = test.dem;
  const double shear_velocity = options.shear_velocity >= 0.0 ? options.shear_velocity : dem.shear_velocity;
  const double mass_scaling_dt = options.mass_scaling_dt >= 0.0 ? options.mass_scaling_dt : dem.mass_scaling_dt;
  const std::size_t nstages = stage_count(test, options);
  const SpecimenGeometry g = specimen_geometry(test);
  toml::table root;
  root.insert("title", (test.title.empty() ? test.specimen : test.title) + " (DEM specimen, Figure 4-7 model)");
  root.insert("model", toml::table{{"rounding", q(dem.rounding, "m")}, {"detection_tolerance", q(dem.detection_tolerance, "m")}});
  toml::table time{{"dt_safety", dem.dt_safety}, {"refresh_interval", 10}};
  if (mass_scaling_dt > 0.0) time.insert("mass_scaling_dt", q(mass_scaling_dt, "s"));
  root.insert("time", std::move(time));
  root.insert("materials", toml::array{toml::table{{"name", "rock"},
                                                   {"model", "elastic"},
                                                   {"density", q(test.rock->density, "kg/m3")},
                                                   {"bulk", q(test.rock->bulk, "Pa")},
                                                   {"shear", q(test.rock->shear, "Pa")}}});
  root.insert("joints", specimen_joints(test));
  root.insert("blocks", specimen_blocks(g, dem));
  SpecimenStages st = specimen_stages(test, nstages, shear_velocity);
  root.insert("boundary", std::move(st.boundary));
  root.insert("stages", std::move(st.stages));
  root.insert("direct_shear", toml::table{{"specimen", test.specimen},
                                          {"joint_length", q(g.L, "m")},
                                          {"loader", "loader"},
                                          {"other_loaders", toml::array{"loader_back"}},
                                          {"top", "top"},
                                          {"bottom", "bottom"},
                                          {"shear_stages", std::move(st.shear_stages)},
                                          {"normal_stresses", std::move(st.normal_stresses)}});
  root.insert("output", toml::table{{"history_interval", dem.history_interval}});
  return root;
}

Case direct_shear_case(const LabTest& test, const DirectShearOptions& options) {
  const toml::table t = direct_shear_case_table(test, options);
  Case c = load_case_table(t, test.file + " (DEM specimen)", std::filesystem::path(test.file).parent_path().string());
  c.direct_shear.metadata = {{"joint_model", test.model->description()}};
  return c;
}

}  // namespace rockdem
