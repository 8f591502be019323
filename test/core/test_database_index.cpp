// The ring-key index's rebuilds on the database's own thread: exact results across them, the same
// candidates in every run, nothing unsearchable, a clean destructor while one is in flight.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "scan_context_loop/core/database.h"
#include "test_scenes.h"

namespace scan_context_loop {
namespace {

std::vector<std::vector<float>> randomKeys(std::size_t count, int dims, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<std::vector<float>> keys(count, std::vector<float>(dims));
  for (auto& key : keys) {
    for (float& v : key) v = u(rng);
  }
  return keys;
}

KeyframeInfo stampedOnly(double stamp) {
  KeyframeInfo info;
  info.stamp = stamp;
  return info;
}

Config everyKeyframeEligible(int candidates, int exact_limit) {
  Config config;
  config.exclude_recent_frames = 0;
  config.exclude_recent_seconds = 0.0;
  config.exclude_recent_distance = 0.0;
  config.num_candidates = candidates;
  config.exact_search_limit = exact_limit;
  return config;
}

/// (index, ring-key distance) of every candidate, in order.
std::vector<std::pair<std::size_t, double>> answer(const QueryResult& r) {
  std::vector<std::pair<std::size_t, double>> out;
  for (const auto& c : r.candidates) out.emplace_back(c.index, c.ring_key_distance);
  return out;
}

TEST(DatabaseIndex, ExactBelowTheLimitAcrossBackgroundRebuilds) {
  const Config config = everyKeyframeEligible(10, 20000);
  Database db(config);
  const auto keys = randomKeys(12000, config.num_rings, 5);
  const auto queries = randomKeys(400, config.num_rings, 6);
  bool asked_in_flight = false;
  for (std::size_t n = 0; n < keys.size(); ++n) {
    if (n % 31 == 7) {
      const auto& q = queries[(n / 31) % queries.size()];
      std::vector<std::pair<float, std::size_t>> brute;
      for (std::size_t i = 0; i < n; ++i) {
        float d2 = 0.0f;
        for (int r = 0; r < config.num_rings; ++r) d2 += (keys[i][r] - q[r]) * (keys[i][r] - q[r]);
        brute.emplace_back(d2, i);
      }
      std::sort(brute.begin(), brute.end());
      brute.resize(std::min<std::size_t>(10, brute.size()));
      asked_in_flight = asked_in_flight || db.indexBuilds().in_flight;
      const QueryResult r = db.query(test::descriptorWithKey(q, config), stampedOnly(static_cast<double>(n)));
      std::set<std::size_t> expected, got;
      for (const auto& b : brute) expected.insert(b.second);
      for (const auto& c : r.candidates) got.insert(c.index);
      ASSERT_EQ(got, expected) << "database size " << n;
      for (const auto& c : r.candidates) {
        const auto it = std::find_if(brute.begin(), brute.end(), [&](const auto& b) { return b.second == c.index; });
        EXPECT_NEAR(c.ring_key_distance, std::sqrt(it->first), 1e-4);
      }
    }
    ASSERT_TRUE(db.add(stampedOnly(static_cast<double>(n)), test::descriptorWithKey(keys[n], config)));
  }
  // The index was rebuilt several times, and queries came while a build was running.
  EXPECT_GE(db.indexBuilds().background, 5u);
  EXPECT_TRUE(asked_in_flight);
}

/// Candidates of a query every 7 keyframes over `count` random keys with approximate search;
/// `pause` makes the owner slower, so the builder is further ahead at each query.
std::vector<std::vector<std::pair<std::size_t, double>>> run(std::size_t count, int exact_limit, bool pause,
                                                             Database::IndexBuilds* builds) {
  const Config config = everyKeyframeEligible(10, exact_limit);
  Database db(config);
  const auto keys = randomKeys(count, config.num_rings, 11);
  const auto queries = randomKeys(count / 7 + 1, config.num_rings, 12);
  std::vector<std::vector<std::pair<std::size_t, double>>> answers;
  for (std::size_t n = 0; n < count; ++n) {
    if (n % 7 == 3) {
      answers.push_back(answer(db.query(test::descriptorWithKey(queries[n / 7], config), stampedOnly(static_cast<double>(n)))));
    }
    // Give the builder time to finish long before the swap point, unlike the run without pauses.
    if (pause && n % 500 == 0 && db.indexBuilds().in_flight) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_TRUE(db.add(stampedOnly(static_cast<double>(n)), test::descriptorWithKey(keys[n], config)));
  }
  *builds = db.indexBuilds();
  return answers;
}

TEST(DatabaseIndex, ExactSearchGivesTheSameCandidatesWhateverTheBuilderTiming) {
  Database::IndexBuilds first_builds, second_builds;
  const auto first = run(20000, 20000, false, &first_builds);
  const auto second = run(20000, 20000, true, &second_builds);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t q = 0; q < first.size(); ++q) ASSERT_EQ(first[q], second[q]) << "query " << q;
  EXPECT_EQ(first_builds.background, second_builds.background);
  EXPECT_GE(first_builds.background, 8u);
}

TEST(DatabaseIndex, EveryEligibleKeyIsFoundWithApproximateSearch) {
  const Config config = everyKeyframeEligible(1, 0);
  Database db(config);
  const auto keys = randomKeys(30000, config.num_rings, 21);
  std::size_t missed = 0;
  for (std::size_t n = 0; n < keys.size(); ++n) {
    ASSERT_TRUE(db.add(stampedOnly(static_cast<double>(n)), test::descriptorWithKey(keys[n], config)));
    // The newest key (in the tail) and an older one (in the index, or in a build's snapshot).
    for (const std::size_t i : {n, n / 2}) {
      const QueryResult r = db.query(test::descriptorWithKey(keys[i], config), stampedOnly(static_cast<double>(n)));
      if (r.candidates.empty() || r.candidates[0].index != i || r.candidates[0].ring_key_distance != 0.0) ++missed;
    }
  }
  EXPECT_EQ(missed, 0u);
  // And every key once more, at the end.
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const QueryResult r = db.query(test::descriptorWithKey(keys[i], config), stampedOnly(static_cast<double>(keys.size())));
    ASSERT_FALSE(r.candidates.empty());
    EXPECT_EQ(r.candidates[0].index, i);
  }
  EXPECT_EQ(db.indexedCount(), keys.size());
}

TEST(DatabaseIndex, ALoadedBatchIsSearchedExactlyUntilItsIndexIsBuilt) {
  // 30,000 loaded keys above a 10,000-key exact limit: appendSessions returns before the kd-tree is
  // built; every query meanwhile scans all keys, so the nearest key is the stored one itself.
  const Config config = everyKeyframeEligible(5, 10000);
  const auto keys = randomKeys(30000, config.num_rings, 41);
  std::vector<Keyframe> prior(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    prior[i].info.stamp = static_cast<double>(i);
    prior[i].descriptor = test::descriptorWithKey(keys[i], config);
  }
  Database db(config);
  ASSERT_TRUE(db.appendSessions(std::move(prior)));
  EXPECT_EQ(db.indexBuilds().batches_behind, 1u);
  EXPECT_EQ(db.indexBuilds().at_once, 0u);
  EXPECT_EQ(db.indexedCount(), keys.size());
  std::size_t missed = 0;
  for (std::size_t i = 0; i < keys.size(); i += 97) {
    const QueryResult r = db.query(test::descriptorWithKey(keys[i], config), stampedOnly(1.0));
    if (r.candidates.empty() || r.candidates[0].ring_key_distance != 0.0) ++missed;
  }
  EXPECT_EQ(missed, 0u);
  // Once the build is done, the next call swaps it in.
  while (!db.indexBuilds().finished) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  db.query(test::descriptorWithKey(keys[0], config), stampedOnly(1.0));
  EXPECT_FALSE(db.indexBuilds().in_flight);
  const QueryResult r = db.query(test::descriptorWithKey(keys[123], config), stampedOnly(1.0));
  ASSERT_FALSE(r.candidates.empty());
  EXPECT_EQ(r.candidates[0].ring_key_distance, 0.0);
}

TEST(DatabaseIndex, DestructorJoinsARebuildInFlight) {
  const Config config = everyKeyframeEligible(5, 0);
  const auto keys = randomKeys(60000, config.num_rings, 31);
  for (const std::size_t loaded : {0, 20000, 50000}) {
    std::vector<Keyframe> prior(loaded);
    for (std::size_t i = 0; i < loaded; ++i) {
      prior[i].info.stamp = static_cast<double>(i);
      prior[i].descriptor = test::descriptorWithKey(keys[i], config);
    }
    bool in_flight = false;
    {
      Database db(config);
      ASSERT_TRUE(db.appendSessions(std::move(prior)));
      // Above the exact limit (0 here) a loaded batch's index is built in the background.
      EXPECT_EQ(db.indexBuilds().at_once, 0u);
      EXPECT_EQ(db.indexBuilds().batches_behind, loaded > 0 ? 1u : 0u);
      // Add keys until a build starts, and leave at once.
      for (std::size_t n = loaded; n < keys.size() && !db.indexBuilds().in_flight; ++n) {
        ASSERT_TRUE(db.add(stampedOnly(static_cast<double>(n)), test::descriptorWithKey(keys[n], config)));
        db.query(test::descriptorWithKey(keys[n], config), stampedOnly(static_cast<double>(n)));
      }
      in_flight = db.indexBuilds().in_flight;
    }
    EXPECT_TRUE(in_flight) << loaded << " keyframes loaded";
  }
}

}  // namespace
}  // namespace scan_context_loop
