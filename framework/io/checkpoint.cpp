#include "framework/io/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/io/hdf5_util.hpp"
#include "framework/model/model.hpp"
#include "framework/model/state_fields.hpp"

namespace rockdem {

namespace {

constexpr std::int32_t kVersion = 1;
constexpr const char* kFormat = "rockdem-checkpoint";
using u8 = std::uint8_t;
using i32 = std::int32_t;
using i64 = std::int64_t;

// Reads datasets of one group, checking their shapes against what the model expects.
class GroupReader {
 public:
  GroupReader(hid_t file, const std::string& group, const std::string& path)
      : group_(h5::open_group(file, group, path)), name_(group), path_(path) {}

  template <class T>
  std::vector<T> get(const std::string& name, hsize_t rows, hsize_t cols = 1) const {
    const std::string where = "checkpoint '" + path_ + "': dataset /" + name_ + "/" + name;
    h5::Handle ds(H5Dopen2(group_, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) throw InputError(where + " is missing");
    const auto shape = h5::dataset_shape(ds);
    // A zero-row dataset written as 1-D or 2-D reads back the same way.
    if (shape.first != rows || (rows > 0 && shape.second != cols))
      throw InputError(where + " has shape " + std::to_string(shape.first) + "x" + std::to_string(shape.second) +
                       ", expected " + std::to_string(rows) + "x" + std::to_string(cols));
    std::vector<T> v(rows * cols);
    if (!v.empty() && H5Dread(ds, h5::native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      throw InputError(where + " cannot be read");
    return v;
  }
  hid_t id() const { return group_; }

 private:
  h5::Handle group_;
  std::string name_, path_;
};

Vec2 vec2_at(const std::vector<double>& v, std::size_t i) { return {v[2 * i], v[2 * i + 1]}; }
Voigt3 voigt_at(const std::vector<double>& v, std::size_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }

std::string str(std::size_t n) { return std::to_string(n); }

herr_t collect_attr_name(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

using fields::Field;
using fields::Role;

hid_t hdf5_type(fields::Scalar s) {
  switch (s) {
    case fields::Scalar::f64: return h5::native_type<double>();
    case fields::Scalar::i64: return h5::native_type<i64>();
    case fields::Scalar::i32: return h5::native_type<i32>();
    case fields::Scalar::u8: return h5::native_type<u8>();
  }
  throw std::logic_error("checkpoint: unknown field type");
}

// Root attributes, one per field of the Model's scalars: each is one value of at most 8 bytes.
using ScalarBuffer = std::array<std::byte, 8>;
static_assert(std::ranges::all_of(fields::kModelFields, [](const Field<Model>& fd) {
  return fd.width == 1 && fd.bytes() <= ScalarBuffer{}.size();
}));

void write_model_fields(hid_t file, const Model& m, const std::string& f) {
  ScalarBuffer value{};
  for (const Field<Model>& fd : fields::kModelFields) {
    fd.get(m, value.data());
    h5::write_attr(file, fd.name, hdf5_type(fd.type), value.data(), f);
  }
}

// One dataset per field, gathered into a flat row-major buffer: one HDF5 write per field keeps the
// file readable field by field in h5py, and the cost is negligible next to a time step.
template <class Item, std::size_t N>
void write_fields(hid_t grp, const Field<Item> (&table)[N], const std::vector<Item>& items, const std::string& f) {
  std::vector<std::byte> buf;
  for (const Field<Item>& fd : table) {
    const std::size_t w = fd.bytes();
    buf.assign(items.size() * w, std::byte{});
    for (std::size_t i = 0; i < items.size(); ++i) fd.get(items[i], buf.data() + i * w);
    h5::write_dataset(grp, fd.name, hdf5_type(fd.type), buf.data(), items.size(), fd.width, f);
  }
}

void write_block_names(hid_t grp, const std::vector<Block>& blocks, const std::string& f) {
  h5::Handle st = h5::vlen_string_type();
  std::vector<const char*> names;
  for (const Block& bl : blocks) names.push_back(bl.name.c_str());
  const hsize_t dims[1] = {blocks.size()};
  h5::Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  h5::Handle ds(h5::check(H5Dcreate2(grp, "name", st, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                          "cannot create /blocks/name in " + f),
                H5Dclose);
  if (!blocks.empty()) h5::check_status(H5Dwrite(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, names.data()), "/blocks/name");
}

// Boundary loops and rest offsets are ragged: flat arrays plus per-block counts.
void write_block_loops(hid_t grp, const std::vector<Block>& blocks, const std::string& f) {
  std::vector<i32> boundary, boundary_count, rest_count;
  std::vector<double> rest;
  for (const Block& bl : blocks) {
    boundary.insert(boundary.end(), bl.boundary.begin(), bl.boundary.end());
    boundary_count.push_back(static_cast<i32>(bl.boundary.size()));
    for (const Vec2& r : bl.rest_offsets) rest.insert(rest.end(), {r.x(), r.y()});
    rest_count.push_back(static_cast<i32>(bl.rest_offsets.size()));
  }
  const hsize_t n = blocks.size();
  h5::write_dataset(grp, "boundary_count", boundary_count, n, 1, f);
  h5::write_dataset(grp, "boundary", boundary, boundary.size(), 1, f);
  h5::write_dataset(grp, "rest_offsets_count", rest_count, n, 1, f);
  h5::write_dataset(grp, "rest_offsets", rest, rest.size() / 2, 2, f);
}

// The joint models' case-file names, one per line: a restore compares them with the model's.
std::string joint_model_names(const ContactStore& store) {
  std::string names;
  for (const auto& s : store.model_names) names += (names.empty() ? "" : "\n") + s;
  return names;
}

void write_contact_store(hid_t grp, const ContactStore& store, const std::string& f) {
  h5::write_attr<double>(grp, "rounding", store.rounding, f);
  h5::write_attr<double>(grp, "tolerance", store.tolerance, f);
  h5::write_attr<i32>(grp, "joint_models", static_cast<i32>(store.models.size()), f);
  h5::write_attr_string(grp, "joint_model_names", joint_model_names(store), f);
  write_fields(grp, fields::kContactFields, store.items, f);
}

}  // namespace

void write_checkpoint(const Model& m, const std::string& path, const CheckpointScalars& extra) {
  const std::string tmp = path + ".tmp";
  {
    h5::QuietErrors quiet;
    h5::Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw InputError("cannot create checkpoint file '" + tmp + "' (does its folder exist?)");
    const std::string& f = path;

    h5::write_attr_string(file, "format", kFormat, f);
    h5::write_attr<i32>(file, "version", kVersion, f);
    write_model_fields(file, m, f);
    write_fields(h5::create_group(file, "gridpoints", f), fields::kGridPointFields, m.gp, f);
    write_fields(h5::create_group(file, "zones", f), fields::kZoneFields, m.zones, f);
    {
      h5::Handle grp = h5::create_group(file, "blocks", f);
      write_block_names(grp, m.blocks, f);
      write_fields(grp, fields::kBlockFields, m.blocks, f);
      write_block_loops(grp, m.blocks, f);
    }
    write_contact_store(h5::create_group(file, "contacts", f), m.contacts, f);
    {
      h5::Handle grp = h5::create_group(file, "extra", f);
      for (const auto& [k, v] : extra) h5::write_attr<double>(grp, k, v, f);
    }
    h5::check_status(H5Fflush(file, H5F_SCOPE_LOCAL), "cannot flush " + tmp);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw InputError("cannot move checkpoint '" + tmp + "' to '" + path + "': " + ec.message());
}

namespace {
CheckpointScalars read_impl(Model& m, const std::string& path) {
  const std::string where = "checkpoint '" + path + "'";
  if (!std::filesystem::exists(path)) throw InputError(where + " does not exist");
  h5::QuietErrors quiet;
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(where + " is not an HDF5 file");
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError("cannot open " + where);

  auto mismatch = [&](const std::string& what) {
    throw InputError(where + " does not match the model: " + what +
                     " (a checkpoint restores only into a model built from the case that wrote it)");
  };

  // Everything is read and checked before the model is touched, so a failed restore leaves the
  // model exactly as it was.
  if (H5Aexists(file, "format") <= 0 || h5::read_attr_string(file, "format", path) != kFormat)
    throw InputError(where + " is not a rockdem checkpoint (no format attribute 'rockdem-checkpoint')");
  const auto version = h5::read_attr<i32>(file, "version", path);
  if (version != kVersion)
    throw InputError(where + " has format version " + std::to_string(version) + "; this rockdem reads version " +
                     std::to_string(kVersion));

  const double time = h5::read_attr<double>(file, "time", path);
  const long step = static_cast<long>(h5::read_attr<i64>(file, "step", path));
  const double thickness = h5::read_attr<double>(file, "thickness", path);
  const Vec2 gravity(h5::read_attr<double>(file, "gravity_x", path), h5::read_attr<double>(file, "gravity_y", path));
  if (thickness != m.thickness)
    mismatch("thickness " + std::to_string(thickness) + " m vs the model's " + std::to_string(m.thickness) + " m");

  // Counts first, for a clear message.
  auto count = [&](const char* group, const char* dataset) {
    GroupReader g(file, group, path);
    h5::Handle ds(H5Dopen2(g.id(), dataset, H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) throw InputError(where + ": dataset /" + std::string(group) + "/" + dataset + " is missing");
    return static_cast<std::size_t>(h5::dataset_shape(ds).first);
  };
  const std::size_t nb = count("blocks", "id"), ng = count("gridpoints", "x"), nz = count("zones", "n"),
                    nc = count("contacts", "key");
  if (nb != m.blocks.size()) mismatch("it has " + str(nb) + " blocks, the model " + str(m.blocks.size()));
  if (ng != m.gp.size()) mismatch("it has " + str(ng) + " gridpoints, the model " + str(m.gp.size()));
  if (nz != m.zones.size()) mismatch("it has " + str(nz) + " zones, the model " + str(m.zones.size()));

  // Blocks: identity and topology must match; the rigid-body state is restored.
  GroupReader bg(file, "blocks", path);
  std::vector<std::string> names(nb);
  {
    h5::Handle ds(H5Dopen2(bg.id(), "name", H5P_DEFAULT), H5Dclose);
    h5::Handle st = h5::vlen_string_type();
    std::vector<char*> raw(nb, nullptr);
    if (!ds.valid() || (nb > 0 && H5Dread(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0))
      throw InputError(where + ": dataset /blocks/name is missing or unreadable");
    for (std::size_t i = 0; i < nb; ++i) {
      names[i] = raw[i] ? raw[i] : "";
      H5free_memory(raw[i]);
    }
  }
  const auto b_id = bg.get<i32>("id", nb), b_group = bg.get<i32>("group", nb), b_first_gp = bg.get<i32>("first_gp", nb),
             b_n_gp = bg.get<i32>("n_gp", nb), b_first_zone = bg.get<i32>("first_zone", nb),
             b_n_zone = bg.get<i32>("n_zone", nb), b_bcount = bg.get<i32>("boundary_count", nb),
             b_rcount = bg.get<i32>("rest_offsets_count", nb);
  const auto b_rigid = bg.get<u8>("rigid", nb), b_fixed = bg.get<u8>("fixed", nb), b_presc = bg.get<u8>("prescribed", nb);
  const auto b_density = bg.get<double>("density", nb), b_mass = bg.get<double>("mass", nb),
             b_inertia = bg.get<double>("inertia", nb), b_theta = bg.get<double>("theta", nb),
             b_omega = bg.get<double>("omega", nb), b_moment = bg.get<double>("moment", nb),
             b_mscale = bg.get<double>("mass_scale", nb);
  const auto b_xc0 = bg.get<double>("xc0", nb, 2), b_xc = bg.get<double>("xc", nb, 2), b_vc = bg.get<double>("vc", nb, 2),
             b_fc = bg.get<double>("fc", nb, 2);
  std::size_t nbound = 0, nrest = 0;
  for (std::size_t i = 0; i < nb; ++i) {
    const Block& b = m.blocks[i];
    const std::string bn = "block " + str(i) + " ('" + b.name + "')";
    if (b_id[i] != b.id) mismatch(bn + " has id " + std::to_string(b_id[i]) + " in the file, " + std::to_string(b.id) + " in the model");
    if (names[i] != b.name) mismatch("block " + str(i) + " is named '" + names[i] + "' in the file, '" + b.name + "' in the model");
    if ((b_rigid[i] != 0) != b.rigid) mismatch(bn + " is " + (b.rigid ? "rigid" : "deformable") + " in the model but not in the file");
    if (b_group[i] != b.group || b_first_gp[i] != b.first_gp || b_n_gp[i] != b.n_gp || b_first_zone[i] != b.first_zone ||
        b_n_zone[i] != b.n_zone || static_cast<std::size_t>(b_bcount[i]) != b.boundary.size())
      mismatch(bn + " has a different group, gridpoint/zone range or boundary loop");
    nbound += static_cast<std::size_t>(b_bcount[i]);
    nrest += static_cast<std::size_t>(b_rcount[i]);
  }
  const auto b_boundary = bg.get<i32>("boundary", nbound);
  const auto b_rest = bg.get<double>("rest_offsets", nrest, 2);
  for (std::size_t i = 0, k = 0; i < nb; ++i)
    for (int gpi : m.blocks[i].boundary)
      if (b_boundary[k++] != gpi) mismatch("the boundary loop of block " + str(i) + " ('" + m.blocks[i].name + "')");

  // Gridpoints: (block, local) ids must match.
  GroupReader gg(file, "gridpoints", path);
  const auto g_block = gg.get<i32>("block", ng), g_local = gg.get<i32>("local", ng);
  for (std::size_t i = 0; i < ng; ++i)
    if (g_block[i] != m.gp[i].block || g_local[i] != m.gp[i].local)
      mismatch("gridpoint " + str(i) + " is (block " + std::to_string(g_block[i]) + ", local " + std::to_string(g_local[i]) +
               ") in the file, (block " + std::to_string(m.gp[i].block) + ", local " + std::to_string(m.gp[i].local) +
               ") in the model");
  const auto g_x0 = gg.get<double>("x0", ng, 2), g_x = gg.get<double>("x", ng, 2), g_v = gg.get<double>("v", ng, 2),
             g_f = gg.get<double>("f", ng, 2), g_mass = gg.get<double>("mass", ng), g_stiff = gg.get<double>("stiffness", ng);
  const auto g_fx = gg.get<u8>("fixed_x", ng), g_fy = gg.get<u8>("fixed_y", ng), g_pr = gg.get<u8>("prescribed", ng);

  // Zones: connectivity and material must match.
  GroupReader zg(file, "zones", path);
  const auto z_n = zg.get<i32>("n", nz, 3), z_mat = zg.get<i32>("material", nz);
  for (std::size_t i = 0; i < nz; ++i) {
    const Zone& z = m.zones[i];
    if (z_n[3 * i] != z.n[0] || z_n[3 * i + 1] != z.n[1] || z_n[3 * i + 2] != z.n[2])
      mismatch("zone " + str(i) + " connects different gridpoints");
    if (z_mat[i] != z.material) mismatch("zone " + str(i) + " has material " + std::to_string(z_mat[i]) + " in the file, " +
                                         std::to_string(z.material) + " in the model");
  }
  constexpr std::size_t zw = sizeof(Zone::material_state);
  const auto z_area = zg.get<double>("area", nz), z_stress = zg.get<double>("stress", nz, 3),
             z_szz = zg.get<double>("szz", nz), z_strain = zg.get<double>("strain", nz, 3);
  const auto z_state = zg.get<u8>("material_state", nz, zw);

  // Contacts: any number; each must refer to existing gridpoints, blocks and joint models.
  GroupReader cg(file, "contacts", path);
  const auto nmodels = h5::read_attr<i32>(cg.id(), "joint_models", path);
  if (static_cast<std::size_t>(nmodels) != m.contacts.models.size())
    mismatch("it has " + std::to_string(nmodels) + " joint models, the model " + str(m.contacts.models.size()));
  {
    std::string names_now;
    for (const auto& s : m.contacts.model_names) names_now += (names_now.empty() ? "" : "\n") + s;
    const std::string names_file = h5::read_attr_string(cg.id(), "joint_model_names", path);
    if (names_file != names_now) mismatch("the joint models are named differently");
  }
  const auto c_key = cg.get<i32>("key", nc, 3), c_point = cg.get<i32>("point", nc), c_other = cg.get<i32>("other", nc),
             c_loop = cg.get<i32>("point_loop", nc),
             c_edge = cg.get<i32>("edge", nc), c_joint = cg.get<i32>("joint", nc);
  const auto c_s = cg.get<double>("s", nc), c_normal = cg.get<double>("normal", nc, 2), c_len = cg.get<double>("length", nc),
             c_overlap = cg.get<double>("overlap", nc), c_gap = cg.get<double>("pretouch_gap", nc),
             c_closure = cg.get<double>("pending_closure", nc), c_sn = cg.get<double>("sigma_n", nc),
             c_tau = cg.get<double>("tau", nc), c_kn = cg.get<double>("kn", nc), c_ks = cg.get<double>("ks", nc),
             c_us = cg.get<double>("u_s", nc), c_un = cg.get<double>("u_n", nc), c_dil = cg.get<double>("dilation", nc),
             c_diss = cg.get<double>("dissipated", nc);
  const auto c_face = cg.get<u8>("face_mode", nc);
  const auto c_fresh = cg.get<u8>("fresh", nc), c_slip = cg.get<u8>("slipping", nc), c_open = cg.get<u8>("open", nc);
  const auto c_state = cg.get<u8>("state", nc, kJointStateBytes);
  std::vector<Contact> contacts(nc);
  for (std::size_t i = 0; i < nc; ++i) {
    Contact& c = contacts[i];
    c.key = {c_key[3 * i], c_key[3 * i + 1], c_key[3 * i + 2]};
    c.point = c_point[i];
    c.other = c_other[i];
    c.point_loop = c_loop[i];
    c.face_mode = c_face[i] != 0;
    c.edge = c_edge[i];
    c.joint = c_joint[i];
    if (c.point < 0 || static_cast<std::size_t>(c.point) >= ng || c.other < 0 || static_cast<std::size_t>(c.other) >= nb ||
        c.joint < 0 || c.joint >= nmodels || m.gp[static_cast<std::size_t>(c.point)].block != c.key.point_block ||
        m.gp[static_cast<std::size_t>(c.point)].local != c.key.point_local ||
        m.blocks[static_cast<std::size_t>(c.other)].id != c.key.other_block)
      mismatch("contact " + str(i) + " refers to gridpoints, blocks or joint models the model does not have");
    const auto& ob = m.blocks[static_cast<std::size_t>(c.other)].boundary;
    if (c.edge < 0 || static_cast<std::size_t>(c.edge) >= ob.size()) mismatch("contact " + str(i) + " refers to a missing edge");
    c.s = c_s[i];
    c.normal = vec2_at(c_normal, i);
    c.length = c_len[i];
    c.overlap = c_overlap[i];
    c.pretouch_gap = c_gap[i];
    c.pending_closure = c_closure[i];
    c.fresh = c_fresh[i] != 0;
    std::memcpy(c.state.bytes.data(), c_state.data() + i * kJointStateBytes, kJointStateBytes);
    c.response.sigma_n = c_sn[i];
    c.response.tau = c_tau[i];
    c.response.kn = c_kn[i];
    c.response.ks = c_ks[i];
    c.response.u_s = c_us[i];
    c.response.u_n = c_un[i];
    c.response.dilation = c_dil[i];
    c.response.dissipated = c_diss[i];
    c.response.slipping = c_slip[i] != 0;
    c.response.open = c_open[i] != 0;
  }

  CheckpointScalars extra;
  {
    GroupReader eg(file, "extra", path);
    std::vector<std::string> keys;
    hsize_t idx = 0;
    H5Aiterate2(eg.id(), H5_INDEX_NAME, H5_ITER_INC, &idx, collect_attr_name, &keys);
    for (const auto& k : keys) extra[k] = h5::read_attr<double>(eg.id(), k, path);
  }

  // All checked: apply.
  m.time = time;
  m.step = step;
  m.gravity = gravity;
  for (std::size_t i = 0; i < nb; ++i) {
    Block& b = m.blocks[i];
    b.density = b_density[i];
    b.mass = b_mass[i];
    b.inertia = b_inertia[i];
    b.xc0 = vec2_at(b_xc0, i);
    b.xc = vec2_at(b_xc, i);
    b.vc = vec2_at(b_vc, i);
    b.fc = vec2_at(b_fc, i);
    b.theta = b_theta[i];
    b.omega = b_omega[i];
    b.moment = b_moment[i];
    b.mass_scale = b_mscale[i];
    b.fixed = b_fixed[i] != 0;
    b.prescribed = b_presc[i];
  }
  for (std::size_t i = 0, k = 0; i < nb; ++i) {
    auto& r = m.blocks[i].rest_offsets;
    r.resize(static_cast<std::size_t>(b_rcount[i]));
    for (auto& o : r) o = vec2_at(b_rest, k++);
  }
  for (std::size_t i = 0; i < ng; ++i) {
    GridPoint& g = m.gp[i];
    g.x0 = vec2_at(g_x0, i);
    g.x = vec2_at(g_x, i);
    g.v = vec2_at(g_v, i);
    g.f = vec2_at(g_f, i);
    g.mass = g_mass[i];
    g.stiffness = g_stiff[i];
    g.fixed_x = g_fx[i] != 0;
    g.fixed_y = g_fy[i] != 0;
    g.prescribed = g_pr[i] != 0;
  }
  for (std::size_t i = 0; i < nz; ++i) {
    Zone& z = m.zones[i];
    z.area = z_area[i];
    z.stress = voigt_at(z_stress, i);
    z.szz = z_szz[i];
    z.strain = voigt_at(z_strain, i);
    std::memcpy(z.material_state.data(), z_state.data() + i * zw, zw);
  }
  m.contacts.restore(std::move(contacts));
  return extra;
}
}  // namespace

CheckpointScalars read_checkpoint(Model& m, const std::string& path) {
  try {
    return read_impl(m, path);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {  // low-level HDF5 failures: still name the file
    throw InputError("checkpoint '" + path + "' cannot be read: " + e.what());
  }
}

}  // namespace rockdem
