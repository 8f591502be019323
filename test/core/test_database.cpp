#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include <malloc.h>

#include <gtest/gtest.h>

#include "scan_context_loop/core/pcl_adapters.h"
#include "scan_context_loop/core/database.h"
#include "scan_context_loop/core/detector.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

std::vector<float> randomKey(std::mt19937* rng, int dims) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> key(dims);
  for (float& v : key) v = u(*rng);
  return key;
}

KeyframeInfo stampedAtX(double stamp, double x = 0.0) {
  KeyframeInfo info;
  info.stamp = stamp;
  info.pose = Eigen::Isometry3d(Eigen::Translation3d(x, 0.0, 0.0));
  return info;
}

/// A configuration that returns every eligible keyframe, with the given exclusion windows.
Config windows(int frames, double seconds, double metres) {
  Config config;
  config.exclude_recent_frames = frames;
  config.exclude_recent_seconds = seconds;
  config.exclude_recent_distance = metres;
  config.num_candidates = 100;
  return config;
}

std::set<std::size_t> candidateSet(const QueryResult& result) {
  std::set<std::size_t> out;
  for (const auto& c : result.candidates) out.insert(c.index);
  return out;
}

TEST(Database, ExcludesTheMostRecentFramesAndSeesEachOneTheMomentItLeaves) {
  const Config config = windows(3, 0.0, 0.0);
  Database db(config);
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  for (int n = 0; n < 12; ++n) {
    const QueryResult r = db.query(d, stampedAtX(n));
    // Query n (before being added) may see keyframes 0 .. n - 4, every one of them.
    const std::size_t expected = n > 3 ? n - 3 : 0;
    EXPECT_EQ(r.eligible, expected) << "query " << n;
    ASSERT_EQ(r.candidates.size(), expected) << "query " << n;
    if (expected > 0) {
      EXPECT_EQ(*candidateSet(r).rbegin(), expected - 1);
    }
    ASSERT_TRUE(db.add(stampedAtX(n), d));
  }
}

TEST(Database, ExcludesByTimeGap) {
  const Config config = windows(0, 2.5, 0.0);
  Database db(config);
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  for (int n = 0; n < 10; ++n) ASSERT_TRUE(db.add(stampedAtX(0.5 * n), d));  // stamps 0 .. 4.5 s
  // A query at 5.0 s may see stamps <= 2.5 s: keyframes 0..5.
  const QueryResult r = db.query(d, stampedAtX(5.0));
  EXPECT_EQ(r.eligible, 6u);
  EXPECT_EQ(candidateSet(r), (std::set<std::size_t>{0, 1, 2, 3, 4, 5}));
  // An earlier query-only call must not see more, although the tree already holds more.
  EXPECT_EQ(candidateSet(db.query(d, stampedAtX(4.0))), (std::set<std::size_t>{0, 1, 2, 3}));
}

TEST(Database, ExcludesByTravelledDistance) {
  const Config config = windows(0, 0.0, 10.0);
  Database db(config);
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  // Drive 3 m per keyframe, then turn back: path length keeps growing while the position returns.
  const double xs[] = {0, 3, 6, 9, 12, 9, 6, 3};
  for (int n = 0; n < 8; ++n) ASSERT_TRUE(db.add(stampedAtX(n, xs[n]), d));
  EXPECT_NEAR(db.keyframe(7).path_length, 21.0, 1e-9);
  // Query back at x = 0 with path 24: keyframes with path <= 14 (0..4, at 0..12 m) are eligible,
  // although keyframe 7 is only 3 m away in space.
  const QueryResult r = db.query(d, stampedAtX(8, 0.0));
  EXPECT_EQ(candidateSet(r), (std::set<std::size_t>{0, 1, 2, 3, 4}));
  // A keyframe without a pose does not advance the path.
  KeyframeInfo no_pose;
  no_pose.stamp = 9;
  ASSERT_TRUE(db.add(no_pose, d));
  EXPECT_NEAR(db.keyframe(8).path_length, 21.0, 1e-9);
}

TEST(Database, KdTreeReturnsTheBruteForceNearestRingKeys) {
  Config config;
  config.exclude_recent_frames = 0;
  config.num_candidates = 10;
  Database db(config);
  std::mt19937 rng(1234);
  std::vector<std::vector<float>> keys;
  // Grow past several rebuilds of the kd-tree (the first after 1,024 keys) and check along the way,
  // so answers come from the tree, its brute-force tail and both together.
  for (int n = 0; n < 3000; ++n) {
    if (n % 97 == 5) {
      const auto query_key = randomKey(&rng, config.num_rings);
      std::vector<std::pair<float, std::size_t>> brute;
      for (std::size_t i = 0; i < keys.size(); ++i) {
        float d2 = 0.0f;
        for (int r = 0; r < config.num_rings; ++r) d2 += (keys[i][r] - query_key[r]) * (keys[i][r] - query_key[r]);
        brute.emplace_back(d2, i);
      }
      std::sort(brute.begin(), brute.end());
      std::set<std::size_t> expected;
      for (std::size_t i = 0; i < std::min<std::size_t>(10, brute.size()); ++i) expected.insert(brute[i].second);
      const QueryResult r = db.query(test::descriptorWithKey(query_key, config), stampedAtX(n));
      EXPECT_EQ(candidateSet(r), expected) << "database size " << n;
      for (const auto& c : r.candidates) {
        const auto it = std::find_if(brute.begin(), brute.end(), [&](const auto& b) { return b.second == c.index; });
        EXPECT_NEAR(c.ring_key_distance, std::sqrt(it->first), 1e-4);
      }
    }
    keys.push_back(randomKey(&rng, config.num_rings));
    ASSERT_TRUE(db.add(stampedAtX(n), test::descriptorWithKey(keys.back(), config)));
  }
  EXPECT_EQ(db.size(), 3000u);
}

/// Ring keys of `places` places each visited `visits` times (a key per place, every visit a little
/// off it), in visit order: the shape of a long run that keeps driving the same streets.
std::vector<std::vector<float>> revisitedKeys(int places, int visits, int dims, std::mt19937* rng) {
  std::vector<std::vector<float>> centres;
  for (int p = 0; p < places; ++p) centres.push_back(randomKey(rng, dims));
  std::normal_distribution<float> noise(0.0f, 0.02f);
  std::vector<std::vector<float>> keys;
  for (int v = 0; v < visits; ++v) {
    for (const auto& centre : centres) {
      keys.push_back(centre);
      for (float& value : keys.back()) value += noise(*rng);
    }
  }
  return keys;
}

TEST(Database, ApproximateSearchAboveTheLimitFindsWhatTheExactOneFinds) {
  // 300 places visited 40 times: 12,000 keys. One database searches them exactly, one approximately
  // (limit 0), one approximately again from the same keys; queries are new visits of the places.
  Config exact_config;
  exact_config.exclude_recent_frames = 0;
  exact_config.num_candidates = 10;
  Config approximate_config = exact_config;
  approximate_config.exact_search_limit = 0;
  Database exact(exact_config), approximate(approximate_config), again(approximate_config);
  std::mt19937 rng(99);
  const auto keys = revisitedKeys(300, 40, exact_config.num_rings, &rng);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    for (Database* db : {&exact, &approximate, &again}) {
      ASSERT_TRUE(db->add(stampedAtX(static_cast<double>(i)), test::descriptorWithKey(keys[i], exact_config)));
    }
  }
  std::normal_distribution<float> noise(0.0f, 0.02f);
  int same_nearest = 0, shared = 0, queries = 0;
  for (int q = 0; q < 200; ++q) {
    // A new visit of place q: its key as the database holds it plus fresh noise.
    std::vector<float> key = keys[static_cast<std::size_t>(q)];
    for (float& value : key) value += noise(rng);
    const KeyframeInfo info = stampedAtX(static_cast<double>(keys.size() + q));
    const QueryResult e = exact.query(test::descriptorWithKey(key, exact_config), info);
    const QueryResult a = approximate.query(test::descriptorWithKey(key, exact_config), info);
    const QueryResult b = again.query(test::descriptorWithKey(key, exact_config), info);
    ASSERT_EQ(e.candidates.size(), 10u);
    ASSERT_EQ(a.candidates.size(), 10u);
    EXPECT_EQ(candidateSet(a), candidateSet(b)) << "the same keys gave other candidates (query " << q << ")";
    const std::set<std::size_t> es = candidateSet(e), as = candidateSet(a);
    std::size_t common = 0;
    for (std::size_t index : as) common += es.count(index);
    shared += static_cast<int>(common);
    // The candidates come sorted by descriptor distance: the nearest ring key is the least of theirs.
    const auto nearest = std::min_element(e.candidates.begin(), e.candidates.end(), [](const auto& x, const auto& y) {
      return x.ring_key_distance < y.ring_key_distance;
    });
    same_nearest += static_cast<int>(as.count(nearest->index));
    for (const auto& c : a.candidates) {
      EXPECT_EQ(c.index % 300, static_cast<std::size_t>(q)) << "a candidate of another place (query " << q << ")";
    }
    ++queries;
  }
  std::printf(
      "approximate search: the exact nearest key among the candidates in %d of %d queries, %.2f of the 10 candidates "
      "shared\n",
      same_nearest, queries, shared / (10.0 * queries));
  EXPECT_GE(same_nearest, queries * 95 / 100);
  EXPECT_GE(shared, queries * 10 * 80 / 100);
}

TEST(Database, OdometryGateDropsFarCandidates) {
  Config config = windows(0, 0.0, 0.0);
  config.gate_odometry_drift = 0.0;  // a fixed radius here; the drift allowance has its own test
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  for (double gate : {0.0, 50.0}) {
    config.gate_odometry_distance = gate;
    Database db(config);
    ASSERT_TRUE(db.add(stampedAtX(0, 0.0), d));    // 0 m
    ASSERT_TRUE(db.add(stampedAtX(1, 100.0), d));  // 100 m
    const QueryResult r = db.query(d, stampedAtX(2, 10.0));
    if (gate == 0.0) {
      EXPECT_EQ(candidateSet(r), (std::set<std::size_t>{0, 1}));
    } else {
      EXPECT_EQ(candidateSet(r), (std::set<std::size_t>{0}));  // keyframe 1 is 90 m away
    }
    // A query without a pose is not gated.
    KeyframeInfo no_pose;
    no_pose.stamp = 3;
    EXPECT_EQ(db.query(d, no_pose).candidates.size(), 2u);
  }
}

TEST(Database, OdometryGateAllowsForDriftAlongThePathBetween) {
  Config config = windows(0, 0.0, 0.0);
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  for (double drift : {0.5, 1.1}) {
    config.gate_odometry_drift = drift;
    Database db(config);
    ASSERT_TRUE(db.add(stampedAtX(0, 0.0), d));    // path 0 m
    ASSERT_TRUE(db.add(stampedAtX(1, 100.0), d));  // path 100 m
    // The query at 10 m has driven 190 m: keyframe 0 is 10 m away after 190 m of path (allowance
    // 95 m at 0.5), keyframe 1 is 90 m away after 90 m (allowance 45 m at 0.5, 99 m at 1.1).
    const QueryResult r = db.query(d, stampedAtX(2, 10.0));
    if (drift < 1.0) {
      EXPECT_EQ(candidateSet(r), (std::set<std::size_t>{0}));
    } else {
      EXPECT_EQ(candidateSet(r), (std::set<std::size_t>{0, 1}));
    }
  }
}

TEST(Database, RejectsBadKeyframesAndKeepsItsContents) {
  Config config;
  Database db(config);
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  ASSERT_TRUE(db.add(stampedAtX(10.0), d));
  std::string error;
  EXPECT_FALSE(db.add(stampedAtX(9.0), d, &error));
  EXPECT_NE(error.find("earlier"), std::string::npos) << error;
  EXPECT_FALSE(db.add(stampedAtX(NAN), d, &error));
  KeyframeInfo bad_pose = stampedAtX(11.0);
  bad_pose.pose->translation().x() = NAN;
  EXPECT_FALSE(db.add(bad_pose, d, &error));
  Config other = config;
  other.num_sectors = 30;
  EXPECT_FALSE(db.add(stampedAtX(11.0), test::descriptorWithKey(std::vector<float>(20, 0.5f), other), &error));
  EXPECT_EQ(db.size(), 1u);
  EXPECT_TRUE(db.add(stampedAtX(10.0), d)) << "equal stamps are allowed";
  EXPECT_EQ(db.size(), 2u);
}

TEST(Database, RefusesAPoseWhoseRotationIsNotARotation) {
  Config config;
  Database db(config);
  const Descriptor d = test::descriptorWithKey(std::vector<float>(20, 0.5f), config);
  ASSERT_TRUE(db.add(stampedAtX(1.0), d));
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // An unnormalised quaternion's matrix, an all-zero quaternion's, a mirror: none is a rotation.
  for (const Eigen::Matrix3d& linear : {Eigen::Matrix3d(1.1 * yaw), Eigen::Matrix3d(Eigen::Matrix3d::Zero()),
                                        Eigen::Matrix3d(yaw * Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal())}) {
    KeyframeInfo bad = stampedAtX(2.0, 1.0);
    bad.pose->linear() = linear;
    std::string error;
    EXPECT_FALSE(db.add(bad, d, &error)) << linear;
    EXPECT_NE(error.find("not a rotation"), std::string::npos) << error;
  }
  EXPECT_EQ(db.size(), 1u);
  KeyframeInfo rounded = stampedAtX(2.0, 1.0);  // a rotation as a text file with 7 digits carries it
  rounded.pose->linear() = yaw + Eigen::Matrix3d::Constant(1e-7);
  std::string error;
  EXPECT_TRUE(db.add(rounded, d, &error)) << error;
}

TEST(Database, NeverIndexesANonFiniteDescriptor) {
  Config config;
  config.exclude_recent_frames = 0;
  Database db(config);
  const std::vector<float> key(20, 0.5f);
  ASSERT_TRUE(db.add(stampedAtX(1.0), test::descriptorWithKey(key, config)));
  std::vector<float> overflowed = key;
  overflowed[3] = std::numeric_limits<float>::infinity();
  std::string error;
  EXPECT_FALSE(db.add(stampedAtX(2.0), test::descriptorWithKey(overflowed, config), &error));
  EXPECT_NE(error.find("not finite"), std::string::npos) << error;
  Descriptor nan_sector = test::descriptorWithKey(key, config);
  nan_sector.sector_key[7] = NAN;
  EXPECT_FALSE(db.add(stampedAtX(2.0), nan_sector, &error));
  EXPECT_EQ(db.size(), 1u);
  // Nor is one a query: it finds nothing, and a good query still finds keyframe 0.
  EXPECT_TRUE(db.query(test::descriptorWithKey(overflowed, config), stampedAtX(3.0)).candidates.empty());
  const QueryResult good = db.query(test::descriptorWithKey(key, config), stampedAtX(3.0));
  ASSERT_FALSE(good.candidates.empty());
  EXPECT_EQ(good.best()->index, 0u);
}

TEST(Database, EmptyDescriptorNeverMatchesAndMemoryStaysInBudget) {
  Config config;
  config.exclude_recent_frames = 0;
  LoopDetector detector(config);
  const auto scene = test::streetScene(9);
  ASSERT_TRUE(detector.process(viewOf(scene), stampedAtX(0)).accepted);
  const Detection empty = detector.process(viewOf(pcl::PointCloud<pcl::PointXYZ>()), stampedAtX(1));
  EXPECT_TRUE(empty.accepted);
  EXPECT_FALSE(empty.query.matched);
  EXPECT_TRUE(empty.query.candidates.empty());
  // The same scene again matches keyframe 0, never the empty keyframe 1.
  const Detection again = detector.process(viewOf(scene), stampedAtX(2));
  ASSERT_TRUE(again.query.matched);
  EXPECT_EQ(again.query.best()->index, 0u);
  EXPECT_NEAR(again.query.best()->alignment.distance, 0.0, 2e-3);  // 0 up to the int8 rounding
  EXPECT_EQ(again.index, 2u);
  EXPECT_LE(detector.database().bytesPerKeyframe(), 3u * 1024u);
}

/// Bytes the heap has handed out and not taken back (glibc's own count, mmapped chunks included).
std::size_t heapInUse() {
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

/// The heap growth of a database of 20,000 real street descriptors, measured by the allocator, against
/// bytesPerKeyframe() (what doc/benchmark.md's bytes per keyframe and the node's memory figures rest on) and the 6 KB
/// budget.
void expectHeapPerKeyframeAsStated(const Config& config) {
  std::vector<Descriptor> scenes;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) scenes.push_back(makeDescriptor(test::streetScene(seed), config));
  constexpr std::size_t kKeyframes = 20000;
  std::size_t before = 0, after = 0;
  {
    Database db(config);
    before = heapInUse();
    std::string error;
    for (std::size_t i = 0; i < kKeyframes; ++i) {
      ASSERT_TRUE(db.add(stampedAtX(static_cast<double>(i), 2.0 * i), Descriptor(scenes[i % scenes.size()]), &error)) << error;
      if (i % 2000 == 1999) db.query(scenes[0], stampedAtX(static_cast<double>(i) + 0.5, 2.0 * i));  // the tree is built
    }
    after = heapInUse();
    const double measured = static_cast<double>(after - before) / kKeyframes;
    const double stated = static_cast<double>(db.bytesPerKeyframe());
    std::printf("heap per keyframe: measured %.0f bytes, stated %.0f bytes\n", measured, stated);
    EXPECT_LE(measured, 1.25 * stated);
    EXPECT_GE(measured, 0.75 * stated);
    EXPECT_LE(measured, 6.0 * 1024.0);
  }
  // Everything is returned with the database.
  EXPECT_LE(heapInUse(), before + 64 * 1024);
}

TEST(Database, MeasuredHeapPerKeyframeMatchesTheStatedBytes) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "a sanitizer's allocator replaces glibc's, whose count this reads";
#endif
  expectHeapPerKeyframeAsStated(Config());
}

TEST(Database, MeasuredHeapPerKeyframeMatchesTheStatedBytesWithApproximateSearch) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "a sanitizer's allocator replaces glibc's, whose count this reads";
#endif
  Config config;
  config.exact_search_limit = 0;
  expectHeapPerKeyframeAsStated(config);
}

}  // namespace
}  // namespace scan_context_loop
