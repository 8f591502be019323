// The worker's exception barrier: what a keyframe or task throws is caught and named. No ROS master.
#include <new>
#include <stdexcept>

#include <gtest/gtest.h>

#include "shared/exception_barrier.h"

namespace scan_context_loop {
namespace {

TEST(ExceptionBarrier, WorkThatReturnsRunsOnce) {
  int runs = 0;
  std::string what = "untouched";
  EXPECT_TRUE(runCatching([&] { ++runs; }, &what));
  EXPECT_EQ(runs, 1);
  EXPECT_EQ(what, "untouched");
}

TEST(ExceptionBarrier, WhatWorkThrowsIsCaughtAndNamed) {
  std::string what;
  EXPECT_FALSE(runCatching([] { throw std::runtime_error("registration: no correspondences"); }, &what));
  EXPECT_EQ(what, "registration: no correspondences");
  EXPECT_FALSE(runCatching([] { throw std::bad_alloc(); }, &what));
  EXPECT_NE(what.find("bad_alloc"), std::string::npos) << what;
  EXPECT_FALSE(runCatching([] { throw 42; }, &what));
  EXPECT_NE(what.find("not a std::exception"), std::string::npos) << what;
}

}  // namespace
}  // namespace scan_context_loop
