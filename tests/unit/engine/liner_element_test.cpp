// The liner's flat shell triangle (liner.h): rigid motions leave it unstressed, and it passes
// the patch tests of constant membrane strain and constant curvature exactly, whatever its
// shape and orientation in space.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/liner.h"
#include "engine/model.h"

using namespace odec;

namespace {

// One liner of one element with corners p0, p1, p2 (their normal away from the rock).
LinerSet one_element(const Vec3& p0, const Vec3& p1, const Vec3& p2, double e, double nu, double t) {
    LinerSet ls;
    ls.materials.resize(2);
    ls.materials[1].defined = true;
    ls.materials[1].e = e;
    ls.materials[1].nu = nu;
    ls.materials[1].thick = t;
    ls.id = {1};
    ls.material = {1};
    ls.axis = {Vec3::UnitZ()};
    ls.next_id = 2;
    ls.node_offset = {0, 3};
    ls.elem_offset = {0, 1};
    ls.pos0 = {p0, p1, p2};
    ls.pos = ls.pos0;
    ls.u.assign(3, Vec3::Zero());
    ls.rot.assign(3, Vec3::Zero());
    ls.elem = {{0, 1, 2}};
    build_liner_stiffness(ls);
    return ls;
}

// The nodal forces and moments K d of the element for the nodes' u and rot.
Eigen::Matrix<double, 18, 1> nodal_forces(const LinerSet& ls) {
    Eigen::Matrix<double, 18, 1> d;
    for (int a = 0; a < 3; ++a) {
        d.segment<3>(6 * a) = ls.u[a];
        d.segment<3>(6 * a + 3) = ls.rot[a];
    }
    const Eigen::Map<const Eigen::Matrix<double, 18, 18, Eigen::RowMajor>> k(ls.k[0].data());
    return k * d;
}

// A tilted frame: the element's plane is spanned by ex, ey, with normal ez.
struct Frame {
    Vec3 ex, ey, ez;
};
Frame tilted() {
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) *
                               Eigen::AngleAxisd(-0.4, Vec3::UnitX())).toRotationMatrix();
    return {r.col(0), r.col(1), r.col(2)};
}

} // namespace

TEST(LinerElement, RigidMotionsGiveNoForce) {
    const Frame f = tilted();
    const Vec3 o(1, -2, 0.5);
    LinerSet ls = one_element(o, o + 1.3 * f.ex + 0.2 * f.ey, o + 0.4 * f.ex + 0.9 * f.ey, 30e9, 0.25, 0.2);
    const Mat3 k0 = Mat3::Identity();
    const double scale = std::abs(ls.k[0][0]) + std::abs(ls.k[0][18 * 3 + 3]);
    for (int mode = 0; mode < 6; ++mode) {
        for (int a = 0; a < 3; ++a) {
            if (mode < 3) {
                ls.u[a] = 1e-3 * k0.col(mode);
                ls.rot[a].setZero();
            } else {
                const Vec3 w = 1e-3 * k0.col(mode - 3);
                ls.u[a] = w.cross(ls.pos0[a] - Vec3(0.3, 0.1, -0.2));
                ls.rot[a] = w;
            }
        }
        const auto f18 = nodal_forces(ls);
        EXPECT_LT(f18.cwiseAbs().maxCoeff(), 1e-12 * scale * 1e-3) << "rigid mode " << mode;
    }
}

TEST(LinerElement, ConstantMembraneStrainIsExact) {
    const Frame f = tilted();
    const Vec3 o(0, 0, 0);
    const double e = 20e9, nu = 0.3, t = 0.15;
    LinerSet ls = one_element(o, o + 2.0 * f.ex + 0.3 * f.ey, o + 0.5 * f.ex + 1.7 * f.ey, e, nu, t);
    ls.axis[0] = f.ey; // report x = axis x normal = ey x ez = ex
    // u = exx x ex + eyy y ey + gxy y ex (in the plane): strains exx, eyy, gxy.
    const double exx = 1e-4, eyy = -3e-5, gxy = 2e-5;
    for (int a = 0; a < 3; ++a) {
        const double x = (ls.pos0[a] - o).dot(f.ex), y = (ls.pos0[a] - o).dot(f.ey);
        ls.u[a] = (exx * x + gxy * y) * f.ex + eyy * y * f.ey;
    }
    const LinerResultants r = liner_resultants(ls, 0);
    const double c = e * t / (1 - nu * nu);
    EXPECT_NEAR(r.nx, c * (exx + nu * eyy), 1e-9 * c * 1e-4);
    EXPECT_NEAR(r.ny, c * (eyy + nu * exx), 1e-9 * c * 1e-4);
    EXPECT_NEAR(r.nxy, c * 0.5 * (1 - nu) * gxy, 1e-9 * c * 1e-4);
    EXPECT_NEAR(r.mx, 0.0, 1e-6);
    EXPECT_NEAR(r.my, 0.0, 1e-6);
}

TEST(LinerElement, ConstantCurvatureIsExactAndSigned) {
    // w = (kx x^2 + ky y^2 + 2 kxy x y) / 2 along the normal: with the normal away from the rock,
    // kx > 0 bends the element so that its face on the normal's side is stretched... in the
    // convention of liner.h, a positive m_x has the void-side face (the normal's) in tension:
    // u(z) = -z w,x, so the strain at z is -z kx: kx < 0 puts the normal's side in tension.
    const Frame f = tilted();
    const Vec3 o(0.5, 0.5, 0.5);
    const double e = 30e9, nu = 0.2, t = 0.3;
    LinerSet ls = one_element(o, o + 1.1 * f.ex - 0.2 * f.ey, o + 0.3 * f.ex + 1.4 * f.ey, e, nu, t);
    ls.axis[0] = f.ey;
    const double kx = -2e-4, ky = 1e-4, kxy = 5e-5;
    for (int a = 0; a < 3; ++a) {
        const double x = (ls.pos0[a] - o).dot(f.ex), y = (ls.pos0[a] - o).dot(f.ey);
        const double w = 0.5 * (kx * x * x + ky * y * y + 2 * kxy * x * y);
        const double wx = kx * x + kxy * y, wy = ky * y + kxy * x;
        ls.u[a] = w * f.ez;
        // The normal turns by grad w: rotation about ex is w,y, about ey is -w,x.
        ls.rot[a] = wy * f.ex - wx * f.ey;
    }
    const LinerResultants r = liner_resultants(ls, 0);
    const double d = e * t * t * t / (12 * (1 - nu * nu));
    // Curvatures of the Kirchhoff plate (u = -z w,x): -kx, -ky, -2 kxy.
    const double tol = 1e-9 * d * 1e-4;
    EXPECT_NEAR(r.mx, d * (-kx - nu * ky), tol);
    EXPECT_NEAR(r.my, d * (-ky - nu * kx), tol);
    EXPECT_NEAR(r.mxy, d * 0.5 * (1 - nu) * (-2 * kxy), tol);
    EXPECT_GT(r.mx, 0.0); // kx < 0: the normal's side stretched
    EXPECT_NEAR(r.nx, 0.0, 1e-6 * e * t * 1e-4);
    // And the element's nodal forces are in equilibrium.
    const auto f18 = nodal_forces(ls);
    Vec3 sum_f = Vec3::Zero(), sum_m = Vec3::Zero();
    for (int a = 0; a < 3; ++a) {
        sum_f += f18.segment<3>(6 * a);
        sum_m += f18.segment<3>(6 * a + 3) + ls.pos0[a].cross(Vec3(f18.segment<3>(6 * a)));
    }
    EXPECT_LT(sum_f.norm(), 1e-9 * f18.cwiseAbs().maxCoeff());
    EXPECT_LT(sum_m.norm(), 1e-9 * f18.cwiseAbs().maxCoeff() * 3);
}
