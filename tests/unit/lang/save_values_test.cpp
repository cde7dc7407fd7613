// A save file whose payload was edited and its checksum recomputed passes every test of
// damage; what it holds must then be checked as carefully as typed input. Chosen edits
// (inf, NaN, negative densities, dangling indices, inconsistent counts, non-unit quaternions,
// repeated ids, tables whose x does not increase) are each refused with a clear message and
// the model kept, and save refuses such a model with the same message; a thousand random edits
// each either are refused or restore a model whose every number is finite, whose arrays agree,
// and which saves and round-trips bit for bit.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "engine/cycle.h"
#include "io/save.h"
#include "test_util.h"

using odec::test::read_bytes;
using odec::test::Session;
using odec::test::write_bytes;

namespace {

const char* kColumn =
    "poly brick -1 2 -1 2 -1 0\n"
    "poly brick 0 1 0 1 0 1\n"
    "poly brick 0 1 0 1 1 2\n"
    "poly brick 0.1 1.1 0 1 2 3\n"
    "prop mat=1 dens=2000\n"
    "prop jmat=1 jkn=1e7 jks=1e7 jfric=30\n"
    "grav 0 0 -10\n"
    "fix range z -1 0\n"
    "table 1 0 0 1 1\n"
    "hist ncyc 7\n"
    "hist zdis 0.5 0.5 2.5\n"
    "hist unbal\n"
    "step 30\n";

// A deformable cube of Mohr-Coulomb zones on a held base, loaded on its top, with histories
// of a gridpoint, a zone and a reaction.
const char* kZonedCube =
    "poly brick 0 1 0 1 0 1\n"
    "prop mat=1 dens=2500 ymod=10e9 prat=0.25 coh=3e5 fric=30 ten=1e5\n"
    "change cons=2\n"
    "gen edge 0.3\n"
    "grav 0 0 -10\n"
    "bound zvel 0 range z -0.001 0.001\n"
    "bound stress 0 0 -1e6 0 0 0 range z 0.999 1.001\n"
    "hist ncyc 5\n"
    "hist zdis 0.5 0.5 1\n"
    "hist szz 0.5 0.5 0.5\n"
    "hist zreaction range z -0.001 0.001\n"
    "step 20\n";


std::uint64_t fnv1a64(const char* p, size_t n) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < n; ++i) {
        h ^= static_cast<unsigned char>(p[i]);
        h *= 0x100000001b3ull;
    }
    return h;
}

// Where the payload of a save file begins: after the magic, the format, the program version
// and the payload length (src/io/save.cpp).
size_t payload_start(const std::string& file) {
    std::uint64_t n = 0;
    std::memcpy(&n, file.data() + 12 + 4, 8);
    return 12 + 4 + 8 + static_cast<size_t>(n) + 8;
}

// The file's checksum made right again after an edit.
void recompute_checksum(std::string& file) {
    const std::uint64_t h = fnv1a64(file.data(), file.size() - 8);
    std::memcpy(&file[file.size() - 8], &h, 8);
}

std::string profile_free_bytes(const odec::Model& m, const std::string& path) {
    odec::Model copy = m;
    copy.profile = odec::Profile();
    std::string error;
    EXPECT_TRUE(odec::save_model_unchecked(copy, path, error)) << error;
    return read_bytes(path);
}

// Every number of a model finite, and its arrays of agreeing lengths.
std::string model_problem(const odec::Model& m) {
    using namespace odec;
    auto fin = [](double x) { return std::isfinite(x); };
    const BlockSet& s = m.blocks;
    const size_t n = s.id.size();
    if (s.centroid.size() != n || s.vel.size() != n || s.mass.size() != n || s.shape.size() != n ||
        s.orientation.size() != n || s.inertia_body.size() != n || s.flags.size() != n)
        return "block arrays";
    for (size_t b = 0; b < n; ++b) {
        for (const Vec3& v : s.shape[b].vertices)
            if (!v.allFinite()) return "vertex";
        for (int v : s.shape[b].face_vertices)
            if (v < 0 || v >= s.shape[b].n_vertices()) return "face vertex";
        if (!s.centroid[b].allFinite() || !s.vel[b].allFinite() || !s.ang_vel[b].allFinite() ||
            !s.orientation[b].coeffs().allFinite() || !s.force[b].allFinite() || !s.moment[b].allFinite() ||
            !s.disp[b].allFinite() || !s.ref_orientation[b].coeffs().allFinite() ||
            !fin(s.mass[b]) || !fin(s.volume[b]) || !s.inertia_body[b].allFinite() || !s.accel[b].allFinite())
            return "block numbers";
        for (const BlockLoad& l : s.loads[b])
            if (!l.lever.allFinite() || !l.force.allFinite() || !l.couple.allFinite()) return "block numbers";
    }
    for (const Vec3& v : s.world_vertices)
        if (!v.allFinite()) return "world vertex";
    const ContactSet& c = m.contacts;
    const size_t nc = c.block_a.size();
    if (c.block_b.size() != nc || c.normal_code.size() != nc || (nc > 0 && c.sub_offset.size() != nc + 1)) return "contact arrays";
    for (size_t k = 0; k < nc; ++k) {
        if (c.block_a[k] < 0 || c.block_b[k] >= static_cast<int>(n) || c.block_a[k] >= c.block_b[k]) return "contact blocks";
        if (!c.normal(k).allFinite() || !fin(c.gap[k])) return "contact numbers";
    }
    for (size_t k = 0; k < c.sub_code.size(); ++k) {
        if (!fin(c.sub_area[k]) || !fin(c.sub_un[k]) || !c.sub_ss[k].allFinite() ||
            !c.sub_us[k].allFinite() || !c.sub_point_local(k).allFinite())
            return "sub-contact numbers";
    }
    for (const Material& x : m.materials)
        if (!fin(x.density) || x.density < 0) return "density";
    for (const JointMaterial& x : m.joint_materials)
        if (!fin(x.kn) || !fin(x.ks) || x.kn < 0 || x.ks < 0) return "stiffness";
    if (!fin(m.time) || !fin(m.dt) || !m.gravity.allFinite() || !fin(m.settings.dtfrac) || !fin(m.settings.dt_fixed))
        return "model scalars";
    for (const History& h : m.histories.items) {
        // Its own samples from its first on, each a finite number.
        if (h.first < 0 || static_cast<size_t>(h.first) + h.values.size() != m.histories.sample_steps.size())
            return "history length";
        for (double v : h.values)
            if (!fin(v)) return "history value";
    }
    // Zones and gridpoints: every index in range, every number finite.
    const ZoneSet& z = m.zones;
    const GridpointSet& g = m.gridpoints;
    const int ng = g.size();
    if (z.block.size() != z.gp.size() || z.stress.size() != z.gp.size() || z.volume.size() != z.gp.size() ||
        z.model.size() != z.gp.size() || (!z.grad.empty() && z.grad.size() != z.gp.size()))
        return "zone arrays";
    if (g.vel.size() != g.pos.size() || g.mass.size() != g.pos.size() || g.force.size() != g.pos.size() ||
        g.block.size() != g.pos.size() || g.vel_bc.size() != g.pos.size() || g.ref.size() != g.pos.size())
        return "gridpoint arrays";
    for (int i = 0; i < z.size(); ++i) {
        for (int c : z.gp[i])
            if (c < 0 || c >= ng) return "zone corner";
        if (z.block[i] < 0 || z.block[i] >= static_cast<int>(n) || z.model[i] > 2) return "zone block or model";
        for (double x : z.stress[i])
            if (!fin(x)) return "zone stress";
    }
    for (const auto& gr : z.grad)
        for (double x : gr)
            if (!fin(x)) return "zone gradient";
    for (int i = 0; i < ng; ++i) {
        if (!g.pos[i].allFinite() || !g.vel[i].allFinite() || !g.force[i].allFinite() || !fin(g.mass[i]) ||
            g.mass[i] < 0)
            return "gridpoint numbers";
        if (g.block[i] < 0 || g.block[i] >= static_cast<int>(n)) return "gridpoint block";
    }
    for (size_t b = 0; b < n; ++b) {
        if (s.corner_gp.size() != n) return "corner arrays";
        if ((s.flags[b] & kDeformable) && static_cast<int>(s.corner_gp[b].size()) != s.shape[b].n_vertices())
            return "corner count";
        for (int c : s.corner_gp[b])
            if (c < 0 || c >= ng) return "block corner";
    }
    for (const BoundaryFace& f : m.stress_boundary.faces) {
        for (int c : f.gp)
            if (c < 0 || c >= ng) return "face corner";
        if (!f.force.allFinite()) return "face force";
    }
    for (const History& h : m.histories.items) {
        if (h.gridpoint < -2 || h.gridpoint >= ng || h.zone < -2 || h.zone >= z.size()) return "history index";
        for (int c : h.gridpoints)
            if (c < 0 || c >= ng) return "reaction gridpoint";
    }
    for (const auto& [number, t] : m.tables.tables) {
        for (size_t k = 0; k < t.points.size(); ++k) {
            if (!fin(t.points[k].first) || !fin(t.points[k].second)) return "table value";
            if (k > 0 && !(t.points[k].first > t.points[k - 1].first)) return "table order";
        }
    }
    return "";
}

class SaveValues : public ::testing::Test {
protected:
    std::string dir;
    void SetUp() override {
        // Memory-backed when there is one: the saves here are many and each is fsync-ed.
        const std::string base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        std::string tmpl = base + "/odec-save-values-XXXXXX";
        ASSERT_NE(mkdtemp(&tmpl[0]), nullptr);
        dir = tmpl;
    }
    void TearDown() override {
        for (const char* f : {"edit.sav", "good.sav", "before.check", "after.check"}) std::remove(at(f).c_str());
        rmdir(dir.c_str());
    }
    std::string at(const std::string& name) const { return dir + "/" + name; }

    void column(Session& s) { ASSERT_TRUE(s.run(kColumn)) << s.error(); }

    // `save` refuses the model with `what` and writes nothing; a file of it written anyway is
    // refused by `restore` with `what` too: the two share one validation.
    void saved_and_restored_refuse(const odec::Model& m, const std::string& what) {
        std::remove(at("edit.sav").c_str());
        std::string error;
        EXPECT_FALSE(odec::save_model(m, at("edit.sav"), error)) << "saved: " << what;
        EXPECT_NE(error.find("the model cannot be saved to '" + at("edit.sav") + "': "), std::string::npos) << error;
        EXPECT_NE(error.find(what), std::string::npos) << error;
        EXPECT_NE(error.find("; nothing was written"), std::string::npos) << error;
        EXPECT_NE(access(at("edit.sav").c_str(), F_OK), 0) << "a file was written";
        ASSERT_TRUE(odec::save_model_unchecked(m, at("edit.sav"), error)) << error;
        refused(at("edit.sav"), what);
    }

    // Restoring `file` into a session holding the column fails with `what`, and the model
    // is kept bit for bit.
    void refused(const std::string& file, const std::string& what) {
        Session s;
        column(s);
        const std::string before = profile_free_bytes(s.model, at("before.check"));
        EXPECT_FALSE(s.run("restore '" + file + "'")) << "accepted: " << what;
        EXPECT_NE(s.error().find(what), std::string::npos) << s.error();
        EXPECT_NE(s.error().find("t.dat:1:9: error: cannot restore '" + file + "': the file is damaged or was written wrongly"),
                  std::string::npos)
            << s.error();
        EXPECT_EQ(profile_free_bytes(s.model, at("after.check")), before) << "the model changed";
    }
};

} // namespace

TEST_F(SaveValues, EditedFieldsAreEachRefusedAndTheModelKept) {
    Session a;
    column(a);
    ASSERT_GE(a.model.contacts.size(), 3);
    ASSERT_GE(a.model.histories.sample_steps.size(), 2u);
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    struct Edit {
        const char* what;
        std::function<void(odec::Model&)> apply;
    };
    const std::vector<Edit> edits = {
        {"material 1: the density is not a finite number", [&](odec::Model& m) { m.materials[1].density = inf; }},
        {"material 1: the density is -1, below 0", [](odec::Model& m) { m.materials[1].density = -1; }},
        {"joint material 1: the normal stiffness is not a finite number", [&](odec::Model& m) { m.joint_materials[1].kn = nan; }},
        {"joint material 1: the shear stiffness is -5, below 0", [](odec::Model& m) { m.joint_materials[1].ks = -5; }},
        {"joint material 1: the friction angle is 95 degrees", [](odec::Model& m) { m.joint_materials[1].friction = 95; }},
        {"dtfrac is outside (0, 1]", [](odec::Model& m) { m.settings.dtfrac = 0; }},
        {"dtfrac is outside (0, 1]", [](odec::Model& m) { m.settings.dtfrac = 2; }},
        {"dtfrac is not a finite number", [&](odec::Model& m) { m.settings.dtfrac = nan; }},
        {"the forced timestep is not a finite number", [&](odec::Model& m) { m.settings.dt_fixed = inf; }},
        {"the model time is not a finite number", [&](odec::Model& m) { m.time = nan; }},
        {"the timestep is -1, below 0", [](odec::Model& m) { m.dt = -1; }},
        {"gravity is not a finite number", [&](odec::Model& m) { m.gravity.z() = -inf; }},
        {"the local damping is outside [0, 1)", [](odec::Model& m) { m.damping.local = 1.5; }},
        {"block 2: the centroid is not a finite number", [&](odec::Model& m) { m.blocks.centroid[1].x() = nan; }},
        {"block 3: the velocity is not a finite number", [&](odec::Model& m) { m.blocks.vel[2].z() = inf; }},
        {"block 2: the orientation is not a unit quaternion", [](odec::Model& m) { m.blocks.orientation[1].w() = 2; }},
        {"block 1: vertex 3 is not a finite number", [&](odec::Model& m) { m.blocks.shape[0].vertices[2].y() = nan; }},
        {"block 2: the volume is not positive", [](odec::Model& m) { m.blocks.volume[1] = 0; }},
        {"block 2: the mass is not a finite number", [&](odec::Model& m) { m.blocks.mass[1] = inf; }},
        {"block 4: the inertia is not a finite number", [&](odec::Model& m) { m.blocks.inertia_body[3](1, 1) = nan; }},
        {"the block ids are not unique", [](odec::Model& m) { m.blocks.id[2] = m.blocks.id[1]; }},
        {"the block ids are not unique", [](odec::Model& m) { m.blocks.id[3] = m.next_block_id + 5; }},
        {"block 2: the material number is out of range", [](odec::Model& m) { m.blocks.material[1] = -3; }},
        {"the world vertex offsets do not match the block shapes", [](odec::Model& m) { m.blocks.vertex_offset[1] += 1; }},
        {"block 2 has a face vertex out of range", [](odec::Model& m) { m.blocks.shape[1].face_vertices[0] = 99; }},
        {"the faces of block 3 are wrong", [](odec::Model& m) { m.blocks.shape[2].face_offsets[1] = -1; }},
        {"the sub-contact offsets are wrong",
         [](odec::Model& m) { std::swap(m.contacts.sub_offset[1], m.contacts.sub_offset[2]); }},
        {"the sub-contact arrays differ in length", [](odec::Model& m) { m.contacts.sub_area.pop_back(); }},
        {"refers to a block that does not exist", [](odec::Model& m) { m.contacts.block_b[0] = 99; }},
        {"its blocks are not in order (a < b)", [](odec::Model& m) { std::swap(m.contacts.block_a[0], m.contacts.block_b[0]); }},
        {"the normal's code is out of range", [](odec::Model& m) { m.contacts.normal_code[1].u = odec::kNormalCodeLimit + 1; }},
        {"a sub-contact area is not a finite number", [&](odec::Model& m) { m.contacts.sub_area[0] = nan; }},
        {"a normal closure is not a finite number", [&](odec::Model& m) { m.contacts.sub_un[2] = inf; }},
        {"two contacts have the same id", [](odec::Model& m) { m.contacts.id[1] = m.contacts.id[0]; }},
        {"a history's samples do not match the model's", [](odec::Model& m) { m.histories.items[0].values.push_back(1); }},
        {"a history's samples do not match the model's", [](odec::Model& m) { m.histories.items[1].values.pop_back(); }},
        {"a history's samples do not match the model's", [](odec::Model& m) { m.histories.items[1].first = -1; }},
        {"a history's samples do not match the model's", [](odec::Model& m) { m.histories.items[0].first = 1; }},
        {"block 2: the orientation at the last 'reset disp' is not a unit quaternion",
         [](odec::Model& m) { m.blocks.ref_orientation[1].coeffs() *= 1.5; }},
        {"history 2: a value is not a finite number", [&](odec::Model& m) { m.histories.items[1].values[1] = nan; }},
        {"history 2: a value is not a finite number", [&](odec::Model& m) { m.histories.items[1].values[0] = inf; }},
        {"history 1: a value is not a finite number", [&](odec::Model& m) {
             m.histories.items[0].values[0] = nan; // leading NaNs too: the samples are its own
         }},
        {"the step number is 1000000000000000001, outside 0 to 1e18", [](odec::Model& m) { m.step = odec::kMaxStep + 1; }},
        {"the step number is -1, outside 0 to 1e18", [](odec::Model& m) { m.step = -1; }},
        {"the history sample steps do not increase",
         [](odec::Model& m) { std::swap(m.histories.sample_steps[0], m.histories.sample_steps[1]); }},
        {"the history interval is below 1", [](odec::Model& m) { m.histories.ncyc = 0; }},
        {"table 1: its x values do not increase", [](odec::Model& m) { m.tables.tables[1].points[1].first = 0; }},
        {"table 1: a y is not a finite number", [&](odec::Model& m) { m.tables.tables[1].points[0].second = inf; }},
        {"a detection orientation is not a unit quaternion",
         [](odec::Model& m) { m.contacts.ref_orientation[0].coeffs().setZero(); }},
    };
    for (const Edit& e : edits) {
        SCOPED_TRACE(e.what);
        odec::Model m = a.model;
        e.apply(m);
        saved_and_restored_refuse(m, e.what);
    }
}

TEST_F(SaveValues, ADoubleEditedInThePayloadWithItsChecksumIsRefused) {
    // The same as above, done to the bytes: the density of material 1 made infinite.
    Session a;
    column(a);
    ASSERT_TRUE(a.run("save '" + at("good.sav") + "'")) << a.error();
    std::string file = read_bytes(at("good.sav"));
    const double rho = 2000;
    const size_t start = payload_start(file);
    size_t at_rho = std::string::npos;
    for (size_t p = start; p + 8 <= file.size() - 8; ++p) {
        if (std::memcmp(file.data() + p, &rho, 8) == 0) {
            at_rho = p;
            break;
        }
    }
    ASSERT_NE(at_rho, std::string::npos);
    const double inf = std::numeric_limits<double>::infinity();
    std::memcpy(&file[at_rho], &inf, 8);
    recompute_checksum(file);
    write_bytes(at("edit.sav"), file);
    refused(at("edit.sav"), "material 1: the density is not a finite number");
}

// Bytes as the save file writes them: a length, then each element (ints in four bytes).
template <class V>
std::string file_bytes(const V& v) {
    using T = typename V::value_type;
    std::string out(8, '\0');
    const std::uint64_t n = v.size();
    std::memcpy(&out[0], &n, 8);
    for (const T& x : v) {
        const auto y = static_cast<std::conditional_t<sizeof(T) == 8, std::int64_t, std::int32_t>>(x);
        out.append(reinterpret_cast<const char*>(&y), sizeof y);
    }
    return out;
}

TEST_F(SaveValues, ASubContactsContactOrVertexEditedInThePayloadIsRefused) {
    // Neither is kept in memory (they follow from the offsets and the key), but the file has
    // them: one that disagrees is damage.
    Session a;
    column(a);
    const odec::ContactSet& c = a.model.contacts;
    ASSERT_GE(c.size(), 2);
    ASSERT_GT(c.sub_offset[1], 0); // the first sub-contact is contact 0's
    ASSERT_TRUE(a.run("save '" + at("good.sav") + "'")) << a.error();
    const std::string good = read_bytes(at("good.sav"));
    std::vector<int> owner, vertex;
    for (int k = 0; k < c.n_subs(); ++k) {
        owner.push_back(c.sub_owner(k));
        vertex.push_back(c.sub_vertex(k));
    }
    {
        // The offsets, then the contact of each sub-contact.
        const std::string pattern = file_bytes(c.sub_offset) + file_bytes(owner);
        const size_t at_owner = good.find(pattern, payload_start(good));
        ASSERT_NE(at_owner, std::string::npos);
        std::string file = good;
        const std::int32_t other = 1;
        std::memcpy(&file[at_owner + file_bytes(c.sub_offset).size() + 8], &other, 4);
        recompute_checksum(file);
        write_bytes(at("edit.sav"), file);
        refused(at("edit.sav"), "a sub-contact belongs to another contact");
    }
    {
        // The keys, then the vertex of each sub-contact.
        const std::string pattern = file_bytes(c.sub_keys()) + file_bytes(vertex);
        const size_t at_vertex = good.find(pattern, payload_start(good));
        ASSERT_NE(at_vertex, std::string::npos);
        std::string file = good;
        const std::int32_t other = vertex[0] + 1;
        std::memcpy(&file[at_vertex + file_bytes(c.sub_keys()).size() + 8], &other, 4);
        recompute_checksum(file);
        write_bytes(at("edit.sav"), file);
        refused(at("edit.sav"), "a sub-contact vertex or gridpoint does not match its key");
    }
}

TEST_F(SaveValues, RandomEditsAreRefusedOrGiveAFiniteConsistentModel) {
    Session a;
    column(a);
    ASSERT_TRUE(a.run("save '" + at("good.sav") + "'")) << a.error();
    const std::string good = read_bytes(at("good.sav"));
    const size_t start = payload_start(good), end = good.size() - 8;
    ASSERT_LT(start + 64, end);
    std::mt19937_64 rng(20261123);
    const double nasty[] = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::quiet_NaN(), 1e308, -1e308, 0.0, -0.0, -1.0, 1e-310,
                            std::numeric_limits<double>::denorm_min()};
    const std::int32_t nasty_ints[] = {-1, 0, 1, 2, 3, 7, 1000, -2147483647 - 1, 2147483647};
    int refused_count = 0, accepted = 0;
    for (int i = 0; i < 1000; ++i) {
        std::string file = good;
        const size_t pos = start + rng() % (end - start - 8);
        switch (rng() % 4) {
        case 0: { // a double from the nasty list
            const double x = nasty[rng() % (sizeof nasty / sizeof nasty[0])];
            std::memcpy(&file[pos], &x, 8);
            break;
        }
        case 1: { // random bits
            const std::uint64_t x = rng();
            std::memcpy(&file[pos], &x, 8);
            break;
        }
        case 2: { // an integer (index, count, offset)
            const std::int32_t x = nasty_ints[rng() % (sizeof nasty_ints / sizeof nasty_ints[0])];
            std::memcpy(&file[pos], &x, 4);
            break;
        }
        default: { // a count (u64) or a small integer plus or minus one
            std::int32_t x;
            std::memcpy(&x, &file[pos], 4);
            x += (rng() % 2) ? 1 : -1;
            std::memcpy(&file[pos], &x, 4);
            break;
        }
        }
        recompute_checksum(file);
        write_bytes(at("edit.sav"), file);
        odec::Model m;
        std::string error;
        if (!odec::restore_model(at("edit.sav"), m, error)) {
            ++refused_count;
            EXPECT_NE(error.find("cannot restore"), std::string::npos) << error;
            continue;
        }
        ++accepted;
        const std::string problem = model_problem(m);
        EXPECT_EQ(problem, "") << "edit " << i << " at byte " << pos;
        if (!problem.empty()) continue;
        // What restore took, save takes, and it round-trips bit for bit.
        EXPECT_TRUE(odec::check_save_round_trip(m, dir, error)) << "edit " << i << " at byte " << pos << ": " << error;
        // What was accepted can be stepped on: it cycles or stops with a named reason.
        odec::CycleLimits lim;
        lim.max_steps = 3;
        odec::cycle(m, lim);
    }
    std::printf("random payload edits: %d refused, %d accepted\n", refused_count, accepted);
    EXPECT_GT(refused_count, 100);
}

TEST_F(SaveValues, EditedZoneFieldsAreEachRefusedAndTheModelKept) {
    Session a;
    ASSERT_TRUE(a.run(kZonedCube)) << a.error();
    const odec::Model& base = a.model;
    const int ng = base.gridpoints.size();
    const int nz = base.zones.size();
    ASSERT_GT(nz, 10);
    ASSERT_GT(base.stress_boundary.faces.size(), 1u);
    ASSERT_EQ(base.histories.items.size(), 3u);
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::string n_gp = std::to_string(ng);
    struct Edit {
        std::string what;
        std::function<void(odec::Model&)> apply;
    };
    const std::vector<Edit> edits = {
        {"zone 4 has a corner at gridpoint " + n_gp + ", which does not exist",
         [&](odec::Model& m) { m.zones.gp[3][2] = ng; }},
        {"zone 2 has a corner at gridpoint -1, which does not exist", [](odec::Model& m) { m.zones.gp[1][0] = -1; }},
        {"zone 1 has gridpoint", [](odec::Model& m) { m.zones.gp[0][3] = m.zones.gp[0][1]; }},
        {"zone 3: its model is 3 (0 to 2 allowed)", [](odec::Model& m) { m.zones.model[2] = 3; }},
        {"zone 5: its state is out of range", [](odec::Model& m) { m.zones.state[4] = 16; }},
        {"zone 5: the stress is not a finite number", [&](odec::Model& m) { m.zones.stress[4][5] = nan; }},
        {"zone 2: the volume is not a finite number", [&](odec::Model& m) { m.zones.volume[1] = inf; }},
        {"which is not a deformable block", [](odec::Model& m) { m.zones.block[0] = 7; }},
        {"the zone arrays differ in length", [](odec::Model& m) { m.zones.grad.pop_back(); }},
        {"the zone arrays differ in length", [](odec::Model& m) { m.zones.state.push_back(0); }},
        {"zone 3: a shape-function gradient is not a finite number", [&](odec::Model& m) { m.zones.grad[2][7] = inf; }},
        {"the gridpoint arrays differ in length", [](odec::Model& m) { m.gridpoints.nmd_rate.pop_back(); }},
        {"gridpoint 3: the position is not a finite number", [&](odec::Model& m) { m.gridpoints.pos[2].z() = nan; }},
        {"gridpoint 2: the velocity is not a finite number", [&](odec::Model& m) { m.gridpoints.vel[1].x() = -inf; }},
        {"gridpoint 1: the mass is -1, below 0", [](odec::Model& m) { m.gridpoints.mass[0] = -1; }},
        {"gridpoint 4: a flag is out of range", [](odec::Model& m) { m.gridpoints.vel_bc[3] = 8; }},
        {"gridpoint 1 belongs to block index 1, which is not a deformable block",
         [](odec::Model& m) { m.gridpoints.block[0] = 1; }},
        {"block 1 is deformable but has 7 corner gridpoints for 8 vertices",
         [](odec::Model& m) { m.blocks.corner_gp[0].pop_back(); }},
        {"block 1 has a corner at gridpoint " + n_gp + ", which does not exist",
         [&](odec::Model& m) { m.blocks.corner_gp[0][5] = ng; }},
        {"block 1 is deformable but belongs to no continuum", [](odec::Model& m) { m.blocks.body[0] = 0; }},
        {"block 1: its zone model is 9 (0 to 2 allowed)", [](odec::Model& m) { m.blocks.cons[0] = 9; }},
        {"block 1: its continuum number is out of range", [](odec::Model& m) { m.blocks.body[0] = 2147483647; }},
        {"block 1: its zone edge is not a finite number", [&](odec::Model& m) { m.blocks.zone_edge[0] = nan; }},
        {"block 1: its zone edge is -0.5, below 0", [](odec::Model& m) { m.blocks.zone_edge[0] = -0.5; }},
        {"block 1 is rigid but has corner gridpoints",
         [](odec::Model& m) { m.blocks.flags[0] &= static_cast<std::uint8_t>(~odec::kDeformable); }},
        {"the block arrays differ in length", [](odec::Model& m) { m.blocks.body.push_back(1); }},
        {"the block arrays differ in length", [](odec::Model& m) { m.blocks.clump.pop_back(); }},
        {"clump 5: block 1 is deformable", [](odec::Model& m) { m.blocks.clump[0] = 5; }},
        {"clump -2: its name is out of range", [](odec::Model& m) { m.blocks.clump[0] = -2; }},
        {"a face loaded by 'bound stress' has a corner at a gridpoint that does not exist",
         [&](odec::Model& m) { m.stress_boundary.faces[1].gp[2] = ng + 3; }},
        {"a face loaded by 'bound stress' does not have three distinct corners",
         [](odec::Model& m) { m.stress_boundary.faces[0].gp[1] = m.stress_boundary.faces[0].gp[0]; }},
        {"the force on a face loaded by 'bound stress' is not a finite number",
         [&](odec::Model& m) { m.stress_boundary.faces[0].force.z() = nan; }},
        {"a history refers to gridpoint -7, which does not exist", [](odec::Model& m) { m.histories.items[0].gridpoint = -7; }},
        {"a history refers to gridpoint " + n_gp + ", which does not exist",
         [&](odec::Model& m) { m.histories.items[0].gridpoint = ng; }},
        {"a history refers to zone -3, which does not exist", [](odec::Model& m) { m.histories.items[1].zone = -3; }},
        {"a history refers to zone " + std::to_string(nz) + ", which does not exist",
         [&](odec::Model& m) { m.histories.items[1].zone = nz; }},
        {"a reaction history refers to gridpoint -1, which does not exist",
         [](odec::Model& m) { m.histories.items[2].gridpoints[0] = -1; }},
        {"a reaction history refers to gridpoint " + n_gp + ", which does not exist",
         [&](odec::Model& m) { m.histories.items[2].gridpoints.back() = ng; }},
    };
    for (const Edit& e : edits) {
        SCOPED_TRACE(e.what);
        odec::Model m = a.model;
        e.apply(m);
        saved_and_restored_refuse(m, e.what);
    }
    // The unedited file is taken.
    std::string error;
    odec::Model m;
    ASSERT_TRUE(odec::save_model(a.model, at("edit.sav"), error)) << error;
    EXPECT_TRUE(odec::restore_model(at("edit.sav"), m, error)) << error;
}

TEST_F(SaveValues, RandomEditsOfAZonedFileAreRefusedOrGiveAFiniteConsistentModel) {
    Session a;
    ASSERT_TRUE(a.run(kZonedCube)) << a.error();
    ASSERT_TRUE(a.run("save '" + at("good.sav") + "'")) << a.error();
    const std::string good = read_bytes(at("good.sav"));
    // Edits in the zone, gridpoint and loaded-face sections, where the new fields are.
    const size_t start = good.find("ZONE", payload_start(good)), end = good.find("CONT", start);
    ASSERT_NE(start, std::string::npos);
    ASSERT_NE(end, std::string::npos);
    ASSERT_LT(start + 64, end);
    std::mt19937_64 rng(20261124);
    const double nasty[] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(),
                            1e308, -1e308, 0.0, -1.0};
    const std::int32_t nasty_ints[] = {-1, 0, 1, 3, 1000, -2147483647 - 1, 2147483647};
    int refused_count = 0, accepted = 0;
    for (int i = 0; i < 300; ++i) {
        std::string file = good;
        const size_t pos = start + rng() % (end - start - 8);
        switch (rng() % 3) {
        case 0: {
            const double x = nasty[rng() % (sizeof nasty / sizeof nasty[0])];
            std::memcpy(&file[pos], &x, 8);
            break;
        }
        case 1: {
            const std::int32_t x = nasty_ints[rng() % (sizeof nasty_ints / sizeof nasty_ints[0])];
            std::memcpy(&file[pos], &x, 4);
            break;
        }
        default: {
            std::int32_t x;
            std::memcpy(&x, &file[pos], 4);
            x += (rng() % 2) ? 1 : -1;
            std::memcpy(&file[pos], &x, 4);
            break;
        }
        }
        recompute_checksum(file);
        write_bytes(at("edit.sav"), file);
        odec::Model m;
        std::string error;
        if (!odec::restore_model(at("edit.sav"), m, error)) {
            ++refused_count;
            EXPECT_NE(error.find("cannot restore"), std::string::npos) << error;
            continue;
        }
        ++accepted;
        const std::string problem = model_problem(m);
        EXPECT_EQ(problem, "") << "edit " << i << " at byte " << pos;
        if (!problem.empty()) continue;
        // What restore took, save takes, and it round-trips bit for bit.
        EXPECT_TRUE(odec::check_save_round_trip(m, dir, error)) << "edit " << i << " at byte " << pos << ": " << error;
        odec::CycleLimits lim;
        lim.max_steps = 3;
        odec::cycle(m, lim);
    }
    std::printf("random zone-section edits: %d refused, %d accepted\n", refused_count, accepted);
    EXPECT_GT(refused_count, 25);
}
