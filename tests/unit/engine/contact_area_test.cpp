// The contact area that print, hist, FISH and pictures report (contact_touch_area): where the
// blocks touch, not the sum of the sub-contacts' spring areas. A 1 x 1 x 1 m block stands on a
// fixed base: flat on its face (1 m^2), tilted on one edge (the strip its penetration makes,
// however large the toe's spring areas are), and tilted a few degrees with its heel lifted
// (the heel's sub-contacts carry nothing and are open).
#include <gtest/gtest.h>

#include <cmath>

#include "contact_test_util.h"

using namespace odec;
using namespace odec::test;

namespace {

struct Standing {
    Model m;
    int block = -1, contact = -1;
};

// The block turned by `tilt` about its edge x = 0, y along it, pressed `depth` into the base
// z < 0 at that edge; one step, no gravity (the geometry alone), stiff joint.
void stand(Standing& s, double tilt, double depth, double ctol) {
    Model& m = s.m;
    m.settings.dyn_configured = m.settings.dynamic = true;
    m.settings.ctol = ctol;
    m.damping.mode = DampingMode::Off;
    set_material(m, 1, 2500);
    set_joint(m, 1, 1e10, 1e10, 40);
    m.settings.default_jmat = 1;
    add_fixed(m, make_brick(-2, 3, -1, 2, -1, 0));
    Polyhedron p = rotated(make_brick(0, 1, 0, 1, 0, 1), Vec3::Zero(), Vec3::UnitY(), -tilt);
    for (Vec3& v : p.vertices) v.z() -= depth;
    s.block = add_block(m, p, 0, -1, 1);
    ASSERT_EQ(prepare_cycle(m), "");
    run_steps(m, 1);
    s.contact = contact_between(m, 0, s.block);
    ASSERT_GE(s.contact, 0);
}

// How deep the block's lowest corner is in the base now (the step has moved it a little).
double depth_now(const Model& m, int b) {
    double lo = 0;
    const Mat3 r = m.blocks.orientation[b].toRotationMatrix();
    for (const Vec3& v : m.blocks.shape[b].vertices) lo = std::min(lo, (m.blocks.centroid[b] + r * v).z());
    return -lo;
}

double spring_area(const Model& m, int c) {
    double a = 0;
    for (int k = m.contacts.sub_offset[c]; k < m.contacts.sub_offset[c + 1]; ++k) a += m.contacts.sub_area[k];
    return a;
}

} // namespace

TEST(ContactArea, FlatFaceTouchesOverItsWholeArea) {
    Standing s;
    stand(s, 0.0, 1e-5, 0.05);
    const ContactInfo info = contact_info(s.m, s.contact);
    EXPECT_NEAR(info.area, 1.0, 1e-9);
    EXPECT_NEAR(spring_area(s.m, s.contact), 1.0, 1e-9);
    EXPECT_EQ(info.state, ContactState::Elastic);
}

TEST(ContactArea, AnEdgeTouchesOverTheStripItsPenetrationMakes) {
    // Tilted 30 deg on its edge, 0.1 mm into the base: the overlap is the strip between the two
    // faces meeting at the edge, d / tan 30 + d / tan 60 = 2.31e-4 m wide along the 1 m edge.
    Standing s;
    const double tilt = 30 * M_PI / 180, d = 1e-4;
    stand(s, tilt, d, 0.05);
    const ContactInfo info = contact_info(s.m, s.contact);
    const double dn = depth_now(s.m, s.block);
    EXPECT_NEAR(dn, d, 0.1 * d);
    const double strip = dn / std::tan(tilt) + dn / std::tan(M_PI / 2 - tilt);
    EXPECT_NEAR(info.area, strip, 0.01 * strip);
    // The toe's sub-contacts carry the force with their own (much larger) spring areas: each
    // corner its share of the face nearest the plane, the base (a quarter of it), as when the
    // block stands on it; the side face, at 60 deg to the plane, adds next to nothing.
    EXPECT_NEAR(spring_area(s.m, s.contact), 0.5, 1e-6);
    EXPECT_GT(info.normal_stress, 0.0);
}

TEST(ContactArea, ALiftedHeelIsOpenAndAddsNoArea) {
    // 4.3 deg, heel 7.5 cm above the base, within a ctol of 0.1 m, so the base counts as lying on
    // the plane: the heel's sub-contacts are open and carry nothing, and the area is the toe
    // corners' half of the base, not all of it.
    Standing s;
    const double tilt = 4.3 * M_PI / 180, d = 1e-5;
    stand(s, tilt, d, 0.1);
    const Model& m = s.m;
    const ContactSet& cs = m.contacts;
    int closed = 0, heel = 0;
    double closed_area = 0;
    for (int k = cs.sub_offset[s.contact]; k < cs.sub_offset[s.contact + 1]; ++k) {
        const Vec3 x = sub_point(m, s.contact, k - cs.sub_offset[s.contact]);
        if (x.x() > 0.5) {
            ++heel;
            EXPECT_TRUE(cs.sub_flags(k) & kSubOpen) << "a heel sub-contact at x = " << x.x() << " is not open";
            EXPECT_EQ(sub_normal_stress(m, k), 0.0);
        } else if (!(cs.sub_flags(k) & kSubOpen)) {
            ++closed;
            closed_area += cs.sub_area[k];
        }
    }
    EXPECT_EQ(heel, 2);
    EXPECT_EQ(closed, 2);
    const ContactInfo info = contact_info(m, s.contact);
    // The springs' shares were measured at the step's start, the area now: the step moved the
    // block by a few micrometres.
    EXPECT_NEAR(info.area, closed_area, 1e-5 * closed_area);
    EXPECT_NEAR(info.area, 0.5 * std::cos(tilt), 0.01);
    EXPECT_EQ(info.state, ContactState::Elastic);
}

TEST(ContactArea, FlatFacesApartWithinCtolTouchNowhere) {
    // Parallel faces 1 cm apart, within a ctol of 0.05 m: a contact, but apart: no area.
    Standing s;
    stand(s, 0.0, -0.01, 0.05);
    const ContactInfo info = contact_info(s.m, s.contact);
    EXPECT_EQ(info.area, 0.0);
    EXPECT_EQ(info.state, ContactState::Open);
}
