// The progress line's rate and ETA, and after a resume: this run's steps only.
#include <gtest/gtest.h>

#include "core/progress.hpp"

namespace granudrag {

TEST(Progress, RateAndEtaOfAFreshRun) {
  const Progress p("pull", 1000);
  EXPECT_EQ(p.line(250, 10.0), "pull: 250/1000 (25%), 25 steps/s, elapsed 10 s, ETA 30 s");
  EXPECT_EQ(p.line(250, 10.0, 100.0, "particle-steps"),
            "pull: 250/1000 (25%), 2.5e+03 particle-steps/s, elapsed 10 s, ETA 30 s");
}

TEST(Progress, AResumedRunCountsOnlyItsOwnSteps) {
  // Resumed at step 600 of 1,000: 100 steps in 10 s is 10 steps/s and 30 s to go, not the
  // 70 steps/s and 4 s that counting the first run's steps would claim.
  const Progress p("pull", 1000, 600);
  EXPECT_EQ(p.line(700, 10.0), "pull: 700/1000 (70%), 10 steps/s, elapsed 10 s, ETA 30 s");
  EXPECT_EQ(p.line(600, 0.0), "pull: 600/1000 (60%), 0 steps/s, elapsed 0 s, ETA 0 s");
}

}  // namespace granudrag
