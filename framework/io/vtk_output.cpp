#include "framework/io/vtk_output.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkSmartPointer.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkFieldData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "framework/core/error.hpp"
#include "framework/mechanics/block_stress.hpp"
#include "framework/model/communication.hpp"
#include "framework/model/model.hpp"

namespace rockdem {

namespace {

vtkNew<vtkDoubleArray> make_array(const char* name, int components, vtkIdType tuples) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

vtkNew<vtkIntArray> make_int_array(const char* name, vtkIdType tuples) {
  vtkNew<vtkIntArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(tuples);
  return a;
}

void write_grid(vtkUnstructuredGrid* grid, const std::string& path) {
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(grid);
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();  // raw binary: smaller and faster than base64
  w->SetCompressorTypeToZLib();
  w->SetHeaderTypeToUInt64();  // no 4 GiB limit on a block of appended data
  // Write() returns 1 also when the file cannot be opened or the disk fills: the error code says.
  if (w->Write() != 1 || w->GetErrorCode() != vtkErrorCode::NoError)
    throw std::runtime_error("cannot write VTK file '" + path + "'");
}

vtkNew<vtkPoints> make_points(vtkIdType n) {
  vtkNew<vtkPoints> p;
  p->SetDataTypeToDouble();
  p->SetNumberOfPoints(n);
  return p;
}

// Nine digits: runs reach millions of steps, and padded names keep `ls` and globs in step order.
// The step's summary (.pvtu) and its pieces (_<p>.vtu, the names VTK's parallel writer gives them).
std::string step_stem(const char* prefix, long step) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%09ld", prefix, step);
  return buf;
}
std::string piece_file(const std::string& stem, int piece) { return stem + "_" + std::to_string(piece) + ".vtu"; }

// VTK's parallel writer writes the summary (.pvtu) of the pieces it wrote itself, and learns which
// pieces the other processes wrote through a vtkMultiProcessController's reduction. Here each
// process writes its own piece with the serial writer and the processes agree on the outcome
// through rockdem's Communication (a piece that fails inside VTK's writer would leave the others
// waiting in that reduction), so process 0 only has the summary left to write: this writer
// writes no piece and declares every one.
class PvtuSummaryWriter : public vtkXMLPUnstructuredGridWriter {
 public:
  static PvtuSummaryWriter* New();
  vtkTypeMacro(PvtuSummaryWriter, vtkXMLPUnstructuredGridWriter)

 protected:
  int WritePieceInternal() override { return 1; }
  void PrepareSummaryFile() override { std::memset(this->PieceWrittenFlags, 1, static_cast<std::size_t>(this->NumberOfPieces)); }
};
vtkStandardNewMacro(PvtuSummaryWriter);

// The .pvtu at `path` listing `pieces` pieces <stem>_<p>.vtu beside it, with the arrays of `grid`
// (a piece: every piece has the same arrays).
void write_summary(vtkUnstructuredGrid* grid, const std::string& path, int pieces) {
  vtkNew<PvtuSummaryWriter> w;
  w->SetController(nullptr);
  w->SetFileName(path.c_str());
  w->SetInputData(grid);
  w->SetNumberOfPieces(pieces);
  w->SetStartPiece(0);
  w->SetEndPiece(0);
  w->SetWriteSummaryFile(1);
  w->SetDataModeToAppended();
  w->SetHeaderTypeToUInt64();
  if (w->Write() != 1 || w->GetErrorCode() != vtkErrorCode::NoError)
    throw std::runtime_error("cannot write VTK file '" + path + "'");
}

// Entries of an existing .pvd written by write_pvd_collection (the step is taken from the file name).
std::vector<VtkSeries::Entry> read_pvd(const std::filesystem::path& path, const char* prefix) {
  std::vector<VtkSeries::Entry> out;
  if (!std::filesystem::exists(path)) return out;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(path.string().c_str());
  if (parser->Parse() != 1 || !parser->GetRootElement())
    throw InputError("cannot parse the ParaView collection '" + path.string() + "'");
  vtkXMLDataElement* coll = parser->GetRootElement()->FindNestedElementWithName("Collection");
  if (!coll) throw InputError("'" + path.string() + "' has no <Collection>");
  const std::string pre = std::string(prefix) + "_";
  for (int i = 0; i < coll->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* ds = coll->GetNestedElement(i);
    const char* t = ds->GetAttribute("timestep");
    const char* f = ds->GetAttribute("file");
    if (!t || !f) continue;
    std::string file = f;
    long step = -1;
    if (file.rfind(pre, 0) == 0) step = std::strtol(file.c_str() + pre.size(), nullptr, 10);
    out.push_back({std::strtod(t, nullptr), step, file});
  }
  return out;
}

void upsert(std::vector<VtkSeries::Entry>& entries, VtkSeries::Entry e) {
  auto it = std::find_if(entries.begin(), entries.end(), [&](const auto& x) { return x.file == e.file; });
  if (it != entries.end())
    *it = std::move(e);
  else
    entries.push_back(std::move(e));
}

// A list of names as a field-data string array (category names for an integer array).
vtkNew<vtkStringArray> name_list(const char* array_name, const std::vector<std::string>& names) {
  vtkNew<vtkStringArray> a;
  a->SetName(array_name);
  for (const std::string& x : names) a->InsertNextValue(x);
  return a;
}

// The names of the edge labels, "<joint>" or "<joint> bridge" ("cut" for glued cuts), by index.
vtkNew<vtkStringArray> edge_label_names(const Model& m) {
  std::vector<std::string> names;
  for (const auto& l : m.contacts.edge_labels)
    names.push_back(l.joint.empty() ? std::string("cut") : l.joint + (l.bridge ? " bridge" : ""));
  return name_list("edge_label_names", names);
}

}  // namespace

// The .pvd is tiny; written to a temporary name and renamed so that a reader (or a crash) never
// sees half a file.
void write_pvd_collection(const std::filesystem::path& path, const std::vector<VtkSeries::Entry>& entries) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot write '" + tmp.string() + "'");
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "  <Collection>\n";
    char t[64];
    for (const auto& e : entries) {
      std::snprintf(t, sizeof t, "%.17g", e.time);
      out << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << e.file << "\"/>\n";
    }
    out << "  </Collection>\n</VTKFile>\n";
    if (!out.flush()) throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  std::filesystem::rename(tmp, path);
}

// Array names carry their unit (SI, as in the model: Pa, m, m/s) so that a colour legend in
// ParaView reads without a manual; integer arrays that are categories have their names in a
// field-data string array (`group_names`, `state_names`, `joint_names`, `edge_label_names`).
namespace {

// The blocks this process owns (all of a serial model), their gridpoints numbered in model order.
vtkSmartPointer<vtkUnstructuredGrid> blocks_grid(const Model& m) {
  std::vector<vtkIdType> local(m.gp.size(), -1);
  vtkIdType np = 0;
  for_owned_gridpoints(m, [&](int i) { local[static_cast<std::size_t>(i)] = np++; });
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto pts = make_points(np);
  auto disp = make_array("displacement_m", 3, np);
  auto vel = make_array("velocity_m_per_s", 3, np);
  for (std::size_t k = 0; k < m.gp.size(); ++k) {
    const vtkIdType i = local[k];
    if (i < 0) continue;
    const GridPoint& g = m.gp[k];
    pts->SetPoint(i, g.x.x(), g.x.y(), 0.0);
    disp->SetTuple3(i, g.x.x() - g.x0.x(), g.x.y() - g.x0.y(), 0.0);
    vel->SetTuple3(i, g.v.x(), g.v.y(), 0.0);
  }
  grid->SetPoints(pts);
  grid->GetPointData()->AddArray(disp);
  grid->GetPointData()->AddArray(vel);
  grid->GetPointData()->SetActiveVectors("displacement_m");  // the default for Warp By Vector

  vtkIdType ncell = 0;
  for_owned_blocks(m, [&](int bi) {
    const Block& b = m.blocks[static_cast<std::size_t>(bi)];
    ncell += b.rigid ? 1 : b.n_zone;
  });
  grid->Allocate(ncell);
  auto stress = make_array("stress_Pa", 6, ncell);
  const char* comp[6] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c) stress->SetComponentName(c, comp[c]);
  auto block_id = make_int_array("block_id", ncell);
  vtkNew<vtkStringArray> block_name;
  block_name->SetName("block_name");
  block_name->SetNumberOfValues(ncell);
  auto rigid = make_int_array("rigid", ncell);
  auto group = make_int_array("group", ncell);
  auto from = make_int_array("stress_from", ncell);
  // The process that computes each block in a domain-decomposed run (0 in a serial one).
  auto process = make_int_array("process", ncell);

  // Rigid blocks have no strain, hence no constitutive stress: they show the mean stress the
  // forces on their boundary put on them (block_stress.hpp), with ZZ = 0 (no out-of-plane stress
  // is defined without an elastic law); a held one (fixed or driven) NaN, its reactions unknown.
  // `stress_from` says which: 1 zone, 2 rigid block's boundary forces, 0 none (names in
  // `stress_from_names`), so that a Threshold on it shows only the known stresses.
  std::vector<Voigt3> mean;
  const bool any_rigid = std::any_of(m.blocks.begin(), m.blocks.end(), [](const Block& b) { return b.rigid; });
  if (any_rigid) mean = block_mean_stress(m);
  std::vector<vtkIdType> ids;
  vtkIdType cell = 0;
  for_owned_blocks(m, [&](int block) {
    const auto bi = static_cast<std::size_t>(block);
    const Block& b = m.blocks[bi];
    auto tag = [&](vtkIdType c) {
      block_id->SetValue(c, id_value(b.id));
      block_name->SetValue(c, b.name);
      rigid->SetValue(c, b.rigid ? 1 : 0);
      group->SetValue(c, b.group);
      process->SetValue(c, m.part.decomposed() ? m.part.owner[bi] : 0);
    };
    if (b.rigid) {
      ids.clear();
      for (int g : b.boundary) ids.push_back(local[static_cast<std::size_t>(g)]);
      grid->InsertNextCell(VTK_POLYGON, static_cast<vtkIdType>(ids.size()), ids.data());
      // Before the first step no force has been computed: not known yet either.
      const bool known = block_stress_known(b) && m.step > 0;
      const double s[6] = {mean[bi][0], mean[bi][1], known ? 0.0 : std::numeric_limits<double>::quiet_NaN(), mean[bi][2], 0.0, 0.0};
      stress->SetTuple(cell, s);
      from->SetValue(cell, known ? 2 : 0);
      tag(cell++);
      return;
    }
    for (int z = b.first_zone; z < b.first_zone + b.n_zone; ++z) {
      const Zone& zn = m.zones[static_cast<std::size_t>(z)];
      const vtkIdType tri[3] = {local[static_cast<std::size_t>(zn.n[0])], local[static_cast<std::size_t>(zn.n[1])],
                                local[static_cast<std::size_t>(zn.n[2])]};
      grid->InsertNextCell(VTK_TRIANGLE, 3, tri);
      const double s[6] = {zn.stress[0], zn.stress[1], zn.szz, zn.stress[2], 0.0, 0.0};
      stress->SetTuple(cell, s);
      from->SetValue(cell, 1);
      tag(cell++);
    }
  });
  grid->GetCellData()->AddArray(stress);
  grid->GetCellData()->AddArray(block_id);
  grid->GetCellData()->AddArray(block_name);
  grid->GetCellData()->AddArray(from);
  grid->GetCellData()->AddArray(rigid);
  grid->GetCellData()->AddArray(group);
  grid->GetCellData()->AddArray(process);
  grid->GetFieldData()->AddArray(name_list("group_names", m.contacts.group_names));
  grid->GetFieldData()->AddArray(name_list("stress_from_names", {"none (held rigid block)", "zone", "rigid block boundary forces"}));
  return grid;
}

// The contacts this process owns (those of its blocks' points; every contact of a serial model).
vtkSmartPointer<vtkUnstructuredGrid> contacts_grid(const Model& m) {
  std::vector<const Contact*> items;
  for (const Contact& c : m.contacts.items)
    if (m.part.owns(m.gp[static_cast<std::size_t>(c.point)].block)) items.push_back(&c);
  const auto n = static_cast<vtkIdType>(items.size());
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto pts = make_points(n);
  auto sn = make_array("normal_stress_Pa", 1, n);
  auto ss = make_array("shear_stress_Pa", 1, n);
  auto us = make_array("shear_displacement_m", 1, n);
  auto un = make_array("normal_displacement_m", 1, n);
  auto len = make_array("length_m", 1, n);
  auto nrm = make_array("normal", 3, n);
  auto state = make_int_array("state", n);
  auto pb = make_int_array("point_block", n);
  auto ob = make_int_array("other_block", n);
  auto joint = make_int_array("joint", n);
  // Rock-mass edge of the other block the point is against: its label (ContactStore::edge_labels,
  // -1 none) and whether that is a rock bridge or glued cut (1), a joint trace (0) or nothing (-1).
  auto label = make_int_array("edge_label", n);
  auto bridge = make_int_array("bridge", n);
  auto process = make_int_array("process", n);  // the process owning the contact (its point's block)
  // One vertex cell per point: each cell is [1, i].
  vtkNew<vtkIdTypeArray> conn;
  conn->SetNumberOfValues(2 * n);
  for (vtkIdType i = 0; i < n; ++i) {
    const Contact& c = *items[static_cast<std::size_t>(i)];
    const Vec2& x = m.gp[static_cast<std::size_t>(c.point)].x;
    pts->SetPoint(i, x.x(), x.y(), 0.0);
    sn->SetValue(i, c.response.sigma_n);
    ss->SetValue(i, c.response.tau);
    us->SetValue(i, c.response.u_s);
    un->SetValue(i, c.response.u_n);
    len->SetValue(i, c.length);
    nrm->SetTuple3(i, c.normal.x(), c.normal.y(), 0.0);
    state->SetValue(i, c.state_category());
    pb->SetValue(i, id_value(c.key.point_block));
    ob->SetValue(i, id_value(c.key.other_block));
    joint->SetValue(i, c.joint);
    const int l = m.blocks[static_cast<std::size_t>(c.other)].edge_label(c.edge);
    label->SetValue(i, l);
    bridge->SetValue(i, l < 0 ? -1 : (m.contacts.edge_labels[static_cast<std::size_t>(l)].bridge ? 1 : 0));
    process->SetValue(i, m.part.decomposed() ? m.part.owner[static_cast<std::size_t>(m.gp[static_cast<std::size_t>(c.point)].block)] : 0);
    conn->SetValue(2 * i, 1);
    conn->SetValue(2 * i + 1, i);
  }
  vtkNew<vtkCellArray> cells;
  cells->ImportLegacyFormat(conn);
  grid->SetPoints(pts);
  grid->SetCells(VTK_VERTEX, cells);
  auto* pd = grid->GetPointData();
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(sn), static_cast<vtkDataArray*>(ss),
                          static_cast<vtkDataArray*>(us), static_cast<vtkDataArray*>(un),
                          static_cast<vtkDataArray*>(state), static_cast<vtkDataArray*>(len),
                          static_cast<vtkDataArray*>(nrm), static_cast<vtkDataArray*>(pb),
                          static_cast<vtkDataArray*>(ob), static_cast<vtkDataArray*>(joint),
                          static_cast<vtkDataArray*>(label), static_cast<vtkDataArray*>(bridge),
                          static_cast<vtkDataArray*>(process)})
    pd->AddArray(a);
  // The joint a contact follows by its model's case-file name: a loading frame's or platen's
  // contacts are told from the rock joint's by it.
  auto* fd = grid->GetFieldData();
  fd->AddArray(name_list("state_names", {std::begin(kContactStateNames), std::end(kContactStateNames)}));
  fd->AddArray(name_list("joint_names", m.contacts.model_names));
  fd->AddArray(edge_label_names(m));
  pd->SetActiveVectors("normal");  // the default orientation for Glyph
  return grid;
}

}  // namespace

void write_blocks_vtu(const Model& m, const std::string& path) { write_grid(blocks_grid(m), path); }

void write_contacts_vtu(const Model& m, const std::string& path) { write_grid(contacts_grid(m), path); }

VtkSeries::VtkSeries(std::filesystem::path dir, bool contacts) : dir_(std::move(dir)), write_contacts_(contacts) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw InputError("cannot create output folder '" + dir_.string() + "': " + ec.message());
}

void VtkSeries::write(const Model& m) { write(m, Communication()); }

void VtkSeries::write(const Model& m, const Communication& comm) {
  // A decomposed run writes one piece per process; a serial one (or a model not decomposed among
  // several processes: process 0's) one piece.
  const bool parallel = m.part.decomposed();
  if (!parallel && !comm.root()) return;
  const int pieces = parallel ? comm.size() : 1, piece = parallel ? comm.rank() : 0;
  auto agree = [&](const std::string& error) {
    const std::string first = parallel ? comm.first_message(error) : error;
    if (!first.empty()) throw std::runtime_error(first);
  };
  const std::string bs = step_stem("blocks", m.step), cs = step_stem("contacts", m.step);
  vtkSmartPointer<vtkUnstructuredGrid> blocks, contacts;
  std::string error;
  try {
    blocks = blocks_grid(m);
    write_grid(blocks, (dir_ / piece_file(bs, piece)).string());
    if (write_contacts_) {
      contacts = contacts_grid(m);
      write_grid(contacts, (dir_ / piece_file(cs, piece)).string());
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree(error);
  // Only after every piece is complete (the agreement above), so that neither the summary nor the
  // collection ever lists a partial file.
  upsert(blocks_, {m.time, m.step, bs + ".pvtu"});
  if (write_contacts_) upsert(contacts_, {m.time, m.step, cs + ".pvtu"});
  if (comm.root()) {
    try {
      write_summary(blocks, (dir_ / (bs + ".pvtu")).string(), pieces);
      write_pvd_collection(dir_ / "blocks.pvd", blocks_);
      if (write_contacts_) {
        write_summary(contacts, (dir_ / (cs + ".pvtu")).string(), pieces);
        write_pvd_collection(dir_ / "contacts.pvd", contacts_);
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  agree(error);
}

void VtkSeries::resume(double time) {
  auto keep = [time](std::vector<Entry> v) {
    std::erase_if(v, [time](const Entry& e) { return e.time > time; });
    return v;
  };
  blocks_ = keep(read_pvd(dir_ / "blocks.pvd", "blocks"));
  if (write_contacts_) contacts_ = keep(read_pvd(dir_ / "contacts.pvd", "contacts"));
}

namespace {

// The arrays of `fields`, each checked to have `n` values, added to `data` (point or cell data),
// and the name lists to the grid's field data.
void add_fields(vtkUnstructuredGrid* grid, vtkDataSetAttributes* data, const VtkFields& fields, vtkIdType n,
                const std::string& path) {
  const auto check = [&](const std::string& name, std::size_t size) {
    if (static_cast<vtkIdType>(size) != n)
      throw std::logic_error("VTK field '" + name + "' of '" + path + "' has " + std::to_string(size) + " values for " +
                             std::to_string(n) + " items");
  };
  for (const auto& [name, v] : fields.scalars) {
    check(name, v.size());
    auto a = make_array(name.c_str(), 1, n);
    for (vtkIdType i = 0; i < n; ++i) a->SetValue(i, v[static_cast<std::size_t>(i)]);
    data->AddArray(a);
  }
  for (const auto& [name, v] : fields.vectors) {
    check(name, v.size());
    auto a = make_array(name.c_str(), 3, n);
    for (vtkIdType i = 0; i < n; ++i) a->SetTuple3(i, v[static_cast<std::size_t>(i)].x(), v[static_cast<std::size_t>(i)].y(), 0.0);
    data->AddArray(a);
  }
  for (const auto& [name, v] : fields.ints) {
    check(name, v.size());
    auto a = make_int_array(name.c_str(), n);
    for (vtkIdType i = 0; i < n; ++i) a->SetValue(i, v[static_cast<std::size_t>(i)]);
    data->AddArray(a);
  }
  for (const auto& [name, v] : fields.names) grid->GetFieldData()->AddArray(name_list(name.c_str(), v));
}

}  // namespace

void write_points_vtu(const std::vector<Vec2>& points, const VtkFields& fields, const std::string& path) {
  vtkNew<vtkUnstructuredGrid> grid;
  const auto n = static_cast<vtkIdType>(points.size());
  auto pts = make_points(n);
  grid->Allocate(n);
  for (vtkIdType i = 0; i < n; ++i) {
    pts->SetPoint(i, points[static_cast<std::size_t>(i)].x(), points[static_cast<std::size_t>(i)].y(), 0.0);
    grid->InsertNextCell(VTK_VERTEX, 1, &i);
  }
  grid->SetPoints(pts);
  add_fields(grid, grid->GetPointData(), fields, n, path);
  write_grid(grid, path);
}

void write_block_cells_vtu(const Model& m, const VtkFields& fields, const std::string& path) {
  vtkNew<vtkUnstructuredGrid> grid;
  auto pts = make_points(static_cast<vtkIdType>(m.gp.size()));
  for (std::size_t i = 0; i < m.gp.size(); ++i) pts->SetPoint(static_cast<vtkIdType>(i), m.gp[i].x.x(), m.gp[i].x.y(), 0.0);
  grid->SetPoints(pts);
  const auto n = static_cast<vtkIdType>(m.blocks.size());
  grid->Allocate(n);
  std::vector<vtkIdType> ids;
  for (const Block& b : m.blocks) {
    ids.assign(b.boundary.begin(), b.boundary.end());
    grid->InsertNextCell(VTK_POLYGON, static_cast<vtkIdType>(ids.size()), ids.data());
  }
  add_fields(grid, grid->GetCellData(), fields, n, path);
  write_grid(grid, path);
}

void write_block_outlines_vtu(const Model& m, const std::vector<int>& region, const std::vector<int>& opening,
                              const std::string& path) {
  VtkFields f;
  std::vector<int> block_id, group, rigid;
  for (const Block& b : m.blocks) {
    block_id.push_back(id_value(b.id));
    group.push_back(b.group);
    rigid.push_back(b.rigid ? 1 : 0);
  }
  f.ints = {{"block_id", block_id}, {"group", group}, {"rigid", rigid}, {"region", region}, {"opening", opening}};
  write_block_cells_vtu(m, f, path);
}

void write_joint_traces_vtu(const std::vector<RockMassSegment>& segments, const std::string& path) {
  vtkNew<vtkUnstructuredGrid> grid;
  const auto n = static_cast<vtkIdType>(segments.size());
  auto pts = make_points(2 * n);
  auto source = make_int_array("joint_set", n), bridge = make_int_array("bridge", n), kind = make_int_array("kind", n);
  grid->Allocate(n);
  for (vtkIdType i = 0; i < n; ++i) {
    const RockMassSegment& s = segments[static_cast<std::size_t>(i)];
    pts->SetPoint(2 * i, s.a.x(), s.a.y(), 0.0);
    pts->SetPoint(2 * i + 1, s.b.x(), s.b.y(), 0.0);
    const vtkIdType line[2] = {2 * i, 2 * i + 1};
    grid->InsertNextCell(VTK_LINE, 2, line);
    source->SetValue(i, s.tag.source);
    bridge->SetValue(i, s.tag.kind == EdgeKind::joint ? 0 : 1);
    kind->SetValue(i, static_cast<int>(s.tag.kind));
  }
  grid->SetPoints(pts);
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(source), static_cast<vtkDataArray*>(bridge),
                          static_cast<vtkDataArray*>(kind)})
    grid->GetCellData()->AddArray(a);
  write_grid(grid, path);
}

}  // namespace rockdem
