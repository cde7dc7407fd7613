// The contact set's growable arrays (PodArray): what they hold through growth, gaps and copies,
// and that growing a large one does not hold its old and new storage at once.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "engine/pod_array.h"

#include "../../bench/memory.h"
#include "../sanitizers.h"

namespace odec {
namespace {

TEST(PodArray, KeepsItsElementsThroughGrowthAndShrinking) {
    PodArray<int> a;
    std::vector<int> ref;
    for (int i = 0; i < 100000; ++i) {
        a.push_back(i * 7);
        ref.push_back(i * 7);
    }
    ASSERT_EQ(a.size(), ref.size());
    EXPECT_TRUE(std::equal(a.begin(), a.end(), ref.begin()));
    a.resize(10);
    a.shrink_to_fit();
    EXPECT_EQ(a.capacity(), 10u);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(a[i], i * 7);
    a.reserve(1000000);
    EXPECT_EQ(a.capacity(), 1000000u);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(a[i], i * 7);
}

TEST(PodArray, NewElementsAreZeroOrTheValueGiven) {
    PodArray<Eigen::Vector3d> v(3);
    for (const auto& x : v) EXPECT_EQ(x, Eigen::Vector3d::Zero());
    v[1] = Eigen::Vector3d(1, 2, 3);
    v.resize(5, Eigen::Vector3d(4, 5, 6));
    EXPECT_EQ(v[1], Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(v[4], Eigen::Vector3d(4, 5, 6));
    PodArray<double> d;
    d.assign(4, 2.5);
    d.resize(6);
    EXPECT_EQ(d[3], 2.5);
    EXPECT_EQ(d[5], 0.0);
}

TEST(PodArray, PushingOneOfItsOwnElementsWhileGrowing) {
    PodArray<Eigen::Vector2d> v;
    v.push_back(Eigen::Vector2d(1, 2));
    while (v.size() < v.capacity()) v.push_back(Eigen::Vector2d(0, 0));
    v.push_back(v[0]); // grows: the element is copied before the storage moves
    EXPECT_EQ(v.back(), Eigen::Vector2d(1, 2));
}

TEST(PodArray, CopiesAreDeepAndMovesTakeTheStorage) {
    PodArray<std::int64_t> a{1, 2, 3};
    PodArray<std::int64_t> b = a;
    b[0] = 9;
    EXPECT_EQ(a[0], 1);
    EXPECT_NE(a, b);
    const std::int64_t* p = b.data();
    PodArray<std::int64_t> c = std::move(b);
    EXPECT_EQ(c.data(), p);
    EXPECT_TRUE(b.empty());
    c.swap(a);
    EXPECT_EQ(a[0], 9);
    EXPECT_EQ(c[0], 1);
    a = c;
    EXPECT_EQ(a, c);
}

// The point of the type: a large array grows where it lies (the allocator moves its mapping)
// instead of being copied, so the process never holds the old and the new storage together.
// 64 MB of doubles, every page touched, grown by an eighth as a refresh pass grows the contact
// set: the peak resident memory rises by far less than the 64 MB a copy would hold.
TEST(PodArray, GrowingALargeArrayDoesNotHoldTwoCopies) {
#if defined(ODEC_TEST_ASAN)
    GTEST_SKIP() << "AddressSanitizer's allocator copies what realloc grows (and keeps the old block in "
                    "quarantine): the memory this test measures is glibc's";
#endif
    const std::size_t n = std::size_t{8} << 20; // 64 MB
    PodArray<double> a;
    a.resize(n, 1.0);
    if (!bench::reset_peak_rss()) GTEST_SKIP() << "/proc/self/clear_refs cannot be written here";
    const double before = bench::peak_rss_bytes();
    ASSERT_GT(before, 0);
    a.reserve(n + n / 8);
    a.resize_for_overwrite(n + n / 8);
    for (std::size_t i = n; i < a.size(); ++i) a[i] = 2.0;
    const double grown = bench::peak_rss_bytes() - before;
    EXPECT_EQ(a[0], 1.0);
    EXPECT_EQ(a[n - 1], 1.0);
    EXPECT_EQ(a[n], 2.0);
    // The eighth written (8 MB) and little else: a copy would add 64 MB.
    EXPECT_LT(grown, 16e6) << "the peak rose by " << grown / 1e6 << " MB";
}

} // namespace
} // namespace odec
