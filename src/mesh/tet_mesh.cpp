#include "mesh/tet_mesh.h"
#include "mesh/tet_improve.h"
#include "engine/grid_cell.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <gmshc.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <type_traits>
#include <unordered_map>

// Gmsh sets up its global state once and keeps it for the life of the process; the leak checker
// of sanitizer builds would report it at exit.
#if defined(__SANITIZE_ADDRESS__)
#define ODEC_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ODEC_ASAN 1
#endif
#endif
#ifdef ODEC_ASAN
extern "C" const char* __lsan_default_suppressions() { return "leak:libgmsh.so\n"; }
#endif

namespace odec {

double radius_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Vec3 u = b - a, v = c - a, w = d - a;
    const double six_v = u.dot(v.cross(w));
    if (!(std::abs(six_v) > 0)) return 0;
    const double area = 0.5 * ((b - a).cross(c - a).norm() + (b - a).cross(d - a).norm() +
                               (c - a).cross(d - a).norm() + (c - b).cross(d - b).norm());
    const double r_in = 0.5 * std::abs(six_v) / area;  // 3 V / A
    const Vec3 o = (u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v)) /
                   (2.0 * six_v);
    const double r_out = o.norm();
    return r_out > 0 ? 3.0 * r_in / r_out : 0.0;
}

namespace {

// Zones of a radius ratio below this are improved after the mesher (mesh/tet_improve.h): a
// margin over the 0.1 'gen' reaches in blocks of ordinary shape. Gmsh's own optimizer
// (Mesh.Optimize, below) cannot: the slivers it leaves have all four corners on the surface.
constexpr double kImproveBelow = 0.2;

// Gmsh is opened when a block is first zoned, not when odec starts: it brings in some hundred
// shared libraries (its CAD kernels among them), which would triple the start-up time of
// every session and every script that never zones. Its C interface is looked up by name.
struct Gmsh {
    bool loaded = false;
    std::string why;  // when it could not be opened
    decltype(&gmshInitialize) initialize = nullptr;
    decltype(&gmshOptionSetNumber) set_number = nullptr;
    decltype(&gmshClear) clear = nullptr;
    decltype(&gmshModelAdd) model_add = nullptr;
    decltype(&gmshModelGeoAddPoint) add_point = nullptr;
    decltype(&gmshModelGeoAddLine) add_line = nullptr;
    decltype(&gmshModelGeoAddCurveLoop) add_curve_loop = nullptr;
    decltype(&gmshModelGeoAddPlaneSurface) add_plane_surface = nullptr;
    decltype(&gmshModelGeoAddSurfaceLoop) add_surface_loop = nullptr;
    decltype(&gmshModelGeoAddVolume) add_volume = nullptr;
    decltype(&gmshModelGeoSynchronize) synchronize = nullptr;
    decltype(&gmshModelMeshGenerate) generate = nullptr;
    decltype(&gmshModelMeshClear) mesh_clear = nullptr;
    decltype(&gmshModelMeshGetNodes) get_nodes = nullptr;
    decltype(&gmshModelMeshGetElementsByType) get_elements_by_type = nullptr;
    decltype(&gmshFree) free = nullptr;
    decltype(&gmshLoggerGetLastError) last_error = nullptr;
};

std::mutex gmsh_mutex;

template <class F>
bool find_symbol(void* lib, const char* name, F& f, std::string& why) {
    f = reinterpret_cast<F>(dlsym(lib, name));
    if (!f && why.empty()) why = std::string("the mesher library has no '") + name + "'";
    return f != nullptr;
}

Gmsh& gmsh_library() {
    static Gmsh g = [] {
        Gmsh r;
        void* lib = nullptr;
        for (const char* name : {"libgmsh.so.4.8", "libgmsh.so"}) {
            lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
            if (lib) break;
        }
        if (!lib) {
            r.why = "the mesher (Gmsh's library, libgmsh.so.4.8) cannot be opened: install Debian's libgmsh-dev "
                    "(tools/setup.sh does)";
            return r;
        }
        bool ok = find_symbol(lib, "gmshInitialize", r.initialize, r.why);
        ok &= find_symbol(lib, "gmshOptionSetNumber", r.set_number, r.why);
        ok &= find_symbol(lib, "gmshClear", r.clear, r.why);
        ok &= find_symbol(lib, "gmshModelAdd", r.model_add, r.why);
        ok &= find_symbol(lib, "gmshModelGeoAddPoint", r.add_point, r.why);
        ok &= find_symbol(lib, "gmshModelGeoAddLine", r.add_line, r.why);
        ok &= find_symbol(lib, "gmshModelGeoAddCurveLoop", r.add_curve_loop, r.why);
        ok &= find_symbol(lib, "gmshModelGeoAddPlaneSurface", r.add_plane_surface, r.why);
        ok &= find_symbol(lib, "gmshModelGeoAddSurfaceLoop", r.add_surface_loop, r.why);
        ok &= find_symbol(lib, "gmshModelGeoAddVolume", r.add_volume, r.why);
        ok &= find_symbol(lib, "gmshModelGeoSynchronize", r.synchronize, r.why);
        ok &= find_symbol(lib, "gmshModelMeshGenerate", r.generate, r.why);
        ok &= find_symbol(lib, "gmshModelMeshClear", r.mesh_clear, r.why);
        ok &= find_symbol(lib, "gmshModelMeshGetNodes", r.get_nodes, r.why);
        ok &= find_symbol(lib, "gmshModelMeshGetElementsByType", r.get_elements_by_type, r.why);
        ok &= find_symbol(lib, "gmshFree", r.free, r.why);
        ok &= find_symbol(lib, "gmshLoggerGetLastError", r.last_error, r.why);
        if (!ok) return r;
        int ierr = 0;
        r.initialize(0, nullptr, 0, &ierr);
        if (ierr) {
            r.why = "the mesher could not start";
            return r;
        }
        r.set_number("General.Terminal", 0, &ierr);
        r.loaded = true;
        return r;
    }();
    return g;
}

// Vertices of different solids that are the same point (within tol) become one geometry
// point: a hash grid of cells 4 tol wide, searched in the 27 cells around a point.
struct PointMerge {
    double tol;
    double cell;
    std::map<std::array<long long, 3>, std::vector<int>> grid;
    std::vector<Vec3> points;

    explicit PointMerge(double t) : tol(t), cell(4 * t) {}
    int find_or_add(const Vec3& p) {
        std::array<long long, 3> k;
        for (int i = 0; i < 3; ++i) k[i] = grid_cell(p[i] / cell);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
                    if (it == grid.end()) continue;
                    for (int q : it->second) {
                        if ((points[q] - p).cwiseAbs().maxCoeff() <= tol) return q;
                    }
                }
        points.push_back(p);
        grid[k].push_back(static_cast<int>(points.size()) - 1);
        return static_cast<int>(points.size()) - 1;
    }
};

// A failed call of the mesher: its message.
struct MeshError {
    std::string what;
};

void check(const Gmsh& g, int ierr, const char* what) {
    if (!ierr) return;
    std::string text = what;
    char* last = nullptr;
    int e2 = 0;
    g.last_error(&last, &e2);
    if (last) {
        if (*last) text += std::string(": ") + last;
        g.free(last);
    }
    throw MeshError{text};
}

// Arrays the mesher allocates, freed with it.
template <class T>
struct GmshArray {
    const Gmsh& g;
    T* data = nullptr;
    size_t n = 0;
    explicit GmshArray(const Gmsh& gm) : g(gm) {}
    ~GmshArray() {
        if (data) g.free(data);
    }
    GmshArray(const GmshArray&) = delete;
    GmshArray& operator=(const GmshArray&) = delete;
};

void mesh_with(const Gmsh& g, const std::vector<Polyhedron>& solids, const std::vector<double>& edges,
               PointMerge& merge, TetMesh& out) {
    const double edge = *std::max_element(edges.begin(), edges.end());
    int ierr = 0;
    auto option = [&](const char* name, double v) {
        g.set_number(name, v, &ierr);
        check(g, ierr, "the mesher refused an option");
    };
    option("General.Terminal", 0);
    option("General.Verbosity", 1);
    g.clear(&ierr);
    check(g, ierr, "the mesher could not start a model");
    option("General.NumThreads", 1);
    option("Mesh.Algorithm", 6);      // frontal-Delaunay on the faces
    // Classic Delaunay in the volumes: the faster HXT orders its work by memory addresses, so
    // its meshes change with whatever the session allocated before; results must not.
    option("Mesh.Algorithm3D", 1);
    option("Mesh.MeshSizeMax", edge);
    option("Mesh.MeshSizeMin", 0);
    option("Mesh.MeshSizeExtendFromBoundary", 1);
    option("Mesh.Optimize", 1);
    option("Mesh.RandomSeed", 1);
    option("Geometry.Tolerance", 1e-12);
    g.model_add("odec", &ierr);
    check(g, ierr, "the mesher could not start a model");

    // Geometry: shared points, lines and faces are one entity each.
    // Points first: one per merged vertex, sized by the finest solid that has it, so that the
    // zones grade from fine blocks to coarse ones.
    std::vector<std::vector<int>> solid_points(solids.size());
    std::vector<double> point_size;
    for (size_t s = 0; s < solids.size(); ++s) {
        for (const Vec3& v : solids[s].vertices) {
            const int q = merge.find_or_add(v);
            if (q == static_cast<int>(point_size.size())) point_size.push_back(edges[s]);
            point_size[q] = std::min(point_size[q], edges[s]);
            solid_points[s].push_back(q);
        }
    }
    std::vector<int> point_tag(point_size.size());  // merged point -> gmsh tag
    for (size_t q = 0; q < point_size.size(); ++q) {
        const Vec3& v = merge.points[q];
        point_tag[q] = g.add_point(v.x(), v.y(), v.z(), point_size[q], -1, &ierr);
        check(g, ierr, "the mesher refused a corner of a block");
    }
    std::map<std::pair<int, int>, int> lines;   // (lo, hi) merged points -> line tag
    std::map<std::vector<int>, int> faces;      // sorted merged points -> surface tag
    std::vector<int> volume_tag(solids.size());
    out.face_surface.assign(solids.size(), {});
    for (size_t s = 0; s < solids.size(); ++s) {
        const Polyhedron& p = solids[s];
        const std::vector<int>& sp = solid_points[s];
        std::vector<int> surfaces;
        for (int f = 0; f < p.n_faces(); ++f) {
            std::vector<int> loop;
            for (int k = 0; k < p.face_size(f); ++k) loop.push_back(sp[p.face_vertex(f, k)]);
            std::vector<int> key = loop;
            std::sort(key.begin(), key.end());
            auto it = faces.find(key);
            if (it != faces.end()) {
                surfaces.push_back(it->second);
                out.face_surface[s].push_back(it->second);
                continue;
            }
            std::vector<int> curve;
            for (size_t k = 0; k < loop.size(); ++k) {
                const int a = loop[k], b = loop[(k + 1) % loop.size()];
                const auto lk = std::make_pair(std::min(a, b), std::max(a, b));
                auto li = lines.find(lk);
                int tag;
                if (li != lines.end()) {
                    tag = li->second;
                } else {
                    tag = g.add_line(point_tag[lk.first], point_tag[lk.second], -1, &ierr);
                    check(g, ierr, "the mesher refused an edge of a block");
                    lines[lk] = tag;
                }
                curve.push_back(a < b ? tag : -tag);
            }
            const int cl = g.add_curve_loop(curve.data(), curve.size(), -1, 0, &ierr);
            check(g, ierr, "the mesher refused a face of a block");
            int wire = cl;
            const int sf = g.add_plane_surface(&wire, 1, -1, &ierr);
            check(g, ierr, "the mesher refused a face of a block");
            faces[key] = sf;
            surfaces.push_back(sf);
            out.face_surface[s].push_back(sf);
        }
        const int shell = g.add_surface_loop(surfaces.data(), surfaces.size(), -1, &ierr);
        check(g, ierr, "the mesher refused the surface of a block");
        int shell_tag = shell;
        volume_tag[s] = g.add_volume(&shell_tag, 1, -1, &ierr);
        check(g, ierr, "the mesher refused a block");
    }
    g.synchronize(&ierr);
    check(g, ierr, "the mesher refused the geometry");
    g.generate(3, &ierr);
    if (ierr) {
        // HXT takes some inputs that the classic Delaunay mesher refuses: a mesh that may differ
        // from run to run is better than none.
        g.mesh_clear(nullptr, 0, &ierr);
        option("Mesh.Algorithm3D", 10);
        g.generate(3, &ierr);
        check(g, ierr, "the mesher failed");
    }

    // Nodes, renumbered densely in the order of their tags.
    GmshArray<size_t> tags(g);
    GmshArray<double> xyz(g), param(g);
    g.get_nodes(&tags.data, &tags.n, &xyz.data, &xyz.n, &param.data, &param.n, -1, -1, 0, 0, &ierr);
    check(g, ierr, "the mesher gave no nodes");
    std::unordered_map<std::size_t, int> index;
    std::vector<std::size_t> order(tags.n);
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return tags.data[a] < tags.data[b]; });
    out.nodes.reserve(tags.n);
    for (size_t i : order) {
        index[tags.data[i]] = static_cast<int>(out.nodes.size());
        out.nodes.emplace_back(xyz.data[3 * i], xyz.data[3 * i + 1], xyz.data[3 * i + 2]);
    }
    // Tetrahedra of each solid, oriented with positive volume.
    out.tets.resize(solids.size());
    out.corner_node.resize(solids.size());
    for (size_t s = 0; s < solids.size(); ++s) {
        GmshArray<size_t> elems(g), enodes(g);
        g.get_elements_by_type(4, &elems.data, &elems.n, &enodes.data, &enodes.n, volume_tag[s], 0, 1, &ierr);
        check(g, ierr, "the mesher gave no zones");
        auto& tv = out.tets[s];
        tv.reserve(elems.n);
        for (size_t e = 0; e < elems.n; ++e) {
            std::array<int, 4> t;
            for (int k = 0; k < 4; ++k) t[k] = index.at(enodes.data[4 * e + k]);
            const Vec3& a = out.nodes[t[0]];
            if ((out.nodes[t[1]] - a).dot((out.nodes[t[2]] - a).cross(out.nodes[t[3]] - a)) < 0) std::swap(t[2], t[3]);
            tv.push_back(t);
        }
        if (tv.empty()) throw MeshError{"the mesher made no zones in a block"};
        // The node at each vertex of the solid: the mesh node of its geometry point.
        for (int q : solid_points[s]) {
            GmshArray<size_t> nt(g);
            GmshArray<double> c(g), pc(g);
            g.get_nodes(&nt.data, &nt.n, &c.data, &c.n, &pc.data, &pc.n, 0, point_tag[q], 0, 0, &ierr);
            check(g, ierr, "the mesher left out a corner of a block");
            if (nt.n == 0) throw MeshError{"the mesher left out a corner of a block"};
            out.corner_node[s].push_back(index.at(nt.data[0]));
        }
    }
    g.clear(&ierr);
}

// The mesh improved where its zones are poor (mesh/tet_improve.h), and its quality measured.
// In the parent: only Gmsh runs in the child.
void improve_and_measure(TetMesh& out) {
    improve_tets(out.nodes, out.tets, kImproveBelow);
    const size_t n_solids = out.tets.size();
    double worst = 1, sum = 0;
    long count = 0;
    out.solid_worst.assign(n_solids, 1.0);
    for (size_t s = 0; s < n_solids; ++s) {
        for (const auto& t : out.tets[s]) {
            const double q = radius_ratio(out.nodes[t[0]], out.nodes[t[1]], out.nodes[t[2]], out.nodes[t[3]]);
            out.solid_worst[s] = std::min(out.solid_worst[s], q);
            worst = std::min(worst, q);
            sum += q;
            ++count;
        }
    }
    out.worst_quality = worst;
    out.mean_quality = count > 0 ? sum / count : 1;
}

// ---- meshing in a child process ----
//
// The mesher runs in a child process forked for each call, and sends its mesh back through a
// pipe. Gmsh has no way to stop a long meshing part way, and a large 'gen' can take a minute:
// the parent waits for the child's bytes, looks at the interrupt flag (Ctrl-C) every tenth of
// a second, and kills the child when it is raised. The child starts from a copy of this
// process, Gmsh's state included, so the mesh is the same bits as meshing here would give;
// and a mesher that crashes takes only the child with it.
//
// What the child writes: a status byte (0: a mesh follows; 1: an error message follows, as a
// u64 length and its bytes), then the nodes (u64 n, 3 n doubles), the solids (u64 n), and for
// each its tetrahedra (u64 n, 4 n int32), corner nodes and face surfaces (u64 n, n int32 each).
// The parent improves the poor zones and measures the quality: odec's own code runs there, where
// a fault in it is the session's to see, and the child runs only Gmsh.

bool write_bytes(int fd, const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    while (n > 0) {
        const ssize_t k = ::write(fd, c, n);
        if (k < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        c += k;
        n -= static_cast<size_t>(k);
    }
    return true;
}

// Buffered writes of the child.
struct ChildOut {
    int fd;
    std::vector<char> buf;
    bool ok = true;
    explicit ChildOut(int f) : fd(f) { buf.reserve(1 << 16); }
    void bytes(const void* p, size_t n) {
        const char* c = static_cast<const char*>(p);
        while (n > 0) {
            const size_t room = (1u << 16) - buf.size();
            const size_t k = std::min(room, n);
            buf.insert(buf.end(), c, c + k);
            c += k;
            n -= k;
            if (buf.size() == (1u << 16)) flush();
        }
    }
    template <class T>
    void raw(T x) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes(&x, sizeof x);
    }
    void flush() {
        if (ok && !buf.empty()) ok = write_bytes(fd, buf.data(), buf.size());
        buf.clear();
    }
};

void send_ints(ChildOut& o, const std::vector<int>& v) {
    o.raw(static_cast<std::uint64_t>(v.size()));
    for (int x : v) o.raw(static_cast<std::int32_t>(x));
}

[[noreturn]] void child_main(int fd, const Gmsh& g, const std::vector<Polyhedron>& solids,
                             const std::vector<double>& edges, double tol) {
    ChildOut o(fd);
    TetMesh mesh;
    std::string error;
    try {
        PointMerge merge(tol);
        mesh_with(g, solids, edges, merge, mesh);
    } catch (const MeshError& e) {
        error = e.what.empty() ? std::string("the mesher failed") : e.what;
    } catch (const std::bad_alloc&) {
        error = "out of memory while meshing";
    } catch (...) {
        error = "the mesher failed";
    }
    if (!error.empty()) {
        o.raw(std::uint8_t{1});
        o.raw(static_cast<std::uint64_t>(error.size()));
        o.bytes(error.data(), error.size());
    } else {
        o.raw(std::uint8_t{0});
        o.raw(static_cast<std::uint64_t>(mesh.nodes.size()));
        for (const Vec3& x : mesh.nodes) {
            for (int i = 0; i < 3; ++i) o.raw(x[i]);
        }
        o.raw(static_cast<std::uint64_t>(mesh.tets.size()));
        for (size_t s = 0; s < mesh.tets.size(); ++s) {
            o.raw(static_cast<std::uint64_t>(mesh.tets[s].size()));
            for (const auto& t : mesh.tets[s]) {
                for (int k = 0; k < 4; ++k) o.raw(static_cast<std::int32_t>(t[k]));
            }
            send_ints(o, mesh.corner_node[s]);
            send_ints(o, mesh.face_surface[s]);
        }
    }
    o.flush();
    ::close(fd);
    // No destructors, no exit handlers: they belong to the parent.
    ::_exit(o.ok ? 0 : 3);
}

struct Interrupted {};
struct ChildFailed {};

// Reads what the child sends, checking the interrupt flag while it waits.
class ChildIn {
public:
    ChildIn(int fd, const std::atomic<bool>* interrupt) : fd_(fd), interrupt_(interrupt) {}
    void bytes(void* p, size_t n) {
        char* c = static_cast<char*>(p);
        while (n > 0) {
            if (pos_ == end_) fill();
            const size_t k = std::min(n, end_ - pos_);
            std::memcpy(c, buf_ + pos_, k);
            pos_ += k;
            c += k;
            n -= k;
        }
    }
    template <class T>
    T raw() {
        T x;
        bytes(&x, sizeof x);
        return x;
    }
    // A count of items of `item_bytes` each; no more than a child could have meshed.
    size_t count(size_t item_bytes) {
        const std::uint64_t n = raw<std::uint64_t>();
        if (n > (std::uint64_t{1} << 40) / item_bytes) throw ChildFailed{};
        return static_cast<size_t>(n);
    }
    std::vector<int> ints() {
        std::vector<int> v(count(4));
        for (int& x : v) x = raw<std::int32_t>();
        return v;
    }

private:
    void fill() {
        for (;;) {
            if (interrupt_ && interrupt_->load()) throw Interrupted{};
            struct pollfd p{fd_, POLLIN, 0};
            const int r = ::poll(&p, 1, 100);
            if (r < 0 && errno != EINTR) throw ChildFailed{};
            if (r <= 0) continue;
            const ssize_t k = ::read(fd_, buf_, sizeof buf_);
            if (k < 0) {
                if (errno == EINTR || errno == EAGAIN) continue;
                throw ChildFailed{};
            }
            if (k == 0) throw ChildFailed{}; // the child ended before its mesh did
            pos_ = 0;
            end_ = static_cast<size_t>(k);
            return;
        }
    }
    int fd_;
    const std::atomic<bool>* interrupt_;
    char buf_[1 << 16];
    size_t pos_ = 0, end_ = 0;
};

} // namespace

std::string mesh_solids(const std::vector<Polyhedron>& solids, const std::vector<double>& edges, TetMesh& out,
                        const std::atomic<bool>* interrupt) {
    out = TetMesh();
    if (solids.empty()) return "";
    if (edges.size() != solids.size()) return "one zone size per block is needed";
    double edge = 0;
    for (double e : edges) {
        if (!(e > 0) || !std::isfinite(e)) return "the zone edge length must be a positive number";
        edge = std::max(edge, e);
    }
    Vec3 lo = solids[0].vertices[0], hi = lo;
    for (const Polyhedron& p : solids) {
        for (const Vec3& v : p.vertices) {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
    }
    const double tol = 1e-9 * std::max((hi - lo).norm(), edge);
    std::lock_guard<std::mutex> lock(gmsh_mutex);
    const Gmsh& g = gmsh_library();
    if (!g.loaded) return g.why;
    if (interrupt && interrupt->load()) return "interrupted before meshing";
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return std::string("the mesher cannot start: ") + std::strerror(errno);
    const pid_t parent = ::getpid();
    const pid_t child = ::fork();
    if (child < 0) {
        const int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return std::string("the mesher cannot start: ") + std::strerror(e);
    }
    if (child == 0) {
        ::close(fds[0]);
        // Ctrl-C is the parent's to judge: it kills this process when it wants it stopped.
        ::signal(SIGINT, SIG_IGN);
        // A fatal signal ends the child as the system ends a process, whatever handlers the
        // parent set (a fuzzer's or a sanitizer's): the parent reports it as the mesher's crash.
        for (int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP}) ::signal(sig, SIG_DFL);
        // And the mesher dies with the parent: a session killed while it meshes (a time limit,
        // a closed terminal) must not leave it running on.
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(4);
        child_main(fds[1], g, solids, edges, tol);
    }
    ::close(fds[1]);
    std::string why;
    bool stop_child = false;
    try {
        ChildIn in(fds[0], interrupt);
        const auto status = in.raw<std::uint8_t>();
        if (status == 1) {
            std::string text(std::min<size_t>(in.count(1), 4096), '\0');
            in.bytes(text.data(), text.size());
            why = text;
        } else if (status != 0) {
            throw ChildFailed{};
        } else {
            out.nodes.resize(in.count(24));
            for (Vec3& x : out.nodes) {
                for (int i = 0; i < 3; ++i) x[i] = in.raw<double>();
            }
            const size_t n_solids = in.count(8);
            if (n_solids != solids.size()) throw ChildFailed{};
            out.tets.resize(n_solids);
            out.corner_node.resize(n_solids);
            out.face_surface.resize(n_solids);
            const auto n_nodes = static_cast<std::int64_t>(out.nodes.size());
            for (size_t s = 0; s < n_solids; ++s) {
                out.tets[s].resize(in.count(16));
                for (auto& t : out.tets[s]) {
                    for (int k = 0; k < 4; ++k) {
                        t[k] = in.raw<std::int32_t>();
                        if (t[k] < 0 || t[k] >= n_nodes) throw ChildFailed{};
                    }
                }
                out.corner_node[s] = in.ints();
                for (int q : out.corner_node[s]) {
                    if (q < 0 || q >= n_nodes) throw ChildFailed{};
                }
                out.face_surface[s] = in.ints();
            }
        }
    } catch (const Interrupted&) {
        why = "interrupted: the blocks were not zoned";
        stop_child = true;
    } catch (const ChildFailed&) {
        why = "the mesher failed";
        stop_child = true;
    } catch (const std::bad_alloc&) {
        why = "out of memory while reading the mesh";
        stop_child = true;
    }
    ::close(fds[0]);
    if (stop_child) ::kill(child, SIGKILL);
    int wstatus = 0;
    while (::waitpid(child, &wstatus, 0) < 0 && errno == EINTR) {
    }
    if (why.empty() && !(WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == 0)) why = "the mesher failed";
    if (why == "the mesher failed" && WIFSIGNALED(wstatus) && WTERMSIG(wstatus) != SIGKILL) {
        why = "the mesher crashed (signal " + std::to_string(WTERMSIG(wstatus)) + ", " + strsignal(WTERMSIG(wstatus)) + ")";
    }
    if (!why.empty()) {
        out = TetMesh();
        return why;
    }
    improve_and_measure(out);
    return why;
}

} // namespace odec
