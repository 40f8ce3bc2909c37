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

  // The element type is given at run time (field tables) or as T; the values come back as the
  // file holds them, row-major.
  std::vector<std::byte> get(const std::string& name, hid_t type, std::size_t size, hsize_t rows, hsize_t cols) const {
    const std::string where = "checkpoint '" + path_ + "': dataset /" + name_ + "/" + name;
    h5::Handle ds(H5Dopen2(group_, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) throw InputError(where + " is missing");
    const auto shape = h5::dataset_shape(ds);
    // A zero-row dataset written as 1-D or 2-D reads back the same way.
    if (shape.first != rows || (rows > 0 && shape.second != cols))
      throw InputError(where + " has shape " + std::to_string(shape.first) + "x" + std::to_string(shape.second) +
                       ", expected " + std::to_string(rows) + "x" + std::to_string(cols));
    std::vector<std::byte> v(rows * cols * size);
    if (!v.empty() && H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      throw InputError(where + " cannot be read");
    return v;
  }
  template <class T>
  std::vector<T> get(const std::string& name, hsize_t rows, hsize_t cols = 1) const {
    const std::vector<std::byte> raw = get(name, h5::native_type<T>(), sizeof(T), rows, cols);
    std::vector<T> v(rows * cols);
    if (!raw.empty()) std::memcpy(v.data(), raw.data(), raw.size());
    return v;
  }
  hid_t id() const { return group_; }

 private:
  h5::Handle group_;
  std::string name_, path_;
};

Vec2 vec2_at(const std::vector<double>& v, std::size_t i) { return {v[2 * i], v[2 * i + 1]}; }

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
  std::vector<i32> boundary, boundary_count, rest_count, edge_joint;
  std::vector<double> rest;
  for (const Block& bl : blocks) {
    boundary.insert(boundary.end(), bl.boundary.begin(), bl.boundary.end());
    // Edge labels (rock-mass joint sets) run along the boundary loop; -1 for unlabelled blocks.
    for (std::size_t e = 0; e < bl.boundary.size(); ++e) edge_joint.push_back(bl.edge_label(static_cast<int>(e)));
    boundary_count.push_back(static_cast<i32>(bl.boundary.size()));
    for (const Vec2& r : bl.rest_offsets) rest.insert(rest.end(), {r.x(), r.y()});
    rest_count.push_back(static_cast<i32>(bl.rest_offsets.size()));
  }
  const hsize_t n = blocks.size();
  h5::write_dataset(grp, "boundary_count", boundary_count, n, 1, f);
  h5::write_dataset(grp, "boundary", boundary, boundary.size(), 1, f);
  h5::write_dataset(grp, "edge_joint", edge_joint, edge_joint.size(), 1, f);
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
  // The joint-law states, one row of the store's stride per contact (its model's state first,
  // then zeros); files written before the states were sized by the models have 256 columns.
  // The states are contiguous, in contact order: written as they are.
  const std::byte* rows = store.items.empty() ? nullptr : store.states.at(0);
  h5::write_dataset(grp, "state", h5::native_type<u8>(), rows, store.items.size(), store.states.stride(), f);
}

}  // namespace

void write_checkpoint(const Model& m, const std::string& path, const CheckpointScalars& extra,
                      const CheckpointArrays& arrays, const CheckpointTexts& texts) {
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
    if (!arrays.empty()) {
      h5::Handle grp = h5::create_group(file, "arrays", f);
      for (const auto& [k, v] : arrays) h5::write_dataset(grp, k, v, v.size(), 1, f);
    }
    if (!texts.empty()) {
      h5::Handle grp = h5::create_group(file, "texts", f);
      for (const auto& [k, v] : texts) h5::write_dataset(grp, k, std::vector<std::uint8_t>(v.begin(), v.end()), v.size(), 1, f);
    }
    h5::check_status(H5Fflush(file, H5F_SCOPE_LOCAL), "cannot flush " + tmp);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw InputError("cannot move checkpoint '" + tmp + "' to '" + path + "': " + ec.message());
}

namespace {

// Reads the fields of one role from a group into `items` (sized to the model's count).
template <class Item, std::size_t N>
void read_fields(const GroupReader& g, const Field<Item> (&table)[N], Role role, std::vector<Item>& items) {
  for (const Field<Item>& fd : table) {
    if (fd.role != role) continue;
    const auto buf = g.get(fd.name, hdf5_type(fd.type), fields::size_of(fd.type), items.size(), fd.width);
    for (std::size_t i = 0; i < items.size(); ++i) fd.set(items[i], buf.data() + i * fd.bytes());
  }
}

// Copies the state fields of one item read from the file into the model's item.
template <class Item, std::size_t N>
void restore_state(const Field<Item> (&table)[N], const Item& from, Item& to) {
  std::vector<std::byte> buf;
  for (const Field<Item>& fd : table) {
    if (fd.role != Role::state) continue;
    buf.resize(fd.bytes());
    fd.get(from, buf.data());
    fd.set(to, buf.data());
  }
}

// A restore in steps: everything is read from the file and checked against the model before the
// model is touched (apply()), so a failed restore leaves the model exactly as it was.
class Restore {
 public:
  Restore(Model& m, hid_t file, const std::string& path)
      : m_(m), file_(file), path_(path), where_("checkpoint '" + path + "'") {}

  void check_format() const;
  void read_scalars();
  void read_counts();
  void read_blocks();
  void read_gridpoints();
  void read_zones();
  void read_contacts();
  CheckpointScalars read_extra() const;
  void apply();

 private:
  [[noreturn]] void mismatch(const std::string& what) const {
    throw InputError(where_ + " does not match the model: " + what +
                     " (a checkpoint restores only into a model built from the case that wrote it)");
  }
  std::size_t count(const char* group, const char* dataset) const;
  void read_block_names(const GroupReader& g);
  void check_block(std::size_t i, std::size_t boundary_count) const;
  void read_block_loops(const GroupReader& g, const std::vector<i32>& boundary_count);
  void check_contact(std::size_t i, i32 nmodels) const;

  Model& m_;
  hid_t file_;
  const std::string& path_;
  const std::string where_;
  std::size_t nb_ = 0, ng_ = 0, nz_ = 0, nc_ = 0;
  // What the file holds, in the model's own structs.
  Model scalars_;
  std::vector<Block> blocks_;
  std::vector<GridPoint> gp_;
  std::vector<Zone> zones_;
  std::vector<Contact> contacts_;
  ContactStates states_;
};

void Restore::check_format() const {
  if (H5Aexists(file_, "format") <= 0 || h5::read_attr_string(file_, "format", path_) != kFormat)
    throw InputError(where_ + " is not a rockdem checkpoint (no format attribute 'rockdem-checkpoint')");
  const auto version = h5::read_attr<i32>(file_, "version", path_);
  if (version != kVersion)
    throw InputError(where_ + " has format version " + std::to_string(version) + "; this rockdem reads version " +
                     std::to_string(kVersion));
}

void Restore::read_scalars() {
  ScalarBuffer value{};
  for (const Field<Model>& fd : fields::kModelFields) {
    h5::read_attr(file_, fd.name, hdf5_type(fd.type), value.data(), path_);
    fd.set(scalars_, value.data());
  }
  if (scalars_.thickness != m_.thickness)
    mismatch("thickness " + std::to_string(scalars_.thickness) + " m vs the model's " + std::to_string(m_.thickness) +
             " m");
}

std::size_t Restore::count(const char* group, const char* dataset) const {
  GroupReader g(file_, group, path_);
  h5::Handle ds(H5Dopen2(g.id(), dataset, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw InputError(where_ + ": dataset /" + std::string(group) + "/" + dataset + " is missing");
  return static_cast<std::size_t>(h5::dataset_shape(ds).first);
}

// Counts first, for a clear message.
void Restore::read_counts() {
  nb_ = count("blocks", "id");
  ng_ = count("gridpoints", "x");
  nz_ = count("zones", "n");
  nc_ = count("contacts", "key");
  if (nb_ != m_.blocks.size()) mismatch("it has " + str(nb_) + " blocks, the model " + str(m_.blocks.size()));
  if (ng_ != m_.gp.size()) mismatch("it has " + str(ng_) + " gridpoints, the model " + str(m_.gp.size()));
  if (nz_ != m_.zones.size()) mismatch("it has " + str(nz_) + " zones, the model " + str(m_.zones.size()));
}

void Restore::read_block_names(const GroupReader& g) {
  h5::Handle ds(H5Dopen2(g.id(), "name", H5P_DEFAULT), H5Dclose);
  h5::Handle st = h5::vlen_string_type();
  std::vector<char*> raw(nb_, nullptr);
  if (!ds.valid() || (nb_ > 0 && H5Dread(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0))
    throw InputError(where_ + ": dataset /blocks/name is missing or unreadable");
  for (std::size_t i = 0; i < nb_; ++i) {
    blocks_[i].name = raw[i] ? raw[i] : "";
    H5free_memory(raw[i]);
  }
}

// Blocks: identity and topology must match; the rigid-body state is restored.
void Restore::read_blocks() {
  GroupReader g(file_, "blocks", path_);
  blocks_.assign(nb_, Block{});
  read_block_names(g);
  read_fields(g, fields::kBlockFields, Role::identity, blocks_);
  read_fields(g, fields::kBlockFields, Role::state, blocks_);
  const auto boundary_count = g.get<i32>("boundary_count", nb_);
  read_block_loops(g, boundary_count);
}

void Restore::check_block(std::size_t i, std::size_t boundary_count) const {
  const Block& b = m_.blocks[i];
  const Block& file = blocks_[i];
  const std::string bn = "block " + str(i) + " ('" + b.name + "')";
  if (file.id != b.id)
    mismatch(bn + " has id " + std::to_string(id_value(file.id)) + " in the file, " + std::to_string(id_value(b.id)) + " in the model");
  if (file.name != b.name)
    mismatch("block " + str(i) + " is named '" + file.name + "' in the file, '" + b.name + "' in the model");
  if (file.rigid != b.rigid) mismatch(bn + " is " + (b.rigid ? "rigid" : "deformable") + " in the model but not in the file");
  if (file.group != b.group || file.first_gp != b.first_gp || file.n_gp != b.n_gp || file.first_zone != b.first_zone ||
      file.n_zone != b.n_zone || boundary_count != b.boundary.size())
    mismatch(bn + " has a different group, gridpoint/zone range or boundary loop");
}

// Checks the blocks' identity with their boundary-loop lengths, then reads the loops (which must
// match) and the rest offsets.
void Restore::read_block_loops(const GroupReader& g, const std::vector<i32>& boundary_count) {
  const auto rest_count = g.get<i32>("rest_offsets_count", nb_);
  std::size_t nbound = 0, nrest = 0;
  for (std::size_t i = 0; i < nb_; ++i) {
    check_block(i, static_cast<std::size_t>(boundary_count[i]));
    nbound += static_cast<std::size_t>(boundary_count[i]);
    nrest += static_cast<std::size_t>(rest_count[i]);
  }
  const auto boundary = g.get<i32>("boundary", nbound);
  const auto rest = g.get<double>("rest_offsets", nrest, 2);
  const auto edge_joint = g.get<i32>("edge_joint", nbound);
  for (std::size_t i = 0, k = 0; i < nb_; ++i)
    for (std::size_t e = 0; e < m_.blocks[i].boundary.size(); ++e, ++k) {
      if (boundary[k] != m_.blocks[i].boundary[e])
        mismatch("the boundary loop of block " + str(i) + " ('" + m_.blocks[i].name + "')");
      if (edge_joint[k] != m_.blocks[i].edge_label(static_cast<int>(e)))
        mismatch("the joint-set labels of the edges of block " + str(i) + " ('" + m_.blocks[i].name + "')");
    }
  for (std::size_t i = 0, k = 0; i < nb_; ++i) {
    auto& r = blocks_[i].rest_offsets;
    r.resize(static_cast<std::size_t>(rest_count[i]));
    for (auto& o : r) o = vec2_at(rest, k++);
  }
}

// Gridpoints: (block, local) ids must match.
void Restore::read_gridpoints() {
  GroupReader g(file_, "gridpoints", path_);
  gp_.assign(ng_, GridPoint{});
  read_fields(g, fields::kGridPointFields, Role::identity, gp_);
  for (std::size_t i = 0; i < ng_; ++i)
    if (gp_[i].block != m_.gp[i].block || gp_[i].local != m_.gp[i].local)
      mismatch("gridpoint " + str(i) + " is (block " + std::to_string(gp_[i].block) + ", local " +
               std::to_string(gp_[i].local) + ") in the file, (block " + std::to_string(m_.gp[i].block) + ", local " +
               std::to_string(m_.gp[i].local) + ") in the model");
  read_fields(g, fields::kGridPointFields, Role::state, gp_);
}

// Zones: connectivity and material must match.
void Restore::read_zones() {
  GroupReader g(file_, "zones", path_);
  zones_.assign(nz_, Zone{});
  read_fields(g, fields::kZoneFields, Role::identity, zones_);
  for (std::size_t i = 0; i < nz_; ++i) {
    const Zone& z = m_.zones[i];
    if (zones_[i].n != z.n) mismatch("zone " + str(i) + " connects different gridpoints");
    if (zones_[i].material != z.material)
      mismatch("zone " + str(i) + " has material " + std::to_string(zones_[i].material) + " in the file, " +
               std::to_string(z.material) + " in the model");
  }
  read_fields(g, fields::kZoneFields, Role::state, zones_);
}

// Contacts: any number; each must refer to existing gridpoints, blocks and joint models.
void Restore::read_contacts() {
  GroupReader g(file_, "contacts", path_);
  const auto nmodels = h5::read_attr<i32>(g.id(), "joint_models", path_);
  if (static_cast<std::size_t>(nmodels) != m_.contacts.models.size())
    mismatch("it has " + std::to_string(nmodels) + " joint models, the model " + str(m_.contacts.models.size()));
  if (h5::read_attr_string(g.id(), "joint_model_names", path_) != joint_model_names(m_.contacts))
    mismatch("the joint models are named differently");
  contacts_.assign(nc_, Contact{});
  read_fields(g, fields::kContactFields, Role::state, contacts_);
  for (std::size_t i = 0; i < nc_; ++i) check_contact(i, nmodels);
  // The states: as wide as the file's rows or the model's stride, whichever is less, each wide
  // enough for its contact's joint model.
  std::size_t width = 0;
  {
    h5::Handle ds(H5Dopen2(g.id(), "state", H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) throw InputError(where_ + ": dataset /contacts/state is missing");
    width = nc_ > 0 ? static_cast<std::size_t>(h5::dataset_shape(ds).second) : 0;
  }
  const std::vector<u8> raw = g.get<u8>("state", nc_, width);
  states_.reset(m_.contacts.state_stride(), nc_);
  const std::size_t kept = std::min(width, states_.stride());
  for (std::size_t i = 0; i < nc_; ++i) {
    const std::size_t need = m_.contacts.models[static_cast<std::size_t>(contacts_[i].joint)]->state_size();
    if (need > width)
      mismatch("contact " + str(i) + "'s joint-law state has " + str(width) + " bytes in the file, its joint model needs " +
               str(need));
    std::memcpy(states_.at(i), raw.data() + i * width, kept);
  }
}

void Restore::check_contact(std::size_t i, i32 nmodels) const {
  const Contact& c = contacts_[i];
  if (c.point < 0 || static_cast<std::size_t>(c.point) >= ng_ || c.other < 0 || static_cast<std::size_t>(c.other) >= nb_ ||
      c.joint < 0 || c.joint >= nmodels || m_.blocks[static_cast<std::size_t>(m_.gp[static_cast<std::size_t>(c.point)].block)].id != c.key.point_block ||
      m_.gp[static_cast<std::size_t>(c.point)].local != c.key.point_local ||
      m_.blocks[static_cast<std::size_t>(c.other)].id != c.key.other_block)
    mismatch("contact " + str(i) + " refers to gridpoints, blocks or joint models the model does not have");
  const auto& ob = m_.blocks[static_cast<std::size_t>(c.other)].boundary;
  if (c.edge < 0 || static_cast<std::size_t>(c.edge) >= ob.size()) mismatch("contact " + str(i) + " refers to a missing edge");
}

CheckpointScalars Restore::read_extra() const {
  CheckpointScalars extra;
  GroupReader g(file_, "extra", path_);
  std::vector<std::string> keys;
  hsize_t idx = 0;
  H5Aiterate2(g.id(), H5_INDEX_NAME, H5_ITER_INC, &idx, collect_attr_name, &keys);
  for (const auto& k : keys) extra[k] = h5::read_attr<double>(g.id(), k, path_);
  return extra;
}

// All checked: the state fields go into the model, the identity fields (equal) stay as they are.
void Restore::apply() {
  restore_state(fields::kModelFields, scalars_, m_);
  for (std::size_t i = 0; i < nb_; ++i) {
    restore_state(fields::kBlockFields, blocks_[i], m_.blocks[i]);
    m_.blocks[i].rest_offsets = std::move(blocks_[i].rest_offsets);
  }
  for (std::size_t i = 0; i < ng_; ++i) restore_state(fields::kGridPointFields, gp_[i], m_.gp[i]);
  for (std::size_t i = 0; i < nz_; ++i) restore_state(fields::kZoneFields, zones_[i], m_.zones[i]);
  m_.contacts.restore({std::move(contacts_), std::move(states_)});
}

CheckpointScalars read_impl(Model& m, const std::string& path) {
  const std::string where = "checkpoint '" + path + "'";
  if (!std::filesystem::exists(path)) throw InputError(where + " does not exist");
  h5::QuietErrors quiet;
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(where + " is not an HDF5 file");
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError("cannot open " + where);

  Restore r(m, file, path);
  r.check_format();
  r.read_scalars();
  r.read_counts();
  r.read_blocks();
  r.read_gridpoints();
  r.read_zones();
  r.read_contacts();
  CheckpointScalars extra = r.read_extra();
  r.apply();
  return extra;
}
}  // namespace

namespace {
herr_t collect_link_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->push_back(name);
  return 0;
}

// Opens a checkpoint for the reads below (InputError naming it when it is not one).
h5::Handle open_checkpoint(const std::string& path) {
  if (!std::filesystem::exists(path) || H5Fis_hdf5(path.c_str()) <= 0) throw InputError("checkpoint '" + path + "' is not an HDF5 file");
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError("cannot open checkpoint '" + path + "'");
  return file;
}

// Every dataset of `group` (none when the checkpoint has no such group), read as the HDF5 `type`
// into a container C (std::vector<double> of doubles, std::string of the bytes of a text).
template <class C>
std::map<std::string, C> read_group(const std::string& path, const char* group, hid_t type) {
  std::map<std::string, C> out;
  h5::QuietErrors quiet;
  h5::Handle file = open_checkpoint(path);
  if (H5Lexists(file, group, H5P_DEFAULT) <= 0) return out;
  h5::Handle grp = h5::open_group(file, group, path);
  std::vector<std::string> names;
  hsize_t idx = 0;
  H5Literate(grp, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_link_name, &names);
  for (const auto& n : names) {
    h5::Handle ds(H5Dopen2(grp, n.c_str(), H5P_DEFAULT), H5Dclose);
    const auto [rows, cols] = h5::dataset_shape(ds);
    C v(rows * cols, typename C::value_type{});
    if (!v.empty())
      h5::check_status(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
                       "checkpoint '" + path + "': cannot read /" + group + "/" + n);
    out[n] = std::move(v);
  }
  return out;
}
}  // namespace

CheckpointArrays read_checkpoint_arrays(const std::string& path) {
  return read_group<std::vector<double>>(path, "arrays", H5T_NATIVE_DOUBLE);
}

CheckpointTexts read_checkpoint_texts(const std::string& path) { return read_group<std::string>(path, "texts", H5T_NATIVE_UINT8); }

long read_checkpoint_step(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = open_checkpoint(path);
  return static_cast<long>(h5::read_attr<std::int64_t>(file, "step", path));
}

CheckpointScalars read_checkpoint_scalars(const std::string& path) {
  CheckpointScalars out;
  h5::QuietErrors quiet;
  h5::Handle file = open_checkpoint(path);
  if (H5Lexists(file, "extra", H5P_DEFAULT) <= 0) return out;
  h5::Handle grp = h5::open_group(file, "extra", path);
  std::vector<std::string> keys;
  hsize_t idx = 0;
  H5Aiterate2(grp, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_attr_name, &keys);
  for (const auto& k : keys) out[k] = h5::read_attr<double>(grp, k, path);
  return out;
}

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
