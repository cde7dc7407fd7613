// Open sub-contacts kept by reference, and the contacts the update leaves alone while they stay
// open (contact.h, sub_closure; joint_law.cpp, update_contacts).
//
// The scene: columns of 1 m cubes 2 cm apart on a fixed base (the settling stacks of
// tests/bench/bench_stack.cpp, smaller), in dynamic mode at a fixed step; the top cube of one
// column is thrown sideways at its neighbour, across the 2 cm gap, so that side contacts go from
// open to closed and the stacks' side faces stay open, within the contact tolerance, throughout.
#include <gtest/gtest.h>

#include <cstring>

#include "contact_test_util.h"
#include "engine/blocks.h"
#include "engine/contact.h"
#include "engine/cycle.h"
#include "engine/model.h"

namespace {

using odec::Model;
using odec::Vec3;

constexpr double kPitch = 1.02, kGap = 0.001;

struct Stack {
    Model m;
    int thrown = -1;    // the top cube of column (0, 0)
    int neighbour = -1; // the top cube of column (1, 0)
    int quiet_steps = 0;
    int close_steps = 0;
};

void build(Stack& st, int nx, int ny, int nz) {
    Model& m = st.m;
    odec::test::set_material(m, 1, 2700);
    odec::test::set_joint(m, 1, 1e9, 1e9, 30);
    m.gravity = Vec3(0, 0, -10);
    m.damping.mode = odec::DampingMode::Local;
    m.damping.local = 0.8;
    m.settings.dyn_configured = true;
    m.settings.dynamic = true;
    m.settings.dt_fixed = 2.5e-5;
    odec::test::add_fixed(m, odec::make_brick(-1, nx * kPitch + 1, -1, ny * kPitch + 1, -1, 0));
    for (int i = 0; i < nx; ++i) {
        for (int j = 0; j < ny; ++j) {
            for (int k = 0; k < nz; ++k) {
                const double z0 = kGap + k * (1 + kGap);
                const int b = odec::add_block(
                    m, odec::make_brick(i * kPitch, i * kPitch + 1, j * kPitch, j * kPitch + 1, z0, z0 + 1), 0, -1, 1);
                if (j == 0 && k == nz - 1 && i == 0) st.thrown = b;
                if (j == 0 && k == nz - 1 && i == 1) st.neighbour = b;
            }
        }
    }
}

template <class T>
bool same_bits(const T& x, const T& y) {
    if (x.size() != y.size()) return false;
    return x.size() == 0 || std::memcmp(x.data(), y.data(), sizeof(x[0]) * x.size()) == 0;
}

// The blocks' motion and the sub-contacts' state (with their flags, kept with their points) of x
// and y are the same bits.
void expect_same_state(const Model& x, const Model& y) {
    EXPECT_TRUE(same_bits(x.blocks.centroid, y.blocks.centroid));
    EXPECT_TRUE(same_bits(x.blocks.orientation, y.blocks.orientation));
    EXPECT_TRUE(same_bits(x.blocks.vel, y.blocks.vel));
    EXPECT_TRUE(same_bits(x.blocks.ang_vel, y.blocks.ang_vel));
    EXPECT_TRUE(same_bits(x.blocks.force_scale, y.blocks.force_scale));
    EXPECT_TRUE(same_bits(x.contacts.sub_un, y.contacts.sub_un));
    EXPECT_TRUE(same_bits(x.contacts.sub_us, y.contacts.sub_us));
    EXPECT_TRUE(same_bits(x.contacts.sub_ss, y.contacts.sub_ss));
    EXPECT_TRUE(same_bits(x.contacts.sub_point, y.contacts.sub_point));
}

// Throws the top cube of column (0, 0) at its neighbour and steps; returns how many contacts the
// updates left alone, summed over the steps, and in *pressed the largest normal stress between the
// two cubes.
long run(Stack& st, long steps, double* pressed) {
    Model& m = st.m;
    EXPECT_TRUE(odec::prepare_cycle(m).empty());
    odec::test::run_steps(m, 200); // the cubes land
    m.blocks.vel[st.thrown] = Vec3(1.0, 0, 0);
    m.blocks.half_kick[st.thrown] = 1;
    long left = 0;
    for (long i = 0; i < steps; ++i) {
        const odec::CycleResult r = odec::test::run_steps(m, 1);
        EXPECT_EQ(r.reason, odec::StopReason::Steps) << r.message;
        left += m.contacts.left_open;
        const int c = odec::test::contact_between(m, st.thrown, st.neighbour);
        for (int k = c < 0 ? 0 : m.contacts.sub_offset[c]; c >= 0 && k < m.contacts.sub_offset[c + 1]; ++k) {
            *pressed = std::max(*pressed, odec::sub_normal_stress(m, c, k));
        }
    }
    return left;
}

struct Batched {
    explicit Batched(bool on) : was(odec::batched_sub_contacts()) { odec::set_batched_sub_contacts(on); }
    ~Batched() { odec::set_batched_sub_contacts(was); }
    bool was;
};

struct RestOpen {
    explicit RestOpen(bool on) : was(odec::rest_open_contacts()) { odec::set_rest_open_contacts(on); }
    ~RestOpen() { odec::set_rest_open_contacts(was); }
    bool was;
};

} // namespace

TEST(ContactRestOpen, LeavingOpenContactsAloneGivesTheSameBits) {
    Stack on, off;
    build(on, 2, 2, 2);
    build(off, 2, 2, 2);
    long left_on, left_off;
    double pressed_on = 0, pressed_off = 0;
    {
        RestOpen r(true);
        left_on = run(on, 3000, &pressed_on);
    }
    {
        RestOpen r(false);
        left_off = run(off, 3000, &pressed_off);
    }
    // Most of the stacks' contact updates leave their side faces alone; told not to, none.
    EXPECT_GT(left_on, 3000);
    EXPECT_EQ(left_off, 0);
    const Model& x = on.m;
    const Model& y = off.m;
    EXPECT_TRUE(same_bits(x.blocks.centroid, y.blocks.centroid));
    EXPECT_TRUE(same_bits(x.blocks.orientation, y.blocks.orientation));
    EXPECT_TRUE(same_bits(x.blocks.vel, y.blocks.vel));
    EXPECT_TRUE(same_bits(x.blocks.ang_vel, y.blocks.ang_vel));
    EXPECT_TRUE(same_bits(x.contacts.sub_un, y.contacts.sub_un));
    EXPECT_TRUE(same_bits(x.contacts.sub_us, y.contacts.sub_us));
    EXPECT_TRUE(same_bits(x.contacts.sub_ss, y.contacts.sub_ss));
    EXPECT_TRUE(same_bits(x.contacts.sub_point, y.contacts.sub_point));
    // The thrown cube crossed the gap and pushed its neighbour (by 1 kPa and more).
    EXPECT_GT(pressed_on, 1e3);
    EXPECT_EQ(pressed_on, pressed_off);
    EXPECT_GT(x.blocks.centroid[on.neighbour].x() - (kPitch + 0.5), 1e-4) << "the neighbour was pushed";
    // The joints given cohesion: the open sub-contacts that had not failed (there was nothing to
    // fail) fail at their next step, left alone or not.
    for (Stack* st : {&on, &off}) {
        st->m.joint_materials[1].cohesion = 1e4;
        RestOpen r(st == &on);
        odec::test::run_steps(st->m, 500);
    }
    EXPECT_TRUE(same_bits(x.blocks.centroid, y.blocks.centroid));
    EXPECT_TRUE(same_bits(x.contacts.sub_un, y.contacts.sub_un));
    EXPECT_TRUE(same_bits(x.contacts.sub_point, y.contacts.sub_point)); // (the flags ride with the points)
    int failed_open = 0;
    for (int k = 0; k < x.contacts.n_subs(); ++k) {
        const std::uint8_t f = x.contacts.sub_flags(k);
        failed_open += (f & odec::kSubOpen) && (f & odec::kSubFailed);
    }
    EXPECT_GT(failed_open, 10);
}

TEST(ContactRestOpen, AnOpenClosureFollowsTheGapAcross) {
    // While the thrown cube crosses the gap, the closures of its open sub-contacts with its
    // neighbour are the gap between their faces, as the blocks stand (their centroids, the
    // cubes hardly turning), though they are kept by reference and not updated.
    Stack st;
    build(st, 2, 1, 1);
    Model& m = st.m;
    ASSERT_TRUE(odec::prepare_cycle(m).empty());
    odec::test::run_steps(m, 200);
    m.blocks.vel[st.thrown] = Vec3(1.0, 0, 0);
    m.blocks.half_kick[st.thrown] = 1;
    const int c = odec::test::contact_between(m, st.thrown, st.neighbour);
    ASSERT_GE(c, 0);
    int checked = 0;
    for (int i = 0; i < 40; ++i) {
        // From the 20th on, static and dynamic mode by turns. Each change rescales the velocities
        // with the masses, so the static step after it takes the blocks' last move at the new
        // velocity (as every closure summed step by step does after a change of masses): the
        // closure may miss up to a step's motion, 2.5e-5 m here, but no more however often the
        // mode changes (the change of the form the open closures are held in takes each step's
        // increment once).
        if (i >= 20) {
            m.settings.dynamic = i % 2 == 0;
            m.geometry_changed = true; // (as 'set dyn' does: the masses are chosen again)
        }
        auto gap_now = [&] {
            return (m.blocks.centroid[st.neighbour].x() - 0.5) - (m.blocks.centroid[st.thrown].x() + 0.5);
        };
        odec::test::run_steps(m, 9);
        const double gap_before = gap_now();
        odec::test::run_steps(m, 1);
        const odec::ContactSet& cs = m.contacts;
        const int cc = odec::test::contact_between(m, st.thrown, st.neighbour);
        ASSERT_GE(cc, 0);
        const double gap = gap_now();
        if (gap < 1e-3) break;
        // Static mode's closure is the one its last step made, of the blocks before they moved
        // on that step; dynamic mode's, held by reference, that of the blocks as they stand.
        const double want = m.settings.dynamic ? -gap : -gap_before;
        const double tol = i < 21 ? 1e-6 : 3e-5;
        for (int k = cs.sub_offset[cc]; k < cs.sub_offset[cc + 1]; ++k) {
            ASSERT_TRUE(cs.sub_flags(k) & odec::kSubOpen);
            EXPECT_NEAR(odec::sub_closure(m, cc, k), want, tol) << "step " << m.step;
            ++checked;
        }
    }
    EXPECT_GT(checked, 40);
}

// The plain sub-contacts stepped many contacts at a time (contact_axes.h, step_plain_subs) give
// the bits of the scalar joint law, through landing, a cube thrown across a gap (sub-contacts
// that open, close, are made new and slip) and joints given cohesion that then fail.
TEST(ContactBatched, SteppingPlainSubContactsInBatchesGivesTheSameBits) {
    Stack on, off;
    build(on, 3, 2, 3);
    build(off, 3, 2, 3);
    double pressed_on = 0, pressed_off = 0;
    long batched = 0;
    {
        Batched b(true);
        run(on, 4000, &pressed_on);
        batched = on.m.contacts.batched;
    }
    {
        Batched b(false);
        run(off, 4000, &pressed_off);
        EXPECT_EQ(off.m.contacts.batched, 0);
    }
    // Most of the pressing contacts of the columns (3 x 2 x 3 cubes on the base, landed) stepped
    // in the batch at the last step.
    EXPECT_GE(batched, 15);
    EXPECT_GT(pressed_on, 1e3);
    EXPECT_EQ(pressed_on, pressed_off);
    const Model& x = on.m;
    const Model& y = off.m;
    expect_same_state(x, y);
    // Cohesion and tension that the slipping and opening sub-contacts break, and the cube thrown
    // again: some fail, in the batch's contacts too.
    for (Stack* st : {&on, &off}) {
        st->m.joint_materials[1].cohesion = 2e3;
        st->m.joint_materials[1].tension = 1e3;
        st->m.blocks.vel[st->thrown] = Vec3(-0.5, 0.3, 0);
        st->m.blocks.half_kick[st->thrown] = 1;
        Batched b(st == &on);
        odec::test::run_steps(st->m, 1500);
    }
    expect_same_state(x, y);
    int failed = 0;
    for (int k = 0; k < x.contacts.n_subs(); ++k) failed += (x.contacts.sub_flags(k) & odec::kSubFailed) != 0;
    EXPECT_GT(failed, 4);
}

// The update's memory of the open contacts it left alone (ContactSet::RestMemory), used within one
// run of the cycle: the same bits as looking at every sub-contact, through landing, a thrown cube
// and joints given cohesion between runs (which the memory must not outlive).
TEST(ContactRestOpen, TheMemoryOfOpenContactsGivesTheSameBits) {
    Stack on, off;
    build(on, 3, 2, 3);
    build(off, 3, 2, 3);
    for (Stack* st : {&on, &off}) {
        RestOpen r(st == &on);
        Model& m = st->m;
        ASSERT_TRUE(odec::prepare_cycle(m).empty());
        EXPECT_EQ(odec::test::run_steps(m, 1500).reason, odec::StopReason::Steps);
        m.blocks.vel[st->thrown] = Vec3(1.0, 0, 0);
        m.blocks.half_kick[st->thrown] = 1;
        for (int i = 0; i < 25; ++i) {
            EXPECT_EQ(odec::test::run_steps(m, 100).reason, odec::StopReason::Steps);
            // (How many steps left the quiet contacts without a look: the last of each hundred.)
            st->quiet_steps += m.contacts.rest.used_quiet > 0;
            st->close_steps += m.contacts.rest.used_close > 0;
        }
    }
    // Left alone by the memory at the last step: most of the stacks' side contacts; and without a
    // look (RestMemory::quiet) at many of the steps looked at, though the thrown cube's motion
    // makes the list be made again each time its reach has doubled.
    EXPECT_GT(on.m.contacts.rest.used, 10);
    EXPECT_EQ(off.m.contacts.rest.used, 0);
    EXPECT_GT(on.quiet_steps, 5);
    EXPECT_EQ(off.quiet_steps, 0);
    // Some by the closer bound alone (the blocks' motion since their references less what they
    // shared: close_reach_of), which must give the same bits too.
    EXPECT_GT(on.close_steps, 3);
    EXPECT_EQ(off.close_steps, 0);
    const Model& x = on.m;
    const Model& y = off.m;
    expect_same_state(x, y);
    // Cohesion given between runs: the open sub-contacts that had not failed fail at their next
    // step, whatever was remembered of them.
    for (Stack* st : {&on, &off}) {
        st->m.joint_materials[1].cohesion = 1e4;
        RestOpen r(st == &on);
        odec::test::run_steps(st->m, 500);
    }
    expect_same_state(x, y);
    int failed_open = 0;
    for (int k = 0; k < x.contacts.n_subs(); ++k) {
        const std::uint8_t f = x.contacts.sub_flags(k);
        failed_open += (f & odec::kSubOpen) && (f & odec::kSubFailed);
    }
    EXPECT_GT(failed_open, 10);
}
