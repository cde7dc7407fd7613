// `export vtk`: the files are read back with VTK's own XML readers and compared with the model.
#include <gtest/gtest.h>

#include <vtkIdList.h>

#include <fstream>
#include <iterator>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/vtk_export.h"
#include "render_test_util.h"

using namespace odec;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), {});
}

Model moved_model() {
    Model m = test::brick_model(3, 2, 2);
    for (int b = 0; b < m.blocks.size(); ++b) {
        m.blocks.disp[b] = Vec3(0.001 * b, -0.002, 0.0001 * b * b);
        m.blocks.vel[b] = Vec3(0.01, 0.02 * b, -0.03);
        m.blocks.ang_vel[b] = Vec3(0, 0, 0.1 * b);
        m.blocks.rotation[b] = Vec3(0.001, 0, 0);
    }
    m.step = 250;
    m.time = 1.25;
    return m;
}

ContactView three_contacts() {
    ContactView v;
    for (int i = 0; i < 3; ++i) {
        ContactRows& r = v.contacts;
        r.centroid.push_back(Vec3(1, 0.5 + i, 1));
        r.normal.push_back(Vec3(1, 0, 0));
        r.area.push_back(1.0);
        r.block1.push_back(1);
        r.block2.push_back(2 + i);
        r.normal_stress.push_back(1.5e6 * (i + 1));
        r.shear_stress.push_back(Vec3(0, 3e5, 4e5 * i));
        r.normal_disp.push_back(-2e-5 * i);
        r.shear_disp.push_back(Vec3(0, 1e-4, 0));
        r.force.push_back(Vec3(-1.5e6 * (i + 1), 0, 0));
        r.state.push_back(i);
    }
    for (int k = 0; k < 4; ++k) {
        ContactRows& s = v.sub_contacts;
        s.centroid.push_back(Vec3(1, 0.25 + 0.5 * (k % 2), 0.75 + 0.5 * (k / 2)));
        s.normal.push_back(Vec3(1, 0, 0));
        s.area.push_back(0.25);
        s.normal_stress.push_back(1e6 + k);
        s.parent.push_back(0);
    }
    v.state_names = {"elastic", "slipping", "tension failed"};
    return v;
}

} // namespace

TEST(ExportVtk, BlocksReadBackAsPolyhedra) {
    const Model m = moved_model();
    const std::string stem = test::out_dir() + "/export-blocks";
    std::remove((stem + ".pvd").c_str());
    std::vector<std::string> written;
    std::string error;
    ASSERT_TRUE(export_vtk(m, nullptr, stem, written, error)) << error;
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(written[0], stem + "-blocks-000250.vtu");
    EXPECT_EQ(written[1], stem + ".pvd");

    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(written[0].c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_EQ(grid->GetNumberOfCells(), m.blocks.size());
    EXPECT_EQ(grid->GetNumberOfPoints(), 8 * m.blocks.size());
    EXPECT_EQ(grid->GetCellType(0), VTK_POLYHEDRON);
    EXPECT_EQ(grid->GetCell(0)->GetNumberOfFaces(), 6);

    vtkDataArray* id = grid->GetCellData()->GetArray("block_id");
    vtkDataArray* group = grid->GetCellData()->GetArray("group");
    vtkDataArray* material = grid->GetCellData()->GetArray("material");
    vtkDataArray* region = grid->GetCellData()->GetArray("region");
    vtkDataArray* disp = grid->GetCellData()->GetArray("displacement");
    vtkDataArray* vel = grid->GetCellData()->GetArray("velocity");
    vtkDataArray* pdisp = grid->GetPointData()->GetArray("displacement");
    vtkDataArray* pvel = grid->GetPointData()->GetArray("velocity");
    ASSERT_TRUE(id && group && material && region && disp && vel && pdisp && pvel);
    EXPECT_EQ(disp->GetNumberOfComponents(), 3);
    for (int b = 0; b < m.blocks.size(); ++b) {
        EXPECT_EQ(id->GetTuple1(b), m.blocks.id[b]);
        EXPECT_EQ(group->GetTuple1(b), m.blocks.group[b]);
        EXPECT_EQ(material->GetTuple1(b), m.blocks.material[b]);
        EXPECT_EQ(region->GetTuple1(b), m.blocks.region[b]);
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(disp->GetComponent(b, k), m.blocks.disp[b][k]); // round-trip exact
            EXPECT_EQ(vel->GetComponent(b, k), velocity_at_t(m, b)[k]);
        }
    }
    // Each cell's volume is its block's, and a vertex carries the rigid motion of its block.
    const Polyhedron w = world_shape(m, 5);
    double x[3];
    grid->GetPoint(5 * 8, x);
    EXPECT_EQ(Vec3(x[0], x[1], x[2]), w.vertices[0]);
    const Vec3 r = w.vertices[0] - m.blocks.centroid[5];
    const Vec3 expected = velocity_at_t(m, 5) + m.blocks.ang_vel[5].cross(r);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(pvel->GetComponent(5 * 8, k), expected[k], 1e-15);

    const std::string pvd = slurp(stem + ".pvd");
    EXPECT_NE(pvd.find("file=\"export-blocks-blocks-000250.vtu\""), std::string::npos);
}

TEST(ExportVtk, ContactsAndCollectionAcrossSteps) {
    Model m = moved_model();
    const ContactView v = three_contacts();
    const std::string stem = test::out_dir() + "/export-steps";
    std::remove((stem + ".pvd").c_str());
    std::vector<std::string> written;
    std::string error;
    ASSERT_TRUE(export_vtk(m, &v, stem + ".vtu", written, error)) << error; // extension dropped
    ASSERT_EQ(written.size(), 4u);
    EXPECT_EQ(written[1], stem + "-contacts-000250.vtp");
    EXPECT_EQ(written[2], stem + "-subcontacts-000250.vtp");

    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(written[1].c_str());
    reader->Update();
    vtkPolyData* poly = reader->GetOutput();
    // One patch a contact: contact 0 is outlined by its four sub-contacts (a 0.5 m square in
    // x = 1), the others, with no sub-contacts, are squares of their area.
    ASSERT_EQ(poly->GetNumberOfPolys(), 3);
    EXPECT_EQ(poly->GetNumberOfVerts(), 0);
    EXPECT_EQ(poly->GetNumberOfPoints(), 12);
    {
        double b[6];
        vtkNew<vtkIdList> ids;
        poly->GetCellPoints(0, ids);
        ASSERT_EQ(ids->GetNumberOfIds(), 4);
        for (int k = 0; k < 3; ++k) { b[2 * k] = 1e300; b[2 * k + 1] = -1e300; }
        for (vtkIdType j = 0; j < 4; ++j) {
            double p[3];
            poly->GetPoint(ids->GetId(j), p);
            for (int k = 0; k < 3; ++k) { b[2 * k] = std::min(b[2 * k], p[k]); b[2 * k + 1] = std::max(b[2 * k + 1], p[k]); }
        }
        EXPECT_NEAR(b[0], 1, 1e-12);
        EXPECT_NEAR(b[1], 1, 1e-12);
        EXPECT_NEAR(b[3] - b[2], 0.5, 1e-12);
        EXPECT_NEAR(b[5] - b[4], 0.5, 1e-12);
    }
    vtkDataArray* sn = poly->GetCellData()->GetArray("normal_stress");
    vtkDataArray* ss = poly->GetCellData()->GetArray("shear_stress");
    vtkDataArray* state = poly->GetCellData()->GetArray("state");
    vtkDataArray* force = poly->GetCellData()->GetArray("force");
    vtkDataArray* b2 = poly->GetCellData()->GetArray("block2");
    ASSERT_TRUE(sn && ss && state && force && b2);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(sn->GetTuple1(i), v.contacts.normal_stress[i]);
        EXPECT_EQ(state->GetTuple1(i), v.contacts.state[i]);
        EXPECT_EQ(b2->GetTuple1(i), v.contacts.block2[i]);
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(ss->GetComponent(i, k), v.contacts.shear_stress[i][k]);
            EXPECT_EQ(force->GetComponent(i, k), v.contacts.force[i][k]);
        }
    }
    vtkNew<vtkXMLPolyDataReader> sub;
    sub->SetFileName(written[2].c_str());
    sub->Update();
    EXPECT_EQ(sub->GetOutput()->GetNumberOfPoints(), 4);

    // A later step adds its entries; exporting the same step again replaces them.
    m.step = 500;
    m.time = 2.5;
    ASSERT_TRUE(export_vtk(m, &v, stem, written, error)) << error;
    ASSERT_TRUE(export_vtk(m, &v, stem, written, error)) << error;
    const std::string pvd = slurp(stem + ".pvd");
    size_t n_entries = 0;
    for (size_t at = pvd.find("<DataSet"); at != std::string::npos; at = pvd.find("<DataSet", at + 1)) ++n_entries;
    EXPECT_EQ(n_entries, 6u);
    EXPECT_LT(pvd.find("-blocks-000250.vtu"), pvd.find("-blocks-000500.vtu"));
    // ParaView's time is the model time, s.
    EXPECT_NE(pvd.find("timestep=\"1.25\" group=\"\" part=\"1\" file=\"export-steps-contacts-000250.vtp\""),
              std::string::npos)
        << pvd;
    EXPECT_NE(pvd.find("timestep=\"2.5\" group=\"\" part=\"1\" file=\"export-steps-contacts-000500.vtp\""),
              std::string::npos)
        << pvd;
    // The same model gives the same bytes.
    const std::string before = slurp(stem + "-blocks-000500.vtu");
    ASSERT_TRUE(export_vtk(m, &v, stem, written, error)) << error;
    EXPECT_EQ(before, slurp(stem + "-blocks-000500.vtu"));
}

TEST(ExportVtk, ExcavatedBlocksAreLeftOutAndErrorsAreReported) {
    Model m = moved_model();
    m.blocks.flags[0] |= kExcavated;
    const std::string stem = test::out_dir() + "/export-excavated";
    std::vector<std::string> written;
    std::string error;
    ASSERT_TRUE(export_vtk(m, nullptr, stem, written, error)) << error;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(written[0].c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), m.blocks.size() - 1);

    EXPECT_FALSE(export_vtk(m, nullptr, "/nonexistent-dir/model", written, error));
    EXPECT_NE(error.find("cannot write"), std::string::npos);
    ContactView bad = three_contacts();
    bad.contacts.normal.pop_back();
    EXPECT_FALSE(export_vtk(m, &bad, stem, written, error));
    EXPECT_NE(error.find("normal"), std::string::npos);
}
