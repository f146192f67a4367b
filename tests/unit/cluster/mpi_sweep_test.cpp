#include "emrm/cluster/mpi_sweep.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>
#include <string>

namespace emrm::cluster {
namespace mpi_sweep_test {

using ::testing::HasSubstr;

// An environment of the given variables only.
auto environment(std::map<std::string, std::string> variables) {
  return [variables = std::move(variables)](const char* name) -> const char* {
    const auto it = variables.find(name);
    return it == variables.end() ? nullptr : it->second.c_str();
  };
}

TEST(MpiUnavailable, SaysWhyWithoutMpiOrWithoutALauncher) {
  const auto alone = mpi_unavailable(environment({}));
  ASSERT_TRUE(alone.has_value());
  if (mpi_built()) {
    EXPECT_THAT(*alone, HasSubstr("not started by an MPI launcher"));
    EXPECT_THAT(*alone, HasSubstr("mpirun -n N"));
  } else {
    EXPECT_THAT(*alone, HasSubstr("built without MPI"));
  }
}

TEST(MpiUnavailable, AcceptsMpirunAndSrunOnlyWhenBuiltWithMpi) {
  for (const char* launcher : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
    const auto reason = mpi_unavailable(environment({{launcher, "0"}}));
    EXPECT_EQ(reason.has_value(), !mpi_built()) << launcher;
    if (reason) {
      EXPECT_THAT(*reason, HasSubstr("built without MPI"));
    }
  }
}

TEST(BusiestAboveMean, ComparesSimulationTimePerThread) {
  EXPECT_DOUBLE_EQ(busiest_above_mean({}), 0.0);
  EXPECT_DOUBLE_EQ(busiest_above_mean({{10, 4.0, 1}}), 0.0);
  EXPECT_DOUBLE_EQ(busiest_above_mean({{10, 4.0, 1}, {10, 4.0, 1}}), 0.0);
  EXPECT_NEAR(busiest_above_mean({{10, 3.0, 1}, {10, 5.0, 1}}), 0.25, 1e-12);  // 5 against a mean of 4
  EXPECT_DOUBLE_EQ(busiest_above_mean({{10, 8.0, 2}, {10, 4.0, 1}}), 0.0);     // the same time per thread
}

}  // namespace mpi_sweep_test
}  // namespace emrm::cluster
