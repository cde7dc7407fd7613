#include "io/vtk_export.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "engine/blocks.h"
#include "io/files.h"
#include "engine/zones.h"

namespace odec {

namespace {

// Shortest text that reads back as the same double.
void put_number(std::string& out, double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    out += buf;
}

void put_int(std::string& out, long v) { out += std::to_string(v); }

std::string xml_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

bool write_atomically(const std::string& path, const std::string& text, std::string& error) {
    const std::string tmp = path + ".tmp" + std::to_string(static_cast<long>(getpid()));
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) {
            error = "cannot write '" + path + "'";
            return false;
        }
        f.write(text.data(), static_cast<std::streamsize>(text.size()));
        f.close();
        if (!f) {
            std::remove(tmp.c_str());
            error = "cannot write '" + path + "' (disk full?)";
            return false;
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        error = "cannot rename the temporary file to '" + path + "'";
        return false;
    }
    return true;
}

void put_array(std::string& out, const VtkArray& a) {
    out += "        <DataArray type=\"";
    out += a.integer ? "Int32" : "Float64";
    out += "\" Name=\"" + xml_escape(a.name) + "\"";
    if (a.n_components != 1) out += " NumberOfComponents=\"" + std::to_string(a.n_components) + "\"";
    for (size_t k = 0; k < a.component_names.size(); ++k) {
        out += " ComponentName" + std::to_string(k) + "=\"" + xml_escape(a.component_names[k]) + "\"";
    }
    out += " format=\"ascii\">\n";
    for (size_t i = 0; i < a.values.size(); ++i) {
        if (a.integer)
            put_int(out, static_cast<long>(a.values[i]));
        else
            put_number(out, a.values[i]);
        out += (i + 1) % static_cast<size_t>(std::max(3, a.n_components)) == 0 ? '\n' : ' ';
    }
    out += "\n        </DataArray>\n";
}

template <class T>
void put_int_array(std::string& out, const char* type, const char* name, const std::vector<T>& v) {
    out += std::string("        <DataArray type=\"") + type + "\" Name=\"" + name + "\" format=\"ascii\">\n";
    for (size_t i = 0; i < v.size(); ++i) {
        put_int(out, static_cast<long>(v[i]));
        out += (i + 1) % 12 == 0 ? '\n' : ' ';
    }
    out += "\n        </DataArray>\n";
}

// Model time and step, which ParaView shows with the data.
void put_field_data(std::string& out, const Model& m) {
    out += "    <FieldData>\n";
    out += "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
    put_number(out, m.time);
    out += "</DataArray>\n";
    out += "      <DataArray type=\"Int64\" Name=\"Step\" NumberOfTuples=\"1\" format=\"ascii\">";
    put_int(out, m.step);
    out += "</DataArray>\n    </FieldData>\n";
}

// A list of names as a String array of FieldData (each name as its character codes, then 0),
// added to the FieldData section already written.
void add_string_field(std::string& out, const char* name, const std::vector<std::string>& strings) {
    std::string s = std::string("      <DataArray type=\"String\" Name=\"") + name + "\" NumberOfTuples=\"" +
                    std::to_string(strings.size()) + "\" format=\"ascii\">\n";
    for (const auto& str : strings) {
        for (unsigned char c : str) s += std::to_string(static_cast<int>(c)) + " ";
        s += "0\n";
    }
    s += "      </DataArray>\n";
    out.insert(out.rfind("    </FieldData>"), s);
}

void put_points(std::string& out, const std::vector<Vec3>& pts) {
    out += "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& p : pts) {
        put_number(out, p.x());
        out += ' ';
        put_number(out, p.y());
        out += ' ';
        put_number(out, p.z());
        out += '\n';
    }
    out += "        </DataArray>\n      </Points>\n";
}

void put_data_section(std::string& out, const char* tag, const std::vector<VtkArray>& arrays) {
    out += std::string("      <") + tag + ">\n";
    for (const auto& a : arrays) put_array(out, a);
    out += std::string("      </") + tag + ">\n";
}

VtkArray vector_array(const char* name, const std::vector<Vec3>& v) {
    VtkArray a;
    a.name = name;
    a.n_components = 3;
    a.values.reserve(3 * v.size());
    for (const Vec3& x : v) a.values.insert(a.values.end(), {x.x(), x.y(), x.z()});
    return a;
}

template <class T>
VtkArray scalar_array(const char* name, const std::vector<T>& v, bool integer) {
    VtkArray a;
    a.name = name;
    a.integer = integer;
    a.values.assign(v.begin(), v.end());
    return a;
}

std::string strip_extension(const std::string& name) {
    for (const char* ext : {".vtu", ".vtp", ".pvd", ".vtk"}) {
        const size_t n = std::string(ext).size();
        if (name.size() > n && name.compare(name.size() - n, n, ext) == 0) return name.substr(0, name.size() - n);
    }
    return name;
}

std::string base_name(const std::string& path) {
    const auto slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

struct PvdEntry {
    double timestep = 0;
    int part = 0;
    std::string file;
};

// Entries of an existing collection (one we wrote: one DataSet element per line). None when
// there is no such file; false with `error` when there is one that cannot be read as text (a
// named pipe, a directory, a huge file), which is refused rather than waited on or replaced.
bool read_pvd(const std::string& path, std::vector<PvdEntry>& entries, std::string& error) {
    entries.clear();
    struct stat st;
    if (::stat(path.c_str(), &st) != 0 && errno == ENOENT) return true;
    std::string text, why;
    if (!read_file_text(path, text, why)) {
        error = "cannot add to the collection '" + path + "': " + why;
        return false;
    }
    std::istringstream f(text);
    std::string line;
    auto attribute = [](const std::string& line, const std::string& key, std::string& value) {
        const auto at = line.find(" " + key + "=\"");
        if (at == std::string::npos) return false;
        const auto from = at + key.size() + 3;
        const auto to = line.find('"', from);
        if (to == std::string::npos) return false;
        value = line.substr(from, to - from);
        return true;
    };
    while (std::getline(f, line)) {
        if (line.find("<DataSet") == std::string::npos) continue;
        PvdEntry e;
        std::string ts, part, file;
        if (!attribute(line, "timestep", ts) || !attribute(line, "file", file)) continue;
        attribute(line, "part", part);
        e.timestep = std::strtod(ts.c_str(), nullptr);
        e.part = part.empty() ? 0 : std::atoi(part.c_str());
        e.file = file;
        entries.push_back(e);
    }
    return true;
}

} // namespace

VtkPolyhedronMesh blocks_mesh(const Model& m) {
    VtkPolyhedronMesh mesh;
    const BlockSet& bs = m.blocks;
    std::vector<double> block_id, material, group, region, disp_mag;
    std::vector<Vec3> disp, vel, rot, point_disp, point_vel;
    mesh.cell_offsets.push_back(0);
    for (int b = 0; b < bs.size(); ++b) {
        if (bs.flags[b] & kExcavated) continue;
        const Polyhedron shape = world_shape(m, b);
        const int base = static_cast<int>(mesh.points.size());
        Vec3 v = velocity_at_t(m, b);
        if (bs.flags[b] & kDeformable) {
            // Its corners are gridpoints: their own motion (the block's velocity is their mean,
            // velocity_at_t).
            const auto& corners = bs.corner_gp[b];
            for (size_t k = 0; k < corners.size(); ++k) {
                mesh.points.push_back(shape.vertices[k]);
                point_disp.push_back(m.gridpoints.disp[corners[k]]);
                point_vel.push_back(gridpoint_velocity_at_t(m, corners[k]));
            }
        } else {
            for (int k = 0; k < shape.n_vertices(); ++k) {
                const Vec3& x = shape.vertices[k];
                mesh.points.push_back(x);
                // A rigid block's motion at its vertex (its displacement exact for any rotation).
                point_disp.push_back(point_displacement(m, b, bs.shape[b].vertices[k]));
                point_vel.push_back(velocity_at_point(m, b, x - bs.centroid[b]));
            }
        }
        for (int f = 0; f < shape.n_faces(); ++f) {
            mesh.cell_faces.push_back(shape.face_size(f));
            for (int k = 0; k < shape.face_size(f); ++k) mesh.cell_faces.push_back(base + shape.face_vertex(f, k));
        }
        mesh.cell_offsets.push_back(static_cast<int>(mesh.cell_faces.size()));
        block_id.push_back(bs.id[b]);
        material.push_back(bs.material[b]);
        group.push_back(bs.group[b]);
        region.push_back(bs.region[b]);
        disp.push_back(bs.disp[b]);
        disp_mag.push_back(bs.disp[b].norm());
        vel.push_back(v);
        rot.push_back(rotation_since_reset(m, b)); // 0 for a deformable block (its gridpoints turn)
    }
    mesh.cell_data.push_back(scalar_array("block_id", block_id, true));
    mesh.cell_data.push_back(scalar_array("material", material, true));
    mesh.cell_data.push_back(scalar_array("group", group, true));
    mesh.cell_data.push_back(scalar_array("region", region, true));
    mesh.cell_data.push_back(vector_array("displacement", disp));
    mesh.cell_data.push_back(scalar_array("displacement_magnitude", disp_mag, false));
    mesh.cell_data.push_back(vector_array("velocity", vel));
    mesh.cell_data.push_back(vector_array("rotation", rot));
    mesh.point_data.push_back(vector_array("displacement", point_disp));
    mesh.point_data.push_back(vector_array("velocity", point_vel));
    return mesh;
}

bool write_vtu(const VtkPolyhedronMesh& mesh, const Model& m, const std::string& path, std::string& error) {
    const int n_cells = mesh.n_cells();
    std::string out;
    out.reserve(200 * mesh.points.size() + 1024);
    out += "<?xml version=\"1.0\"?>\n";
    out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out += "  <UnstructuredGrid>\n";
    put_field_data(out, m);
    // The names of the group numbers of the cell array 'group' (-1: none).
    if (!m.group_names.empty()) add_string_field(out, "group_names", m.group_names);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.points.size()) + "\" NumberOfCells=\"" +
           std::to_string(n_cells) + "\">\n";
    put_data_section(out, "PointData", mesh.point_data);
    put_data_section(out, "CellData", mesh.cell_data);
    put_points(out, mesh.points);

    // A polyhedron cell lists its points once in `connectivity` and its faces in `faces`.
    std::vector<long> connectivity, offsets, faces, face_offsets;
    std::vector<int> types(static_cast<size_t>(n_cells), 42); // VTK_POLYHEDRON
    for (int c = 0; c < n_cells; ++c) {
        const int from = mesh.cell_offsets[c], to = mesh.cell_offsets[c + 1];
        std::vector<int> ids;
        int n_faces = 0;
        for (int i = from; i < to;) {
            const int k = mesh.cell_faces[i];
            ids.insert(ids.end(), mesh.cell_faces.begin() + i + 1, mesh.cell_faces.begin() + i + 1 + k);
            i += k + 1;
            ++n_faces;
        }
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        connectivity.insert(connectivity.end(), ids.begin(), ids.end());
        offsets.push_back(static_cast<long>(connectivity.size()));
        faces.push_back(n_faces);
        faces.insert(faces.end(), mesh.cell_faces.begin() + from, mesh.cell_faces.begin() + to);
        face_offsets.push_back(static_cast<long>(faces.size()));
    }
    out += "      <Cells>\n";
    put_int_array(out, "Int64", "connectivity", connectivity);
    put_int_array(out, "Int64", "offsets", offsets);
    put_int_array(out, "UInt8", "types", types);
    put_int_array(out, "Int64", "faces", faces);
    put_int_array(out, "Int64", "faceoffsets", face_offsets);
    out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    return write_atomically(path, out, error);
}

VtkTetMesh zones_mesh(const Model& m) {
    VtkTetMesh mesh;
    const ZoneSet& z = m.zones;
    const GridpointSet& g = m.gridpoints;
    const BlockSet& bs = m.blocks;
    // Points: the gridpoints of the zones written, numbered in gridpoint order.
    std::vector<int> point_of(static_cast<size_t>(g.size()), -1);
    for (int i = 0; i < z.size(); ++i) {
        if (bs.flags[z.block[i]] & kExcavated) continue;
        for (int c : z.gp[i]) point_of[c] = 0;
    }
    std::vector<double> number;
    std::vector<Vec3> disp, vel;
    for (int i = 0; i < g.size(); ++i) {
        if (point_of[i] < 0) continue;
        point_of[i] = static_cast<int>(mesh.points.size());
        mesh.points.push_back(g.pos[i]);
        number.push_back(i + 1);
        disp.push_back(g.disp[i]);
        vel.push_back(gridpoint_velocity_at_t(m, i));
    }
    VtkArray stress;
    stress.name = "stress";
    stress.n_components = 6;
    stress.component_names = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
    std::vector<double> smin, smid, smax, state, model, block_id, zone;
    for (int i = 0; i < z.size(); ++i) {
        if (bs.flags[z.block[i]] & kExcavated) continue;
        const auto& q = z.gp[i];
        mesh.cells.push_back({point_of[q[0]], point_of[q[1]], point_of[q[2]], point_of[q[3]]});
        // Zones keep xx yy zz xy xz yz; VTK reads a symmetric tensor as xx yy zz xy yz xz.
        const Sym6& s = z.stress[i];
        stress.values.insert(stress.values.end(), {s[0], s[1], s[2], s[3], s[5], s[4]});
        Vec3 p;
        principal_stresses(s, p);
        smin.push_back(p[0]);
        smid.push_back(p[1]);
        smax.push_back(p[2]);
        state.push_back(z.state[i]);
        model.push_back(z.model[i]);
        block_id.push_back(bs.id[z.block[i]]);
        zone.push_back(i + 1);
    }
    mesh.cell_data.push_back(std::move(stress));
    mesh.cell_data.push_back(scalar_array("smin", smin, false));
    mesh.cell_data.push_back(scalar_array("smid", smid, false));
    mesh.cell_data.push_back(scalar_array("smax", smax, false));
    mesh.cell_data.push_back(scalar_array("state", state, true));
    mesh.cell_data.push_back(scalar_array("model", model, true));
    mesh.cell_data.push_back(scalar_array("block_id", block_id, true));
    mesh.cell_data.push_back(scalar_array("zone", zone, true));
    mesh.point_data.push_back(scalar_array("gridpoint", number, true));
    mesh.point_data.push_back(vector_array("displacement", disp));
    mesh.point_data.push_back(vector_array("velocity", vel));
    return mesh;
}

bool write_tet_vtu(const VtkTetMesh& mesh, const Model& m, const std::string& path, std::string& error) {
    const size_t n_cells = mesh.cells.size();
    std::string out;
    out.reserve(200 * mesh.points.size() + 400 * n_cells + 1024);
    out += "<?xml version=\"1.0\"?>\n";
    out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out += "  <UnstructuredGrid>\n";
    put_field_data(out, m);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.points.size()) + "\" NumberOfCells=\"" +
           std::to_string(n_cells) + "\">\n";
    put_data_section(out, "PointData", mesh.point_data);
    put_data_section(out, "CellData", mesh.cell_data);
    put_points(out, mesh.points);
    std::vector<long> connectivity, offsets;
    connectivity.reserve(4 * n_cells);
    for (const auto& c : mesh.cells) {
        connectivity.insert(connectivity.end(), c.begin(), c.end());
        offsets.push_back(static_cast<long>(connectivity.size()));
    }
    const std::vector<int> types(n_cells, 10); // VTK_TETRA
    out += "      <Cells>\n";
    put_int_array(out, "Int64", "connectivity", connectivity);
    put_int_array(out, "Int64", "offsets", offsets);
    put_int_array(out, "UInt8", "types", types);
    out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    return write_atomically(path, out, error);
}

std::vector<Vec3> contact_outline(const ContactRows& rows, const ContactRows& subs, const std::vector<int>& own,
                                  int i) {
    const Vec3 n = rows.normal[i].norm() > 0 ? Vec3(rows.normal[i].normalized()) : Vec3(Vec3::UnitZ());
    const Vec3 ref = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 e1 = (ref - ref.dot(n) * n).normalized(), e2 = n.cross(e1);
    const Vec3& c = rows.centroid[i];
    // The sub-contacts of this contact, in the plane of the contact.
    std::vector<std::pair<double, double>> uv;
    for (int k : own) {
        const Vec3 d = subs.centroid[k] - c;
        uv.emplace_back(e1.dot(d), e2.dot(d));
    }
    std::sort(uv.begin(), uv.end());
    uv.erase(std::unique(uv.begin(), uv.end()), uv.end());
    // Their convex hull (monotone chain), counter-clockwise about the normal.
    std::vector<std::pair<double, double>> hull;
    if (uv.size() >= 3) {
        auto cross = [](const auto& o, const auto& a, const auto& b) {
            return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first);
        };
        std::vector<std::pair<double, double>> h(2 * uv.size());
        size_t k = 0;
        for (size_t j = 0; j < uv.size(); ++j) {
            while (k >= 2 && cross(h[k - 2], h[k - 1], uv[j]) <= 0) --k;
            h[k++] = uv[j];
        }
        for (size_t j = uv.size() - 1, t = k + 1; j-- > 0;) {
            while (k >= t && cross(h[k - 2], h[k - 1], uv[j]) <= 0) --k;
            h[k++] = uv[j];
        }
        h.resize(k > 0 ? k - 1 : 0);
        hull = h;
    }
    std::vector<Vec3> out;
    if (hull.size() >= 3) {
        for (const auto& p : hull) out.push_back(c + p.first * e1 + p.second * e2);
    } else {
        // No outline to follow: a square of the contact's area, as 'plot contact' draws it
        // (a point, for a contact that touches nowhere).
        const double h = 0.5 * std::sqrt(std::max(rows.area[i], 0.0));
        out = {c - h * e1 - h * e2, c + h * e1 - h * e2, c + h * e1 + h * e2, c - h * e1 + h * e2};
    }
    return out;
}

bool write_contacts_vtp(const ContactRows& rows, const std::vector<std::string>& state_names, const Model& m,
                        const std::string& path, std::string& error, const ContactRows* outline) {
    if (!contact_rows_valid(rows, error)) return false;
    const int n = rows.size();
    std::vector<VtkArray> data;
    data.push_back(vector_array("normal", rows.normal));
    data.push_back(scalar_array("area", rows.area, false));
    if (!rows.block1.empty()) data.push_back(scalar_array("block1", rows.block1, true));
    if (!rows.block2.empty()) data.push_back(scalar_array("block2", rows.block2, true));
    if (!rows.normal_stress.empty()) data.push_back(scalar_array("normal_stress", rows.normal_stress, false));
    if (!rows.pore_pressure.empty()) data.push_back(scalar_array("pore_pressure", rows.pore_pressure, false));
    if (!rows.aperture.empty()) data.push_back(scalar_array("aperture", rows.aperture, false));
    if (!rows.shear_stress.empty()) {
        data.push_back(vector_array("shear_stress", rows.shear_stress));
        std::vector<double> mag;
        for (const Vec3& t : rows.shear_stress) mag.push_back(t.norm());
        data.push_back(scalar_array("shear_stress_magnitude", mag, false));
    }
    if (!rows.normal_disp.empty()) data.push_back(scalar_array("normal_closure", rows.normal_disp, false));
    if (!rows.shear_disp.empty()) {
        data.push_back(vector_array("shear_displacement", rows.shear_disp));
        std::vector<double> mag;
        for (const Vec3& t : rows.shear_disp) mag.push_back(t.norm());
        data.push_back(scalar_array("shear_displacement_magnitude", mag, false));
    }
    if (!rows.force.empty()) data.push_back(vector_array("force", rows.force));
    if (!rows.state.empty()) data.push_back(scalar_array("state", rows.state, true));
    if (!rows.parent.empty()) data.push_back(scalar_array("contact", rows.parent, true));

    std::string out;
    out += "<?xml version=\"1.0\"?>\n";
    out += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out += "  <PolyData>\n";
    put_field_data(out, m);
    // The names of the state numbers, for whoever reads the file.
    if (!state_names.empty()) add_string_field(out, "state_names", state_names);
    if (!outline) {
        // Points, one vertex cell each, the data on the points.
        out += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
               "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
        put_data_section(out, "PointData", data);
        put_points(out, rows.centroid);
        std::vector<long> conn(static_cast<size_t>(n)), offs(static_cast<size_t>(n));
        for (int i = 0; i < n; ++i) {
            conn[i] = i;
            offs[i] = i + 1;
        }
        out += "      <Verts>\n";
        put_int_array(out, "Int64", "connectivity", conn);
        put_int_array(out, "Int64", "offsets", offs);
        out += "      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
        return write_atomically(path, out, error);
    }
    // Patches: one polygon cell per contact, in contact order, the data on the cells.
    // The sub-contacts of each contact, found in one pass.
    std::vector<std::vector<int>> own(static_cast<size_t>(n));
    for (int k = 0; k < outline->size(); ++k) {
        if (k < static_cast<int>(outline->parent.size()) && outline->parent[k] >= 0 && outline->parent[k] < n) {
            own[outline->parent[k]].push_back(k);
        }
    }
    std::vector<Vec3> points;
    std::vector<long> conn, offs;
    for (int i = 0; i < n; ++i) {
        for (const Vec3& x : contact_outline(rows, *outline, own[i], i)) {
            conn.push_back(static_cast<long>(points.size()));
            points.push_back(x);
        }
        offs.push_back(static_cast<long>(conn.size()));
    }
    out += "    <Piece NumberOfPoints=\"" + std::to_string(points.size()) +
           "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(n) +
           "\">\n";
    put_data_section(out, "CellData", data);
    put_points(out, points);
    out += "      <Polys>\n";
    put_int_array(out, "Int64", "connectivity", conn);
    put_int_array(out, "Int64", "offsets", offs);
    out += "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    return write_atomically(path, out, error);
}

bool write_cables_vtp(const Model& m, const std::string& path, std::string& error) {
    const CableSet& cs = m.cables;
    const int nn = cs.n_nodes();
    // Points: the nodes, with their data.
    std::vector<double> node_no, host, grout, slip, gstate;
    for (int c = 0; c < cs.size(); ++c) {
        for (int i = cs.node_offset[c]; i < cs.node_offset[c + 1]; ++i) {
            node_no.push_back(i - cs.node_offset[c] + 1);
            host.push_back(cs.host_block[i]);
            grout.push_back(cs.grout_force[i]);
            slip.push_back(cs.slip[i]);
            gstate.push_back(cs.host_block[i] <= 0 ? -1 : (cs.state[i] & kGroutSlipNow) ? 1 : (cs.state[i] & kGroutSlipPast) ? 2 : 0);
        }
    }
    std::vector<VtkArray> point_data;
    point_data.push_back(scalar_array("node", node_no, true));
    point_data.push_back(vector_array("displacement", cs.disp));
    point_data.push_back(scalar_array("block_id", host, true));
    point_data.push_back(scalar_array("grout_force", grout, false));
    point_data.push_back(scalar_array("grout_slip", slip, false));
    point_data.push_back(scalar_array("grout_state", gstate, true));
    // Cells: the segments, one line each, with their data.
    std::vector<double> axial, yield, cable_id, seg_no;
    std::vector<long> conn, offs;
    for (int c = 0; c < cs.size(); ++c) {
        for (int k = 0; k < cs.segments_of(c); ++k) {
            const int seg = cs.first_segment(c) + k, i = cs.node_offset[c] + k;
            const std::uint8_t st = cs.seg_state[seg];
            axial.push_back(cs.axial[seg]);
            yield.push_back((st & kCableYieldTensionNow) ? 1 : (st & kCableYieldCompNow) ? 2 : (st & kCableYieldPast) ? 3 : 0);
            cable_id.push_back(cs.id[c]);
            seg_no.push_back(k + 1);
            conn.push_back(i);
            conn.push_back(i + 1);
            offs.push_back(static_cast<long>(conn.size()));
        }
    }
    std::vector<VtkArray> cell_data;
    cell_data.push_back(scalar_array("axial_force", axial, false));
    cell_data.push_back(scalar_array("yield_state", yield, true));
    cell_data.push_back(scalar_array("cable_id", cable_id, true));
    cell_data.push_back(scalar_array("segment", seg_no, true));
    std::string out;
    out += "<?xml version=\"1.0\"?>\n";
    out += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out += "  <PolyData>\n";
    put_field_data(out, m);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(nn) + "\" NumberOfVerts=\"0\" NumberOfLines=\"" +
           std::to_string(axial.size()) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
    put_data_section(out, "PointData", point_data);
    put_data_section(out, "CellData", cell_data);
    put_points(out, cs.pos);
    out += "      <Lines>\n";
    put_int_array(out, "Int64", "connectivity", conn);
    put_int_array(out, "Int64", "offsets", offs);
    out += "      </Lines>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    return write_atomically(path, out, error);
}

bool write_liners_vtp(const Model& m, const std::string& path, std::string& error) {
    const LinerSet& ls = m.liners;
    const int nn = ls.n_nodes();
    std::vector<double> node_no, host, bond_n, bond_s, bstate;
    for (int c = 0; c < ls.size(); ++c) {
        for (int i = ls.node_offset[c]; i < ls.node_offset[c + 1]; ++i) {
            node_no.push_back(i - ls.node_offset[c] + 1);
            host.push_back(ls.host_block[i]);
            bond_n.push_back(ls.bond_n[i]);
            bond_s.push_back(ls.bond_s[i].norm());
            bstate.push_back(ls.host_block[i] <= 0 ? -1 : ls.state[i]);
        }
    }
    std::vector<VtkArray> point_data;
    point_data.push_back(scalar_array("node", node_no, true));
    point_data.push_back(vector_array("displacement", ls.disp));
    point_data.push_back(scalar_array("block_id", host, true));
    point_data.push_back(scalar_array("bond_normal_force", bond_n, false));
    point_data.push_back(scalar_array("bond_shear_force", bond_s, false));
    point_data.push_back(scalar_array("bond_state", bstate, true));
    std::vector<double> nx, ny, nxy, mx, my, mxy, liner_id, el_no;
    std::vector<long> conn, offs;
    for (int c = 0; c < ls.size(); ++c) {
        for (int e = ls.elem_offset[c]; e < ls.elem_offset[c + 1]; ++e) {
            const LinerResultants r = liner_resultants(ls, e);
            nx.push_back(r.nx); ny.push_back(r.ny); nxy.push_back(r.nxy);
            mx.push_back(r.mx); my.push_back(r.my); mxy.push_back(r.mxy);
            liner_id.push_back(ls.id[c]);
            el_no.push_back(e - ls.elem_offset[c] + 1);
            for (int i : ls.elem[e]) conn.push_back(i);
            offs.push_back(static_cast<long>(conn.size()));
        }
    }
    std::vector<VtkArray> cell_data;
    cell_data.push_back(scalar_array("n_x", nx, false));
    cell_data.push_back(scalar_array("n_y", ny, false));
    cell_data.push_back(scalar_array("n_xy", nxy, false));
    cell_data.push_back(scalar_array("m_x", mx, false));
    cell_data.push_back(scalar_array("m_y", my, false));
    cell_data.push_back(scalar_array("m_xy", mxy, false));
    cell_data.push_back(scalar_array("liner_id", liner_id, true));
    cell_data.push_back(scalar_array("element", el_no, true));
    std::string out;
    out += "<?xml version=\"1.0\"?>\n";
    out += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out += "  <PolyData>\n";
    put_field_data(out, m);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(nn) +
           "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(nx.size()) +
           "\">\n";
    put_data_section(out, "PointData", point_data);
    put_data_section(out, "CellData", cell_data);
    put_points(out, ls.pos);
    out += "      <Polys>\n";
    put_int_array(out, "Int64", "connectivity", conn);
    put_int_array(out, "Int64", "offsets", offs);
    out += "      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    return write_atomically(path, out, error);
}

bool export_vtk(const Model& m, const ContactView* contacts, const std::string& name,
                std::vector<std::string>& written, std::string& error) {
    written.clear();
    const std::string stem = strip_extension(name);
    if (stem.empty() || stem.back() == '/') {
        error = "export vtk needs a file name";
        return false;
    }
    // The collection this export adds to, read before anything is written.
    const std::string pvd_path = stem + ".pvd";
    std::vector<PvdEntry> entries;
    if (!read_pvd(pvd_path, entries, error)) return false;
    char step[32];
    std::snprintf(step, sizeof step, "%06ld", m.step);
    struct Part {
        std::string path;
        int part;
    };
    std::vector<Part> parts;

    const std::string blocks_path = stem + "-blocks-" + step + ".vtu";
    if (!write_vtu(blocks_mesh(m), m, blocks_path, error)) return false;
    parts.push_back({blocks_path, 0});
    {
        const VtkTetMesh zones = zones_mesh(m);
        if (!zones.cells.empty()) {
            const std::string path = stem + "-zones-" + step + ".vtu";
            if (!write_tet_vtu(zones, m, path, error)) return false;
            parts.push_back({path, 3});
        }
    }
    if (m.cables.size() > 0) {
        const std::string path = stem + "-cables-" + step + ".vtp";
        if (!write_cables_vtp(m, path, error)) return false;
        parts.push_back({path, 4});
    }
    if (m.liners.size() > 0) {
        const std::string path = stem + "-liners-" + step + ".vtp";
        if (!write_liners_vtp(m, path, error)) return false;
        parts.push_back({path, 5});
    }
    if (contacts) {
        const std::string path = stem + "-contacts-" + step + ".vtp";
        if (!write_contacts_vtp(contacts->contacts, contacts->state_names, m, path, error, &contacts->sub_contacts)) {
            return false;
        }
        parts.push_back({path, 1});
        if (contacts->sub_contacts.size() > 0) {
            const std::string sub = stem + "-subcontacts-" + step + ".vtp";
            if (!write_contacts_vtp(contacts->sub_contacts, contacts->state_names, m, sub, error)) return false;
            parts.push_back({sub, 2});
        }
    }

    // The collection: earlier steps' entries stay, this step's replace any of the same file.
    // ParaView's time axis is the model time, in seconds (each file also carries it as
    // TimeValue, and its step as Step).
    for (const Part& p : parts) {
        const std::string file = base_name(p.path);
        entries.erase(std::remove_if(entries.begin(), entries.end(), [&](const PvdEntry& e) { return e.file == file; }),
                      entries.end());
        entries.push_back({m.time, p.part, file});
    }
    std::stable_sort(entries.begin(), entries.end(), [](const PvdEntry& a, const PvdEntry& b) {
        return a.timestep != b.timestep ? a.timestep < b.timestep : a.part < b.part;
    });
    std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                      "  <Collection>\n";
    for (const PvdEntry& e : entries) {
        std::string ts;
        put_number(ts, e.timestep);
        pvd += "    <DataSet timestep=\"" + ts + "\" group=\"\" part=\"" + std::to_string(e.part) + "\" file=\"" +
               xml_escape(e.file) + "\"/>\n";
    }
    pvd += "  </Collection>\n</VTKFile>\n";
    if (!write_atomically(pvd_path, pvd, error)) return false;
    for (const Part& p : parts) written.push_back(p.path);
    written.push_back(pvd_path);
    return true;
}

} // namespace odec
