// The PVD collection (issue 35, item 3): each DataSet's timestep is the load factor to 15
// significant digits, so a series whose steps are thirtieths lines up with steps.csv and steps
// closer than 1e-6 stay apart (the stream's default 6 digits merged them).
#include "core/writers.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <utility>
#include <vector>

using namespace c2d;

TEST(Writers, PvdTimestepsKeepFifteenDigits) {
  const std::vector<std::pair<double, std::string>> steps{{1.0 / 30.0, "step_0001.vtu"},
                                                          {2.0 / 3.0, "step_0002.vtu"},
                                                          {2.0 / 3.0 + 1e-9, "step_0003.vtu"},
                                                          {1.0 - 1e-16, "step_0004.vtu"}};
  const std::string pvd = core::pvd_document(steps);
  const std::regex dataset("<DataSet timestep=\"([^\"]+)\" part=\"0\" file=\"([^\"]+)\"/>");
  size_t k = 0;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), dataset);
       it != std::sregex_iterator(); ++it, ++k) {
    ASSERT_LT(k, steps.size()) << pvd;
    EXPECT_NEAR(std::stod((*it)[1]), steps[k].first, 5e-15 * steps[k].first) << (*it)[1];
    EXPECT_EQ((*it)[2], steps[k].second);
  }
  EXPECT_EQ(k, steps.size()) << pvd;
  // A sum of steps a few ulps short of 1 prints as 1.
  EXPECT_NE(pvd.find("timestep=\"1\""), std::string::npos) << pvd;
}
