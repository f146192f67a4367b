// The trace CSV reads back to the same numbers, ordered by time then actor.

#include "emrm/openscenario/trace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "input_error.hpp"

namespace emrm::openscenario {
namespace {

TEST(Trace, RoundTripsEveryDigitInTimeThenActorOrder) {
  Trajectories t;
  for (int i = 0; i < 3; ++i) {
    const double ti = 0.01 * i;
    t["b"].push_back({ti, 1.0 / 3.0 + i, -2e-7 * i, std::nextafter(3.0, 4.0), 13.000000000000002});
    t["a"].push_back({ti, 1e6 + 0.1 * i, 5.5, -3.14159, 0.0});
  }
  std::stringstream csv;
  write_trace_csv(csv, t);
  std::string header, first, second;
  std::getline(csv, header);
  std::getline(csv, first);
  std::getline(csv, second);
  EXPECT_EQ(header, "t,actor,x,y,heading,speed");
  EXPECT_EQ(first.substr(0, 4), "0,a,");
  EXPECT_EQ(second.substr(0, 4), "0,b,");
  csv.seekg(0);
  const Trajectories back = read_trace_csv(csv, "trace.csv");
  ASSERT_EQ(back.size(), 2U);
  for (const auto& [name, samples] : t) {
    ASSERT_EQ(back.at(name).size(), samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      EXPECT_EQ(back.at(name)[i].t_s, samples[i].t_s);
      EXPECT_EQ(back.at(name)[i].x_m, samples[i].x_m);
      EXPECT_EQ(back.at(name)[i].y_m, samples[i].y_m);
      EXPECT_EQ(back.at(name)[i].heading_rad, samples[i].heading_rad);
      EXPECT_EQ(back.at(name)[i].speed_mps, samples[i].speed_mps);
    }
  }
}

TEST(Trace, ABadFieldIsAnErrorAtItsLineAndColumn) {
  std::stringstream csv("t,actor,x,y,heading,speed\n0,a,1,2,3,4\n0.01,a,1,x2,3,4\n");
  const InputError e = emrm::testing::input_error_of([&] { (void)read_trace_csv(csv, "trace.csv"); }, "csv");
  EXPECT_EQ(e.where().line, 3);
  EXPECT_EQ(e.where().column, 10);
}

}  // namespace
}  // namespace emrm::openscenario
