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

#include <vtkCell.h>
#include <vtkMath.h>
#include <vtkTetra.h>

#include "engine/range.h"
#include "engine/zones.h"
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
        m.blocks.ref_orientation[b] = Quat(Eigen::AngleAxisd(-0.001, Vec3::UnitX())); // turned 0.001 rad about x
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

// A rigid brick (id 1, x 2..3) and a unit cube (id 2) made deformable with six tetrahedra
// about its diagonal from (0,0,0) to (1,1,1), each with positive volume.
Model zoned_model() {
    Model m;
    add_block(m, make_brick(2, 3, 0, 1, 0, 1), 1, -1, 1);
    add_block(m, make_brick(0, 1, 0, 1, 0, 1), 1, -1, 1);
    m.materials.resize(2);
    m.materials[1] = Material{true, 2500, 6.7e9, 4e9, 0, 0, 0, 0};
    BlockMesh mesh;
    for (int k = 0; k < 8; ++k) mesh.nodes.push_back(Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    std::vector<std::array<int, 4>> tets;
    // The six paths from corner 0 to corner 7 along the edges of the cube.
    for (const auto& path : std::vector<std::array<int, 2>>{{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}}) {
        std::array<int, 4> t = {0, path[0], path[1], 7};
        const Vec3 e1 = mesh.nodes[t[1]] - mesh.nodes[t[0]], e2 = mesh.nodes[t[2]] - mesh.nodes[t[0]],
                   e3 = mesh.nodes[t[3]] - mesh.nodes[t[0]];
        if (e1.dot(e2.cross(e3)) < 0) std::swap(t[1], t[2]);
        tets.push_back(t);
    }
    mesh.tets.push_back(tets);
    std::vector<int> corners;
    const Polyhedron w = world_shape(m, 1);
    for (const Vec3& v : w.vertices) {
        int node = -1;
        for (int k = 0; k < 8; ++k) {
            if ((mesh.nodes[k] - v).norm() < 1e-12) node = k;
        }
        corners.push_back(node);
    }
    mesh.corner_node.push_back(corners);
    zone_blocks(m, {1}, {0}, mesh);
    return m;
}

} // namespace

TEST(ExportVtk, ZonesReadBackAsTetrahedraWithStressAndDisplacement) {
    Model m = zoned_model();
    ASSERT_EQ(m.zones.size(), 6);
    ASSERT_EQ(m.gridpoints.size(), 8);
    // Stresses as 'insitu' sets them (xx yy zz xy xz yz, tension positive), one zone apart.
    const Sym6 s = {-1e6, -2e6, -3e6, 1e5, 2e5, 3e5};
    const Sym6 zero = {0, 0, 0, 0, 0, 0};
    ASSERT_EQ(set_insitu_stress(m, Range{}, s, zero, zero, zero), 6);
    m.zones.stress[4] = {5e5, -1e5, -7e5, -4e4, 6e4, -8e4};
    m.zones.state[4] = kShearNow | kShearPast;
    // The gridpoints moved and moving, each by its own amount.
    for (int i = 0; i < m.gridpoints.size(); ++i) {
        const Vec3 d(1e-4 * i, -2e-4 * i, -3e-4 * i * i);
        m.gridpoints.pos[i] += d;
        m.gridpoints.disp[i] = d;
        m.gridpoints.vel[i] = Vec3(0.01 * i, 0, -0.02);
    }
    refresh_world_vertices(m);
    m.step = 42;
    m.time = 0.5;
    const std::string stem = test::out_dir() + "/export-zones";
    std::remove((stem + ".pvd").c_str());
    std::vector<std::string> written;
    std::string error;
    ASSERT_TRUE(export_vtk(m, nullptr, stem, written, error)) << error;
    ASSERT_EQ(written.size(), 3u);
    EXPECT_EQ(written[0], stem + "-blocks-000042.vtu");
    EXPECT_EQ(written[1], stem + "-zones-000042.vtu");
    EXPECT_NE(slurp(stem + ".pvd").find("part=\"3\" file=\"export-zones-zones-000042.vtu\""), std::string::npos);

    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(written[1].c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_EQ(grid->GetNumberOfCells(), 6);
    ASSERT_EQ(grid->GetNumberOfPoints(), 8);
    vtkDataArray* stress = grid->GetCellData()->GetArray("stress");
    vtkDataArray* smin = grid->GetCellData()->GetArray("smin");
    vtkDataArray* smid = grid->GetCellData()->GetArray("smid");
    vtkDataArray* smax = grid->GetCellData()->GetArray("smax");
    vtkDataArray* state = grid->GetCellData()->GetArray("state");
    vtkDataArray* block_id = grid->GetCellData()->GetArray("block_id");
    vtkDataArray* zone = grid->GetCellData()->GetArray("zone");
    vtkDataArray* number = grid->GetPointData()->GetArray("gridpoint");
    vtkDataArray* disp = grid->GetPointData()->GetArray("displacement");
    vtkDataArray* vel = grid->GetPointData()->GetArray("velocity");
    ASSERT_TRUE(stress && smin && smid && smax && state && block_id && zone && number && disp && vel);
    ASSERT_EQ(stress->GetNumberOfComponents(), 6);
    ASSERT_TRUE(stress->GetComponentName(4));
    EXPECT_STREQ(stress->GetComponentName(4), "YZ");
    EXPECT_STREQ(stress->GetComponentName(5), "XZ");
    for (int c = 0; c < 6; ++c) {
        SCOPED_TRACE(c);
        EXPECT_EQ(grid->GetCellType(c), VTK_TETRA);
        EXPECT_EQ(zone->GetTuple1(c), c + 1);
        EXPECT_EQ(block_id->GetTuple1(c), 2);
        EXPECT_EQ(state->GetTuple1(c), m.zones.state[c]);
        // The tensor VTK builds from the six components is the zone's stress.
        double six[6], t[9];
        stress->GetTuple(c, six);
        vtkMath::TensorFromSymmetricTensor(six, t);
        const Sym6& z = m.zones.stress[c];
        const double expected[9] = {z[0], z[3], z[4], z[3], z[1], z[5], z[4], z[5], z[2]};
        for (int k = 0; k < 9; ++k) EXPECT_EQ(t[k], expected[k]) << k;
        Vec3 p;
        principal_stresses(z, p);
        EXPECT_EQ(smin->GetTuple1(c), p[0]);
        EXPECT_EQ(smid->GetTuple1(c), p[1]);
        EXPECT_EQ(smax->GetTuple1(c), p[2]);
        EXPECT_LE(p[0], p[1]);
        EXPECT_LE(p[1], p[2]);
        // Corners at the gridpoints' current positions, in VTK's order (positive volume).
        vtkCell* cell = grid->GetCell(c);
        double x[4][3];
        for (int k = 0; k < 4; ++k) {
            const int gp = static_cast<int>(number->GetTuple1(cell->GetPointId(k))) - 1;
            EXPECT_EQ(gp, m.zones.gp[c][k]);
            grid->GetPoint(cell->GetPointId(k), x[k]);
            EXPECT_EQ(Vec3(x[k][0], x[k][1], x[k][2]), m.gridpoints.pos[m.zones.gp[c][k]]);
        }
        EXPECT_GT(vtkTetra::ComputeVolume(x[0], x[1], x[2], x[3]), 0);
    }
    // The stress of the zone set apart, component by component, in VTK's order.
    EXPECT_EQ(stress->GetComponent(4, 0), 5e5);
    EXPECT_EQ(stress->GetComponent(4, 3), -4e4);  // xy
    EXPECT_EQ(stress->GetComponent(4, 4), -8e4);  // yz
    EXPECT_EQ(stress->GetComponent(4, 5), 6e4);   // xz
    EXPECT_EQ(stress->GetComponent(0, 2), -3e6);
    EXPECT_EQ(state->GetTuple1(4), kShearNow | kShearPast);
    // Displacements and velocities of the gridpoints, exactly.
    for (int i = 0; i < 8; ++i) {
        const int gp = static_cast<int>(number->GetTuple1(i)) - 1;
        ASSERT_GE(gp, 0);
        ASSERT_LT(gp, 8);
        const Vec3 v = gridpoint_velocity_at_t(m, gp);
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(disp->GetComponent(i, k), m.gridpoints.disp[gp][k]);
            EXPECT_EQ(vel->GetComponent(i, k), v[k]);
        }
    }
    EXPECT_EQ(disp->GetComponent(7, 2), -3e-4 * 7 * 7);

    // The blocks file: the rigid brick as before, the deformable one's corners at and with
    // the motion of their gridpoints.
    vtkNew<vtkXMLUnstructuredGridReader> blocks;
    blocks->SetFileName(written[0].c_str());
    blocks->Update();
    vtkUnstructuredGrid* bg = blocks->GetOutput();
    ASSERT_EQ(bg->GetNumberOfCells(), 2);
    vtkDataArray* pdisp = bg->GetPointData()->GetArray("displacement");
    ASSERT_TRUE(pdisp);
    for (int v = 0; v < 8; ++v) {
        const int gp = m.blocks.corner_gp[1][v];
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(pdisp->GetComponent(8 + v, k), m.gridpoints.disp[gp][k]);
            EXPECT_EQ(pdisp->GetComponent(v, k), 0.0); // the rigid brick has not moved
        }
    }

    // Zones of an excavated block are left out: no zones file.
    m.blocks.flags[1] |= kExcavated;
    ASSERT_TRUE(export_vtk(m, nullptr, stem, written, error)) << error;
    EXPECT_EQ(written.size(), 2u);
}

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
    // Its displacement is exact for the block's turn (0.001 rad about x since 'reset disp'): where
    // the vertex is less where it was; the cell's rotation is that turn as a rotation vector.
    vtkDataArray* rot = grid->GetCellData()->GetArray("rotation");
    ASSERT_TRUE(rot);
    const Vec3 was = m.blocks.centroid[5] - m.blocks.disp[5] + Eigen::AngleAxisd(-0.001, Vec3::UnitX()) * r;
    const Vec3 moved = w.vertices[0] - was;
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(pdisp->GetComponent(5 * 8, k), moved[k], 1e-15);
        EXPECT_NEAR(rot->GetComponent(5, k), k == 0 ? 0.001 : 0.0, 1e-15);
    }

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
