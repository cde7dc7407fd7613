#include <gtest/gtest.h>
#include <cstdio>
#include <fstream>
#include <sstream>
#include "engine/blocks.h"
#include "test_util.h"
using odec::test::Session;
TEST(ZZDebug, Dump) {
    const char* f = getenv("DBG_SCRIPT");
    if (!f) GTEST_SKIP();
    Session s;
    std::ifstream in(f); std::stringstream ss; ss << in.rdbuf();
    ASSERT_TRUE(s.run(ss.str())) << s.error();
    if (getenv("DBG_DETECT")) { odec::refresh_world_vertices(s.model); odec::detect_contacts(s.model); }
    const auto& cs = s.model.contacts; const auto& b = s.model.blocks;
    for (int c = 0; c < cs.size(); ++c) {
        auto info = odec::contact_info(s.model, c);
        double maxsn = 0; for (int k = cs.sub_offset[c]; k < cs.sub_offset[c+1]; ++k) maxsn = std::max(maxsn, std::abs(cs.sub_sn[k]));
        printf("c%d id%d blocks %d-%d n=(%.3f,%.3f,%.3f) gap %.4g area %.4g nsub %d sn %.4g un %.4g maxsubsn %.4g\n", c, cs.id[c], b.id[cs.block_a[c]], b.id[cs.block_b[c]],
          cs.normal[c].x(), cs.normal[c].y(), cs.normal[c].z(), cs.gap[c], info.area, info.n_subs, info.normal_stress, info.normal_disp, maxsn);
        if (getenv("DBG_SUBS")) for (int k = cs.sub_offset[c]; k < cs.sub_offset[c+1]; ++k)
            printf("   side %d key %llx area %.4g un %.4g sn %.4g\n", cs.sub_side[k], (long long)cs.sub_key[k], cs.sub_area[k], cs.sub_un[k], cs.sub_sn[k]);
    }
}
#include "engine/common_plane.h"
TEST(ZZDebug, Pair) {
    const char* f = getenv("DBG_SCRIPT");
    if (!f || !getenv("DBG_A")) GTEST_SKIP();
    Session s;
    std::ifstream in(f); std::stringstream ss; ss << in.rdbuf();
    ASSERT_TRUE(s.run(ss.str())) << s.error();
    int ia = s.model.block_index(atoi(getenv("DBG_A"))), ib = s.model.block_index(atoi(getenv("DBG_B")));
    auto pa = odec::world_shape(s.model, ia), pb = odec::world_shape(s.model, ib);
    auto gap = [&](Eigen::Vector3d n) { double ha=-1e300, lb=1e300; for (auto& v: pa.vertices) ha = std::max(ha, n.dot(v)); for (auto& v: pb.vertices) lb = std::min(lb, n.dot(v)); return lb-ha; };
    odec::BlockView va{pa.vertices.data(), &pa}, vb{pb.vertices.data(), &pb};
    for (int k = 0; k < pa.n_faces(); ++k) { auto n = odec::world_face_normal(va, k); printf("A face %d n=(%.3f %.3f %.3f) gap %.4g joint %d\n", k, n.x(), n.y(), n.z(), gap(n), pa.face_joint.empty()?-1:pa.face_joint[k]); }
    for (int k = 0; k < pb.n_faces(); ++k) { auto n = -odec::world_face_normal(vb, k); printf("B face %d n=(%.3f %.3f %.3f) gap %.4g joint %d\n", k, n.x(), n.y(), n.z(), gap(n), pb.face_joint.empty()?-1:pb.face_joint[k]); }
    auto cp = odec::find_common_plane(pa, pb, nullptr);
    printf("cp n=(%.3f %.3f %.3f) gap %.4g\n", cp.normal.x(), cp.normal.y(), cp.normal.z(), cp.gap);
    for (auto& v: pa.vertices) printf("A v %.4f %.4f %.4f\n", v.x(), v.y(), v.z());
    for (auto& v: pb.vertices) printf("B v %.4f %.4f %.4f\n", v.x(), v.y(), v.z());
}
