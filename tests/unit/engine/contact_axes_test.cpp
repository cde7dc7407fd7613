// The contact update's per-contact set-up, made many contacts at a time (contact_axes.h), gives
// the very bits of the expressions it stands for, written with Eigen as the rest of the engine
// reads them (decode_normal, shear_axes, the turn matrices, the products on the contact's axes),
// whatever a contact's place in its batch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "engine/contact.h"
#include "engine/contact_axes.h"
#include "engine/normal_code.h"
#include "engine/stages.h"

namespace {

using odec::ContactAxesBatch;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

struct BlockMotion {
    Vec3 k, disp, centroid;
    double sin = 0, cos1 = 0;
    Mat3 rot;
};

// The turn matrix as the contact update wrote it with Eigen: cos1 (I - k k^T) + sin [k]x.
Mat3 turn_matrix(const BlockMotion& x) {
    const Vec3& k = x.k;
    const double c1 = x.cos1, sn = x.sin;
    Mat3 t = -c1 * (k * k.transpose());
    t.diagonal().array() += c1;
    t(0, 1) -= sn * k.z(); t(0, 2) += sn * k.y();
    t(1, 0) += sn * k.z(); t(1, 2) -= sn * k.x();
    t(2, 0) -= sn * k.y(); t(2, 1) += sn * k.x();
    return t;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(ContactAxes, EveryLaneGivesTheBitsOfTheEigenExpressions) {
    std::mt19937_64 rng(19);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(-1, 1);
    const std::int32_t lim = odec::kNormalCodeLimit;
    std::uniform_int_distribution<std::int32_t> any_code(-lim, lim);
    auto block = [&](int i) {
        BlockMotion x;
        x.k = Vec3(g(rng), g(rng), g(rng)).normalized();
        if (i % 7 == 0) x.k.setZero(); // a block that did not turn
        const double angle = i % 3 == 0 ? 1e-9 * u(rng) : u(rng);
        x.sin = std::sin(angle);
        x.cos1 = 1 - std::cos(angle);
        x.disp = Vec3(u(rng), u(rng), u(rng)) * (i % 5 == 0 ? 1e-12 : 1e-3);
        x.centroid = Vec3(u(rng), u(rng), u(rng)) * 100;
        x.rot = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
        return x;
    };
    int checked = 0, x_refs = 0, folded = 0;
    // (About 33,000 lanes whatever the batch's size.)
    for (int round = 0; round < 64000 / ContactAxesBatch::kSize; ++round) {
        ContactAxesBatch batch;
        const int count = 1 + round % ContactAxesBatch::kSize; // partial batches too
        std::vector<odec::NormalCode> codes(count);
        std::vector<BlockMotion> a(count), b(count);
        for (int l = 0; l < count; ++l) {
            const int i = round * ContactAxesBatch::kSize + l;
            odec::NormalCode c{any_code(rng), any_code(rng)};
            if (i % 5 == 1) c = odec::encode_normal(Vec3(g(rng), g(rng), g(rng)).normalized());
            if (i % 11 == 2) c = odec::encode_normal(Vec3(0, 0, i % 2 ? 1 : -1)); // along the axes
            if (i % 13 == 3) c = odec::encode_normal(Vec3(1, 0, 0));
            codes[l] = c;
            a[l] = block(i);
            b[l] = block(i + 1);
            batch.nu[l] = c.u;
            batch.nv[l] = c.v;
            const BlockMotion* both[2] = {&a[l], &b[l]};
            for (int s = 0; s < 2; ++s) {
                for (int j = 0; j < 3; ++j) {
                    batch.k[s][j][l] = both[s]->k[j];
                    batch.disp[s][j][l] = both[s]->disp[j];
                    batch.centroid[s][j][l] = both[s]->centroid[j];
                }
                for (int j = 0; j < 9; ++j) batch.rot[s][j][l] = both[s]->rot.data()[j];
                batch.sin[s][l] = both[s]->sin;
                batch.cos1[s][l] = both[s]->cos1;
            }
        }
        odec::make_contact_axes(batch, count);
        for (int l = 0; l < count; ++l) {
            // The expressions of the scalar contact update.
            const Vec3 nrm = odec::decode_normal(codes[l]);
            Vec3 e1, e2;
            odec::shear_axes(nrm, e1, e2);
            Mat3 ax;
            ax.row(0) = nrm;
            ax.row(1) = e1;
            ax.row(2) = e2;
            const Vec3 cab = b[l].centroid - a[l].centroid;
            const Mat3 ta = turn_matrix(a[l]), tb = turn_matrix(b[l]);
            const Vec3 du0 = ax * (b[l].disp - a[l].disp - tb * cab);
            const Mat3 dt_ax = ax * (tb - ta) * ax.transpose();
            const Mat3 to_a = ax * a[l].rot, to_b = ax * b[l].rot;
            const Vec3 cab_ax = ax * cab;
            x_refs += std::abs(nrm.x()) < 0.6;
            folded += std::abs(codes[l].u) + std::abs(static_cast<double>(codes[l].v)) > lim;
            for (int i = 0; i < 3; ++i) {
                ASSERT_TRUE(same_bits(batch.n[i][l], nrm[i])) << "lane " << l << " n" << i;
                ASSERT_TRUE(same_bits(batch.e1[i][l], e1[i])) << "lane " << l << " e1 " << i;
                ASSERT_TRUE(same_bits(batch.e2[i][l], e2[i])) << "lane " << l << " e2 " << i;
                ASSERT_TRUE(same_bits(batch.cab[i][l], cab[i]));
                ASSERT_TRUE(same_bits(batch.cab_ax[i][l], cab_ax[i]));
                ASSERT_TRUE(same_bits(batch.du0[i][l], du0[i])) << "lane " << l << " du0 " << i;
                for (int j = 0; j < 3; ++j) {
                    ASSERT_TRUE(same_bits(batch.dt_ax[3 * i + j][l], dt_ax(i, j))) << "lane " << l << " dt_ax " << i << j;
                    ASSERT_TRUE(same_bits(batch.to[0][3 * i + j][l], to_a(i, j)));
                    ASSERT_TRUE(same_bits(batch.to[1][3 * i + j][l], to_b(i, j)));
                }
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 30000);
    // Both choices of the shear axes' reference, and codes on the octahedron's folded half.
    EXPECT_GT(x_refs, checked / 10);
    EXPECT_LT(x_refs, checked - checked / 10);
    EXPECT_GT(folded, checked / 10);
}

} // namespace

namespace {

// A block's turn as the contact update made it block by block (joint_law.cpp).
void reference_turn(const Vec3& w_now, bool still, double dt, bool dynamic, Vec3& axis, double& sin, double& cos1) {
    const Vec3 w = still ? Vec3(Vec3::Zero()) : w_now;
    const double angle = w.norm() * dt;
    axis = angle > 0 ? Vec3(w / w.norm()) : Vec3(Vec3::Zero());
    double sin_h = 0, cos_h = 1;
    if (angle > 0) {
        odec::half_turn(angle * angle, sin_h, cos_h);
        sin_h *= angle;
    }
    sin = dynamic ? 2.0 * sin_h * cos_h : angle;
    cos1 = dynamic ? 2.0 * sin_h * sin_h : 0.0;
}

} // namespace

TEST(ContactAxes, BlockTurnsFourAtATimeAreTheBitsOfTheBlockByBlockOnes) {
    std::mt19937_64 rng(41);
    std::normal_distribution<double> g;
    const int n = 403; // (groups of four and the rest)
    std::vector<Vec3> w(n);
    std::vector<std::uint8_t> still(n);
    int library = 0, series = 0;
    for (int b = 0; b < n; ++b) {
        const double scale = b % 4 == 0 ? 1e3 : b % 4 == 1 ? 1e-3 : 1; // angles past the series' range too
        w[b] = Vec3(g(rng), g(rng), g(rng)) * scale;
        if (b % 9 == 0) w[b].setZero();
        still[b] = b % 7 == 3;
    }
    const double dt = 1e-4;
    for (const bool dynamic : {true, false}) {
        std::vector<Vec3> axis(n);
        std::vector<double> sn(n), c1(n);
        odec::make_block_turns(w.data(), still.data(), 0, n, dt, dynamic, axis.data(), sn.data(), c1.data());
        for (int b = 0; b < n; ++b) {
            Vec3 ax;
            double s, c;
            reference_turn(w[b], still[b] != 0, dt, dynamic, ax, s, c);
            ASSERT_EQ(std::memcmp(ax.data(), axis[b].data(), sizeof(double) * 3), 0) << "block " << b;
            ASSERT_TRUE(same_bits(s, sn[b])) << "block " << b << ": " << s << " " << sn[b];
            ASSERT_TRUE(same_bits(c, c1[b])) << "block " << b;
            const double h2 = 0.25 * std::pow(w[b].norm() * dt, 2);
            if (!still[b] && h2 > 0) (h2 < 1e-6 ? series : library) += 1;
        }
    }
    EXPECT_GT(series, 100);
    EXPECT_GT(library, 50);
}
