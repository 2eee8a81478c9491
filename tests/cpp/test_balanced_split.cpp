// The contiguous split of weighted items among threads (core/balanced_split.hpp), used by the
// force loop's row blocks and the integrator's body ranges.
#include <gtest/gtest.h>

#include <vector>

#include "core/balanced_split.hpp"

using namespace granudrag;

namespace {
std::vector<long> prefix_of(const std::vector<long>& cost) {
  std::vector<long> prefix(cost.size() + 1, 0);
  for (std::size_t i = 0; i < cost.size(); ++i) prefix[i + 1] = prefix[i] + cost[i];
  return prefix;
}
}  // namespace

TEST(BalancedSplit, CheapItemsFirstGiveTheFirstPartMoreOfThem) {
  // Ten items of cost 1 (a frozen base), then ten of cost 4 (mobile grains): 50 in all, so the
  // first part ends where the running cost first reaches 25, after item 13 (10 + 4 x 4 = 26).
  std::vector<long> cost(20, 4);
  for (int i = 0; i < 10; ++i) cost[i] = 1;
  std::vector<long> bounds;
  balanced_split(prefix_of(cost), 2, bounds);
  EXPECT_EQ(bounds, (std::vector<long>{0, 14, 20}));
}

TEST(BalancedSplit, PartsCoverEveryItemOnceAndStayWithinOneItemOfTheirShare) {
  std::vector<long> cost;
  for (int i = 0; i < 1000; ++i) cost.push_back(1 + (i * 7919) % 13);
  const std::vector<long> prefix = prefix_of(cost);
  for (int parts : {1, 2, 3, 4, 7, 64}) {
    std::vector<long> bounds;
    balanced_split(prefix, parts, bounds);
    ASSERT_EQ(bounds.size(), static_cast<std::size_t>(parts + 1));
    EXPECT_EQ(bounds.front(), 0);
    EXPECT_EQ(bounds.back(), 1000);
    for (int k = 0; k < parts; ++k) {
      ASSERT_LE(bounds[k], bounds[k + 1]) << parts << " parts";
      const double share = static_cast<double>(prefix.back()) / parts;
      const long part_cost = prefix[bounds[k + 1]] - prefix[bounds[k]];
      EXPECT_LE(std::abs(part_cost - share), 2 * 13) << "part " << k << " of " << parts;
    }
  }
}

TEST(BalancedSplit, MorePartsThanItemsLeavesTheLastOnesEmpty) {
  std::vector<long> bounds;
  balanced_split(prefix_of({5, 5}), 4, bounds);
  EXPECT_EQ(bounds, (std::vector<long>{0, 1, 1, 2, 2}));
  balanced_split(prefix_of({}), 3, bounds);
  EXPECT_EQ(bounds, (std::vector<long>{0, 0, 0, 0}));
}
