// TaskThread runs posted tasks in order on its own thread; RateLimit is a token bucket; MinInterval spaces
// events on a clock that may go back.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include "scan_context_loop/core/rate_limit.h"
#include "scan_context_loop/core/task_thread.h"

namespace scan_context_loop {
namespace {

TEST(TaskThread, RunsTasksInOrderOnItsOwnThreadAndSurvivesOneThatThrows) {
  TaskThread thread;
  std::vector<int> order;
  std::promise<std::thread::id> where;
  ASSERT_TRUE(thread.post([&] { where.set_value(std::this_thread::get_id()); }));
  ASSERT_TRUE(thread.post([] { throw std::runtime_error("a failing task"); }));
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(thread.post([&order, i] { order.push_back(i); }));
  std::promise<void> done;
  ASSERT_TRUE(thread.post([&] { done.set_value(); }));
  ASSERT_EQ(done.get_future().wait_for(std::chrono::seconds(10)), std::future_status::ready);
  EXPECT_NE(where.get_future().get(), std::this_thread::get_id());
  ASSERT_EQ(order.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(order[i], i);
  EXPECT_EQ(thread.failures(), 1u);
}

TEST(TaskThread, RefusesPostsBeyondItsCapacityAndAfterStop) {
  TaskThread thread(2);
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::promise<void> started;
  ASSERT_TRUE(thread.post([&started, gate] {
    started.set_value();
    gate.wait();
  }));
  started.get_future().wait();  // the thread holds the first task: the queue is empty
  EXPECT_TRUE(thread.post([] {}));
  EXPECT_TRUE(thread.post([] {}));
  EXPECT_FALSE(thread.post([] {}));  // full
  EXPECT_EQ(thread.waiting(), 2u);
  EXPECT_TRUE(thread.post([] {}, true)) << "a reply is taken beyond the capacity";
  EXPECT_EQ(thread.waiting(), 3u);
  release.set_value();
  thread.stop();
  EXPECT_FALSE(thread.post([] {}));
  EXPECT_FALSE(thread.post([] {}, true)) << "nothing is taken once stopped";
  thread.stop();  // idempotent
}

TEST(RateLimit, PassesABurstThenTheRate) {
  RateLimit limit(1000.0, 4000.0);  // 1 kB/s, bursts of 4 kB
  EXPECT_TRUE(limit.take(3000, 0.0));
  EXPECT_FALSE(limit.take(2000, 0.0));  // 1 kB left
  EXPECT_TRUE(limit.take(1000, 0.0));
  EXPECT_FALSE(limit.take(1, 0.0));
  EXPECT_FALSE(limit.take(600, 0.5));  // 500 B came back
  EXPECT_TRUE(limit.take(500, 0.5));
  EXPECT_TRUE(limit.take(4000, 100.0));  // never more than the burst saved up
  EXPECT_FALSE(limit.take(1, 100.0));
  EXPECT_FALSE(limit.take(10, 99.0));  // a clock going back gives nothing
}

// LIO-SAM's hook at most once a second of ROS time: when a bag loops, ROS time goes back by the bag's
// length, and the next loop must go out then, not a bag's length later.
TEST(MinInterval, ATimeBeforeTheLastEventStartsAfresh) {
  MinInterval interval;
  EXPECT_TRUE(interval.due(1000.0, 1.0));
  interval.record(1000.0);
  EXPECT_FALSE(interval.due(1000.5, 1.0));
  EXPECT_TRUE(interval.due(1001.0, 1.0));
  EXPECT_TRUE(interval.due(400.0, 1.0)) << "the clock went back (a bag played again)";
  interval.record(400.0);
  EXPECT_FALSE(interval.due(400.2, 1.0));
  EXPECT_TRUE(interval.due(401.5, 1.0));
}

}  // namespace
}  // namespace scan_context_loop
