#include "commands.h"
#include "common.h"
#include "engine/blocks.h"

namespace odec {

namespace {

std::vector<Vec3> points_of(const KeywordUse& u) {
    std::vector<Vec3> pts;
    for (const Value& v : u.values) {
        if (v.type == ValueType::Vec3) pts.push_back(v.vec);
    }
    return pts;
}

// Geometric tolerance for merging vertices and checking planarity: relative to the size.
double tolerance_for(const std::vector<Vec3>& pts) {
    Vec3 lo = pts.front(), hi = pts.front();
    for (const Vec3& p : pts) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return 1e-6 * std::max(1e-3, (hi - lo).norm());
}

} // namespace

const CommandSpec& poly_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("poly", 4, "create a rigid convex polyhedral block");
        c.keyword("brick", 2, "axis-aligned box from x1 to x2, y1 to y2, z1 to z2")
            .real("x1").real("x2").real("y1").real("y2").real("z1").real("z2")
            .in_choice(1);
        c.keyword("prism", 2, "prism between polygon 'a' and its translated copy 'b'").in_choice(1);
        c.keyword("a", 1, "with 'prism': the vertices of one end, in order").vec("v").repeat();
        c.keyword("b", 1, "with 'prism': the vertices of the other end, in order").vec("v").repeat();
        c.keyword("face", 2, "one face of a general convex polyhedron: its vertices in order (repeat 'face' "
                             "for every face)")
            .integer("id", 1).labelled().optional()
            .vec("v").repeat()
            .many()
            .in_choice(1);
        c.keyword("tetra", 2, "tetrahedron with these four corners").vec("v1").vec("v2").vec("v3").vec("v4").in_choice(1);
        c.keyword("region", 3, "region number of the new block, for 'range region'").integer("n", 0).defaults("0");
        c.keyword("group", 2, "group name of the new block").word("name");
        c.keyword("material", 3, "material number of the new block").integer("n", 1, 1000000).defaults("1");
        c.keyword("cons", 3, "zone model its zones get when it is divided into zones (0 null, 1 elastic, 2 Mohr-Coulomb)")
            .integer("c", 0, 2);
        c.require_one_of(1);
        c.describe("The block is rigid: it moves as a whole, with three translations and three rotations "
                   "about its centroid. Its mass and inertia come from its faces and the density of its "
                   "material ('prop mat=n dens=...'). Faces must be planar and the solid convex; an error "
                   "names the face that is not.");
        c.example("poly brick 0 10 0 10 -5 0 region 1 group 'base'");
        c.example("poly prism a (0,0,0) (1,0,0) (0,1,0) b (0,0,2) (1,0,2) (0,1,2)");
        c.example("poly tetra (0,0,0) (1,0,0) (0,1,0) (0,0,1)");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            const std::string kind = a.chosen(1);
            if (kind != "prism" && (a.has("a") || a.has("b"))) {
                const KeywordUse* u = a.has("a") ? a.find("a") : a.find("b");
                fail(u->loc, "'" + u->spec->name + "' goes with 'prism'", {}, "poly");
            }
            // Coordinates within reach of doubles: their squares and cubes (areas, volumes,
            // inertias) must not overflow, and round-off must leave the block its shape.
            constexpr double kMaxCoordinate = 1e9;
            for (const char* k : {"brick", "a", "b", "face", "tetra"}) {
                for (const KeywordUse* u : a.all(k)) {
                    for (const Value& v : u->values) {
                        const double x = v.type == ValueType::Vec3 ? v.vec.cwiseAbs().maxCoeff() : std::abs(v.number);
                        if ((v.type == ValueType::Vec3 || v.type == ValueType::Real) && x > kMaxCoordinate) {
                            fail(v.loc, "coordinate " + num(x) + " is too far from the origin: poly takes coordinates within " +
                                            num(kMaxCoordinate) + " m",
                                 {"odec works in metres; move the origin near the model"}, "poly");
                        }
                    }
                }
            }
            Polyhedron p;
            std::string error;
            SourceLoc where = a.find(kind)->loc;
            if (kind == "brick") {
                const KeywordUse* b = a.find("brick");
                const char* axes[3] = {"x", "y", "z"};
                for (int i = 0; i < 3; ++i) {
                    const Value& lo = b->values[2 * i];
                    const Value& hi = b->values[2 * i + 1];
                    if (!(hi.number > lo.number)) {
                        fail(hi.loc, std::string("'brick' ") + axes[i] + "2 must be greater than " + axes[i] +
                                         "1 (got " + num(hi.number) + " after " + num(lo.number) + ")",
                             {}, "poly");
                    }
                }
                p = make_brick(b->values[0].number, b->values[1].number, b->values[2].number, b->values[3].number,
                               b->values[4].number, b->values[5].number);
            } else if (kind == "prism") {
                if (!a.has("a") || !a.has("b")) fail(where, "'prism' needs both ends: 'a' v ... 'b' v ...", {}, "poly");
                const std::vector<Vec3> pa = points_of(*a.find("a")), pb = points_of(*a.find("b"));
                std::vector<Vec3> all = pa;
                all.insert(all.end(), pb.begin(), pb.end());
                if (!make_prism(pa, pb, tolerance_for(all), p, error)) fail(a.find("a")->loc, error, {}, "poly");
            } else if (kind == "face") {
                std::vector<std::vector<Vec3>> faces;
                std::vector<Vec3> all;
                for (const KeywordUse* u : a.all("face")) {
                    faces.push_back(points_of(*u));
                    all.insert(all.end(), faces.back().begin(), faces.back().end());
                    if (faces.back().size() < 3) {
                        fail(u->loc, "face " + std::to_string(faces.size()) + " has " +
                                         std::to_string(faces.back().size()) + " vertices: a face needs at least 3",
                             {}, "poly");
                    }
                }
                if (!make_from_faces(faces, tolerance_for(all), p, error)) {
                    // The message names the face by its number; point at that 'face' keyword.
                    const auto uses = a.all("face");
                    SourceLoc loc = uses.front()->loc;
                    const size_t at = error.find("face ");
                    if (at != std::string::npos) {
                        const int n = std::atoi(error.c_str() + at + 5);
                        if (n >= 1 && n <= static_cast<int>(uses.size())) loc = uses[n - 1]->loc;
                    }
                    fail(loc, error, {}, "poly");
                }
            } else {
                const KeywordUse* t = a.find("tetra");
                std::vector<Vec3> v = points_of(*t);
                if (!make_tetra(v[0], v[1], v[2], v[3], tolerance_for(v), p, error)) fail(t->loc, error, {}, "poly");
            }
            const int region = a.has("region") ? a.integer("region") : 0;
            const int material = a.has("material") ? a.integer("material") : 1;
            {
                const double rho = material < static_cast<int>(m.materials.size()) ? m.materials[material].density : 0.0;
                const std::string problem = block_numbers_problem(mass_properties(p), rho);
                if (!problem.empty()) fail(where, problem, {"odec works in metres, kilograms and seconds"}, "poly");
            }
            const int group = a.has("group") ? m.group_index(a.text("group"), true) : -1;
            const int b = add_block(m, p, region, group, material);
            if (a.has("cons")) m.blocks.cons[b] = static_cast<std::uint8_t>(a.integer("cons"));
        });
        return c;
    }();
    return spec;
}

} // namespace odec
