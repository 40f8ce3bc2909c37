// VTK output read back with VTK's own readers: cell kinds and counts, point/cell arrays, contact
// vertices and their data, the .pvd collections listing every step (also after a resume), and the
// .pvtu of a decomposed run's pieces, one per process.
#include <gtest/gtest.h>
#include <unistd.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkStringArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "framework/io/vtk_output.hpp"
#include "framework/mechanics/block_stress.hpp"
#include "framework/model/communication.hpp"
#include "framework/model/partition.hpp"
#include "io_test_model.hpp"

namespace fs = std::filesystem;
using namespace rockdem;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("rockdem_test_vtk_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  return d;
}

// A piece (.vtu) or a step's summary of its pieces (.pvtu), as ParaView reads them.
vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& p) {
  if (p.extension() == ".pvtu") {
    vtkNew<vtkXMLPUnstructuredGridReader> r;
    r->SetFileName(p.string().c_str());
    r->Update();
    return r->GetOutput();
  }
  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(p.string().c_str());
  r->Update();
  return r->GetOutput();
}

struct PvdEntry {
  double time;
  std::string file;
};
std::vector<PvdEntry> read_pvd(const fs::path& p) {
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(p.string().c_str());
  EXPECT_EQ(parser->Parse(), 1) << p;
  std::vector<PvdEntry> out;
  vtkXMLDataElement* coll = parser->GetRootElement()->FindNestedElementWithName("Collection");
  EXPECT_NE(coll, nullptr);
  if (!coll) return out;
  for (int i = 0; i < coll->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = coll->GetNestedElement(i);
    out.push_back({std::stod(e->GetAttribute("timestep")), e->GetAttribute("file")});
  }
  return out;
}

}  // namespace

TEST(VtkOutput, BlocksAndContactsReadBackWithValues) {
  const fs::path dir = temp_dir("grids");
  Model m = test::make_io_test_model();
  test::fill_io_test_state(m, 1.0);
  m.blocks[0].fixed = false;  // a free rigid block: its stress is known from its boundary forces
  m.blocks[0].prescribed = 0;
  m.step = 100;
  VtkSeries vtk(dir);
  vtk.write(m);

  const fs::path bf = dir / "blocks_000000100_0.vtu";  // the one piece of a serial model
  ASSERT_TRUE(fs::exists(bf));
  ASSERT_TRUE(fs::exists(dir / "blocks_000000100.pvtu"));
  {  // binary appended and compressed, as asked of the writer
    std::ifstream in(bf, std::ios::binary);
    std::string head(512, '\0');
    in.read(head.data(), 512);
    EXPECT_NE(head.find("vtkZLibDataCompressor"), std::string::npos);
    EXPECT_NE(head.find("format=\"appended\""), std::string::npos);
  }
  auto g = read_vtu(dir / "blocks_000000100.pvtu");
  ASSERT_EQ(g->GetNumberOfPoints(), 8);
  ASSERT_EQ(g->GetNumberOfCells(), 3);  // one polygon (rigid) + two triangles (zones)
  EXPECT_EQ(g->GetCellType(0), VTK_POLYGON);
  EXPECT_EQ(g->GetCell(0)->GetNumberOfPoints(), 4);
  EXPECT_EQ(g->GetCellType(1), VTK_TRIANGLE);
  EXPECT_EQ(g->GetCellType(2), VTK_TRIANGLE);
  EXPECT_EQ(g->GetCell(2)->GetPointId(1), 6);
  for (vtkIdType i = 0; i < 8; ++i) {
    double x[3];
    g->GetPoint(i, x);
    EXPECT_DOUBLE_EQ(x[0], m.gp[static_cast<std::size_t>(i)].x.x());
    EXPECT_DOUBLE_EQ(x[1], m.gp[static_cast<std::size_t>(i)].x.y());
  }

  vtkDataArray* disp = g->GetPointData()->GetArray("displacement_m");
  vtkDataArray* vel = g->GetPointData()->GetArray("velocity_m_per_s");
  ASSERT_NE(disp, nullptr);
  ASSERT_NE(vel, nullptr);
  EXPECT_EQ(disp->GetNumberOfComponents(), 3);
  for (vtkIdType i = 0; i < 8; ++i) {
    const GridPoint& p = m.gp[static_cast<std::size_t>(i)];
    EXPECT_DOUBLE_EQ(disp->GetComponent(i, 0), p.x.x() - p.x0.x());
    EXPECT_DOUBLE_EQ(disp->GetComponent(i, 1), p.x.y() - p.x0.y());
    EXPECT_EQ(disp->GetComponent(i, 2), 0.0);
    EXPECT_DOUBLE_EQ(vel->GetComponent(i, 0), p.v.x());
    EXPECT_DOUBLE_EQ(vel->GetComponent(i, 1), p.v.y());
  }

  vtkDataArray* stress = g->GetCellData()->GetArray("stress_Pa");
  vtkDataArray* bid = g->GetCellData()->GetArray("block_id");
  ASSERT_NE(stress, nullptr);
  ASSERT_NE(bid, nullptr);
  ASSERT_EQ(stress->GetNumberOfComponents(), 6);
  // The rigid block shows the mean stress of the forces on its boundary, ZZ undefined (0).
  const Voigt3 rigid_mean = block_mean_stress(m)[0];
  EXPECT_TRUE(std::isfinite(rigid_mean[1]));
  EXPECT_DOUBLE_EQ(stress->GetComponent(0, 0), rigid_mean[0]);
  EXPECT_DOUBLE_EQ(stress->GetComponent(0, 1), rigid_mean[1]);
  EXPECT_EQ(stress->GetComponent(0, 2), 0.0);
  EXPECT_DOUBLE_EQ(stress->GetComponent(0, 3), rigid_mean[2]);
  vtkDataArray* from = g->GetCellData()->GetArray("stress_from");
  ASSERT_NE(from, nullptr);
  EXPECT_EQ(from->GetComponent(0, 0), 2);  // rigid block's boundary forces
  EXPECT_EQ(from->GetComponent(1, 0), 1);  // zone
  for (int z = 0; z < 2; ++z) {
    const Zone& zn = m.zones[static_cast<std::size_t>(z)];
    EXPECT_DOUBLE_EQ(stress->GetComponent(1 + z, 0), zn.stress[0]);  // XX
    EXPECT_DOUBLE_EQ(stress->GetComponent(1 + z, 1), zn.stress[1]);  // YY
    EXPECT_DOUBLE_EQ(stress->GetComponent(1 + z, 2), zn.szz);        // ZZ
    EXPECT_DOUBLE_EQ(stress->GetComponent(1 + z, 3), zn.stress[2]);  // XY
    EXPECT_EQ(stress->GetComponent(1 + z, 4), 0.0);
  }
  EXPECT_EQ(bid->GetComponent(0, 0), 0);
  EXPECT_EQ(bid->GetComponent(1, 0), 1);
  EXPECT_EQ(bid->GetComponent(2, 0), 1);
  // Names: each cell's block by name, and the group names for the `group` index.
  auto* bname = vtkStringArray::SafeDownCast(g->GetCellData()->GetAbstractArray("block_name"));
  ASSERT_NE(bname, nullptr);
  EXPECT_EQ(bname->GetValue(0), "base");
  EXPECT_EQ(bname->GetValue(2), "top");
  auto* gnames = vtkStringArray::SafeDownCast(g->GetFieldData()->GetAbstractArray("group_names"));
  ASSERT_NE(gnames, nullptr);
  ASSERT_EQ(gnames->GetNumberOfValues(), 2);
  EXPECT_EQ(gnames->GetValue(1), "top");

  auto c = read_vtu(dir / "contacts_000000100.pvtu");
  ASSERT_EQ(c->GetNumberOfPoints(), 3);
  ASSERT_EQ(c->GetNumberOfCells(), 3);
  EXPECT_EQ(c->GetCellType(2), VTK_VERTEX);
  auto* pd = c->GetPointData();
  for (const char* name : {"normal_stress_Pa", "shear_stress_Pa", "shear_displacement_m", "normal_displacement_m", "state",
                           "length_m", "normal"})
    ASSERT_NE(pd->GetArray(name), nullptr) << name;
  for (vtkIdType i = 0; i < 3; ++i) {
    const Contact& k = m.contacts.items[static_cast<std::size_t>(i)];
    double x[3];
    c->GetPoint(i, x);
    EXPECT_DOUBLE_EQ(x[0], m.gp[static_cast<std::size_t>(k.point)].x.x());
    EXPECT_DOUBLE_EQ(x[1], m.gp[static_cast<std::size_t>(k.point)].x.y());
    EXPECT_DOUBLE_EQ(pd->GetArray("normal_stress_Pa")->GetComponent(i, 0), k.response.sigma_n);
    EXPECT_DOUBLE_EQ(pd->GetArray("shear_stress_Pa")->GetComponent(i, 0), k.response.tau);
    EXPECT_DOUBLE_EQ(pd->GetArray("shear_displacement_m")->GetComponent(i, 0), k.response.u_s);
    EXPECT_DOUBLE_EQ(pd->GetArray("normal_displacement_m")->GetComponent(i, 0), k.response.u_n);
    EXPECT_DOUBLE_EQ(pd->GetArray("length_m")->GetComponent(i, 0), k.length);
    EXPECT_DOUBLE_EQ(pd->GetArray("normal")->GetComponent(i, 1), k.normal.y());
  }
  // fill_io_test_state: contact 0 elastic, 1 slipping, 2 open.
  EXPECT_EQ(pd->GetArray("state")->GetComponent(0, 0), 0);
  EXPECT_EQ(pd->GetArray("state")->GetComponent(1, 0), 1);
  EXPECT_EQ(pd->GetArray("state")->GetComponent(2, 0), 2);
  {  // a held rigid block's reactions are unknown: no stress, and stress_from says so
    m.blocks[0].fixed = true;
    m.step = 101;
    vtk.write(m);
    auto held = read_vtu(dir / "blocks_000000101.pvtu");
    EXPECT_TRUE(std::isnan(held->GetCellData()->GetArray("stress_Pa")->GetComponent(0, 1)));
    EXPECT_EQ(held->GetCellData()->GetArray("stress_from")->GetComponent(0, 0), 0);
    EXPECT_EQ(held->GetCellData()->GetArray("stress_from")->GetComponent(1, 0), 1);
  }
  // The categories' names and the joint models' names travel with the file.
  auto* snames = vtkStringArray::SafeDownCast(c->GetFieldData()->GetAbstractArray("state_names"));
  ASSERT_NE(snames, nullptr);
  ASSERT_EQ(snames->GetNumberOfValues(), 3);
  EXPECT_EQ(snames->GetValue(0), "elastic");
  EXPECT_EQ(snames->GetValue(1), "slipping");
  EXPECT_EQ(snames->GetValue(2), "open");
  auto* jnames = vtkStringArray::SafeDownCast(c->GetFieldData()->GetAbstractArray("joint_names"));
  ASSERT_NE(jnames, nullptr);
  ASSERT_EQ(jnames->GetNumberOfValues(), 1);
  EXPECT_EQ(jnames->GetValue(0), "rock_joint");
  fs::remove_all(dir);
}

TEST(VtkOutput, PvdListsEveryStepAndSurvivesResume) {
  const fs::path dir = temp_dir("pvd");
  Model m = test::make_io_test_model();
  {
    VtkSeries vtk(dir);
    m.time = 0.0;
    m.step = 0;
    vtk.write(m);
    m.time = 0.125;
    m.step = 250;
    ContactList fewer = m.contacts.copy();  // contact sets change between steps
    fewer.items.pop_back();
    fewer.states.reset(fewer.states.stride(), fewer.items.size());
    m.contacts.restore(std::move(fewer));
    vtk.write(m);
    m.time = 0.25;
    m.step = 500;
    vtk.write(m);
  }
  for (const char* which : {"blocks", "contacts"}) {
    const auto e = read_pvd(dir / (std::string(which) + ".pvd"));
    ASSERT_EQ(e.size(), 3u) << which;
    EXPECT_EQ(e[0].time, 0.0);
    EXPECT_EQ(e[1].time, 0.125);
    EXPECT_EQ(e[2].time, 0.25);
    EXPECT_EQ(e[1].file, std::string(which) + "_000000250.pvtu");
    for (const auto& x : e) EXPECT_TRUE(fs::exists(dir / x.file)) << x.file;
  }
  EXPECT_EQ(read_vtu(dir / "contacts_000000250.pvtu")->GetNumberOfPoints(), 2);

  // Restart from the checkpoint at t = 0.125: steps after it are dropped, new ones appended.
  VtkSeries again(dir);
  again.resume(0.125);
  ASSERT_EQ(again.block_steps().size(), 2u);
  EXPECT_EQ(again.block_steps()[1].step, 250);
  m.time = 0.2;
  m.step = 400;
  again.write(m);
  const auto e = read_pvd(dir / "blocks.pvd");
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[2].time, 0.2);
  EXPECT_EQ(e[2].file, "blocks_000000400.pvtu");
  fs::remove_all(dir);
}

namespace {
// The processes of a decomposed run, one at a time: what VtkSeries asks of the communication.
struct OneOfThree : Communication {
  int r = 0;
  int rank() const override { return r; }
  int size() const override { return 3; }
};
}  // namespace

// A decomposed run: each process writes the blocks it owns and the contacts of their points as
// its piece; the step's .pvtu lists every piece (process 2 owns nothing here: an empty piece),
// and read through it the output is the serial one, each cell and contact tagged with its process.
TEST(VtkOutput, EachProcessWritesItsPieceAndTheSummaryListsThemAll) {
  const fs::path serial_dir = temp_dir("serial_pieces"), dir = temp_dir("pieces");
  Model m = test::make_io_test_model();
  test::fill_io_test_state(m, 1.0);
  m.step = 7;
  VtkSeries(serial_dir).write(m);
  const std::vector<int> owner{1, 0};  // the rigid block on process 1, the deformable one on 0
  ASSERT_EQ(m.blocks.size(), owner.size());
  VtkSeries vtk(dir);
  OneOfThree comm;
  for (int r : {2, 1, 0}) {  // process 0 last: it writes the summary once the pieces are there
    assign_owners(m, owner, r);
    comm.r = r;
    vtk.write(m, comm);
  }
  for (int r = 0; r < 3; ++r) EXPECT_TRUE(fs::exists(dir / ("blocks_000000007_" + std::to_string(r) + ".vtu"))) << r;
  EXPECT_EQ(read_vtu(dir / "blocks_000000007_2.vtu")->GetNumberOfCells(), 0);
  EXPECT_EQ(read_vtu(dir / "blocks_000000007_1.vtu")->GetNumberOfCells(), 1);  // the rigid block's polygon
  EXPECT_EQ(read_vtu(dir / "blocks_000000007_0.vtu")->GetNumberOfCells(), 2);  // the two zones
  for (const char* which : {"blocks", "contacts"}) {
    const std::string name = std::string(which) + "_000000007.pvtu";
    auto whole = read_vtu(dir / name);
    auto one = read_vtu(serial_dir / name);
    EXPECT_EQ(whole->GetNumberOfPoints(), one->GetNumberOfPoints()) << which;
    EXPECT_EQ(whole->GetNumberOfCells(), one->GetNumberOfCells()) << which;
  }
  auto blocks = read_vtu(dir / "blocks_000000007.pvtu");
  vtkDataArray* proc = blocks->GetCellData()->GetArray("process");
  vtkDataArray* id = blocks->GetCellData()->GetArray("block_id");
  ASSERT_NE(proc, nullptr);
  for (vtkIdType c = 0; c < blocks->GetNumberOfCells(); ++c) {
    const bool first = id->GetComponent(c, 0) == id_value(m.blocks[0].id);
    EXPECT_EQ(proc->GetComponent(c, 0), first ? owner[0] : owner[1]) << c;
  }
  EXPECT_EQ(read_pvd(dir / "blocks.pvd").at(0).file, "blocks_000000007.pvtu");
  fs::remove_all(serial_dir);
  fs::remove_all(dir);
}

// A piece that cannot be written (here a folder stands where its file goes) is an error, not a
// silent gap that the step's .pvtu would list: VTK's writer reports it by its error code only.
TEST(VtkOutput, APieceThatCannotBeWrittenIsAnError) {
  const fs::path dir = temp_dir("unwritable");
  Model m = test::make_io_test_model();
  m.step = 5;
  VtkSeries vtk(dir);
  fs::create_directories(dir / "blocks_000000005_0.vtu");
  EXPECT_THROW(vtk.write(m), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "blocks_000000005.pvtu"));
  fs::remove_all(dir);
}
