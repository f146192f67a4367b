// The sweep's ETA cost model: exact when every class's cost is constant, whatever the mix done so
// far; a class not seen yet costs the mean of those seen.

#include "emrm/campaign/eta.hpp"

#include <gtest/gtest.h>

namespace emrm::campaign {
namespace eta_test {

TEST(EtaModel, NothingDoneGivesNoEstimate) {
  const EtaModel eta({1, 2, 3});
  EXPECT_FALSE(eta.remaining_seconds(1.0).has_value());
}

TEST(EtaModel, ExactForConstantCostsPerClassWhateverTheOrder) {
  // 10 dear cells of 2 s and 10 cheap ones of 0.5 s on two fully busy workers: 12.5 s in all.
  EtaModel eta({0, 10, 10});
  double busy = 0.0;
  for (int i = 0; i < 5; ++i, busy += 2.0) eta.record(2, 2.0);
  for (int i = 0; i < 2; ++i, busy += 0.5) eta.record(1, 0.5);
  const double elapsed = busy / 2.0;
  const auto left = eta.remaining_seconds(elapsed);
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(*left, (5 * 2.0 + 8 * 0.5) / 2.0, 1e-12);
  EXPECT_NEAR(elapsed + *left, (10 * 2.0 + 10 * 0.5) / 2.0, 1e-12);
  // A rate over all cells done would say 13 cells × (5.5 s / 7 cells) = 10.2 s.
}

TEST(EtaModel, AClassNotSeenYetCostsTheMeanOfThoseSeen) {
  EtaModel eta({4, 0, 2});
  eta.record(2, 3.0);
  eta.record(2, 1.0);                                        // mean 2 s
  EXPECT_NEAR(*eta.remaining_seconds(4.0), 4 * 2.0, 1e-12);  // one worker: wall time = busy time
}

TEST(EtaModel, MoreCellsThanCountedNeverGoNegative) {
  EtaModel eta({0, 1, 0});
  eta.record(1, 1.0);
  eta.record(1, 1.0);
  eta.record(7, 1.0);  // an out-of-range class is clamped
  EXPECT_NEAR(*eta.remaining_seconds(3.0), 0.0, 1e-12);
}

}  // namespace eta_test
}  // namespace emrm::campaign
