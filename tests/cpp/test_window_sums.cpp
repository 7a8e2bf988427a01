// A run's metric sums as the outside world reads them (RunSums::visit, what
// run_batch's metrics_only and neurov._core.RunSums.as_dict hand over): every
// entry once, in order, and the first refused step as none until one is met.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "neurov/sim/window_sums.hpp"

namespace {

using namespace neurov;
using FirstRefused = std::optional<std::pair<double, int>>;

/// The names visit gives, and first_refused's value.
std::pair<std::vector<std::string>, FirstRefused> visited(const RunSums& s) {
  std::vector<std::string> names;
  FirstRefused first = std::pair(-1.0, -1);
  s.visit([&](const char* name, const auto& v) {
    names.emplace_back(name);
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, FirstRefused>) first = v;
  });
  return {names, first};
}

TEST(RunSums, VisitGivesEveryEntryInOrderAndTheFirstRefusedStepOnceMet) {
  RunSums s;
  s.after = 1.0;
  const auto [names, none] = visited(s);
  EXPECT_EQ(names, (std::vector<std::string>{"after", "before", "window", "final_adaptive_norm",
                                             "max_adaptive_norm", "diverged", "first_refused"}));
  EXPECT_FALSE(none.has_value());

  Eigen::VectorXd t(3);
  t << 0.0, 1.0, 2.0;
  const Eigen::Matrix<double, Eigen::Dynamic, 6> eta = Eigen::Matrix<double, 3, 6>::Ones(), eta_d = eta * 0.5;
  const Eigen::Matrix<double, Eigen::Dynamic, 6> tau = Eigen::Matrix<double, 3, 6>::Zero();
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> status(3);
  status << 0, 4, 2;
  const Eigen::VectorXd norm = Eigen::VectorXd::Zero(3);
  s.add_rows(t, eta, eta_d, tau, status, norm, 3, false);
  const FirstRefused first = visited(s).second;
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(*first, std::pair(1.0, 4));
  EXPECT_EQ(s.window.rows, 2);
  EXPECT_EQ(s.before.rows, 1);
}

}  // namespace
