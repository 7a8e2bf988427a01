// The one list of logged series (NEUROV_RESULT_SERIES): the table and the
// members it declares agree, and allocate/clear/truncate reach every series.
#include <cstring>
#include <iterator>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "neurov/sim/result.hpp"

namespace {

using namespace neurov;

Eigen::Index columns(const SeriesSpec& spec, Eigen::Index thrusters, Eigen::Index parameters) {
  return spec.width == kPerThruster ? thrusters : spec.width == kPerParameter ? parameters : spec.width;
}

TEST(ResultSeriesTest, EveryEntryHasAUniqueNameAndALabelPerFixedColumn) {
  std::set<std::string> names;
  for (const SeriesSpec& spec : kResultSeries) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
    EXPECT_GT(std::strlen(spec.description), 0u) << spec.name;
    std::istringstream words(spec.labels);
    int labels = 0;
    for (std::string w; words >> w;) ++labels;
    if (spec.width > 1) EXPECT_EQ(labels, spec.width) << spec.name;
    else EXPECT_EQ(labels, 0) << spec.name;
  }
  EXPECT_STREQ(kResultSeries[0].name, "t");
}

TEST(ResultSeriesTest, AllocateClearAndTruncateReachEverySeriesInTheTablesOrder) {
  SimulationResult<double> r;
  r.allocate(7, 3, 2);
  std::size_t seen = 0;
  r.visit([&](const SeriesSpec& spec, auto& series) {
    EXPECT_EQ(&spec, &kResultSeries[seen]) << spec.name;
    EXPECT_EQ(series.rows(), 7) << spec.name;
    EXPECT_EQ(series.cols(), columns(spec, 3, 2)) << spec.name;
    series.setOnes();
    ++seen;
  });
  EXPECT_EQ(seen, std::size(kResultSeries));
  r.clear();
  r.visit([](const SeriesSpec& spec, auto& series) {
    EXPECT_EQ(series.count(), 0) << spec.name;
  });
  r.truncate(4);
  r.visit([](const SeriesSpec& spec, auto& series) {
    EXPECT_EQ(series.rows(), 4) << spec.name;
    EXPECT_EQ(series.cols(), columns(spec, 3, 2)) << spec.name;
  });
  EXPECT_EQ(r.eta.cols(), 6);
  EXPECT_EQ(r.current.cols(), 3);
}

}  // namespace
