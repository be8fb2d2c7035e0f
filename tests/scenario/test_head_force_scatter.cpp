// The head force's scatter of a centrifuge run (scenario/centrifuge/experiment.hpp): the
// root-mean-square deviation about a least-squares quadratic in the travel, over the mean, for
// the last D of installation and the roughest D of it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pilempm/scenario/centrifuge/experiment.hpp"

namespace pilempm::scenario {
namespace {

// Rows every 0.05 D over [from, to] D of travel: a smooth rise, with an alternating ±amplitude.
struct Series {
  std::vector<double> travel, head;
};

Series series(double from, double to, double amplitude) {
  Series s;
  const int rows = static_cast<int>(std::lround((to - from) / 0.05));
  for (int i = 0; i <= rows; ++i) {
    const double x = from + 0.05 * i;
    s.travel.push_back(x);
    s.head.push_back(1000.0 + 120.0 * x - 8.0 * x * x + (i % 2 == 0 ? amplitude : -amplitude));
  }
  return s;
}

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

TEST(HeadForceScatter, IsZeroForAQuadraticAndTheAmplitudeOfAnAlternatingDeviation) {
  const Series smooth = series(2.0, 3.0, 0.0);
  EXPECT_LT(head_force_scatter(smooth.travel, smooth.head), 1e-13);
  // ±a about a quadratic: the fit takes up almost none of it (the residual's norm is at most
  // the deviation's, and the deviation is nearly orthogonal to the quadratics), so the scatter
  // is a / mean within a few per cent.
  const Series rough = series(2.0, 3.0, 20.0);
  const double scatter = head_force_scatter(rough.travel, rough.head);
  const double expected = 20.0 / mean(rough.head);
  EXPECT_LE(scatter, expected * (1.0 + 1e-12));
  EXPECT_GT(scatter, 0.95 * expected);
}

TEST(HeadForceScatter, NeedsFiveRowsAndAPositiveMean) {
  EXPECT_TRUE(std::isnan(head_force_scatter({0.0, 0.1, 0.2, 0.3}, {1.0, 2.0, 1.0, 2.0})));
  EXPECT_FALSE(std::isnan(head_force_scatter({0.0, 0.1, 0.2, 0.3, 0.4}, {1, 2, 1, 2, 1})));
  EXPECT_TRUE(std::isnan(head_force_scatter({0.0, 0.1, 0.2, 0.3, 0.4}, {-1, -2, -1, -2, -1})));
}

TEST(HeadForceScatter, TheSummaryGivesTheLastDAndTheRoughestD) {
  CentrifugeScenario s;
  const double D = s.pile_diameter;
  // Three D of installation: ±5 N over the first D, ±40 N over the second, ±20 N over the third.
  std::vector<PileRow> rows;
  const double amplitude[3] = {5.0, 40.0, 20.0};
  for (int k = 0; k < 3; ++k) {
    const Series part = series(k, k + 1, amplitude[k]);
    // A part's last row is the next part's first (on the edge, in both windows).
    const std::size_t end = part.travel.size() - (k < 2 ? 1 : 0);
    for (std::size_t i = 0; i < end; ++i) {
      PileRow r;
      r.role = simulation::MpmPhaseRole::installation;
      r.displacement = part.travel[i] * D;
      r.head = part.head[i];
      rows.push_back(r);
    }
  }
  CentrifugeSummary summary;
  summarise_pile(s, rows, summary);
  // The last D holds the third part's rows.
  std::vector<double> x, f;
  for (const PileRow& r : rows)
    if (r.displacement / D >= 2.0 - 1e-9) {
      x.push_back(r.displacement / D);
      f.push_back(r.head);
    }
  EXPECT_DOUBLE_EQ(summary.scatter_last_D, head_force_scatter(x, f));
  EXPECT_NEAR(summary.scatter_last_D, 20.0 / mean(f), 0.1 * 20.0 / mean(f));
  EXPECT_EQ(summary.largest_scatter_from_D, 1.0);
  EXPECT_NEAR(summary.largest_scatter, 40.0 / 1180.0, 0.1 * 40.0 / 1180.0);
  // A D with fewer than 5 rows is left out, not taken as the largest: with the second D's inner
  // rows dropped but the one at 1.5 D (3 rows with its edges), the largest is the third D's.
  std::vector<PileRow> sparse;
  for (const PileRow& r : rows) {
    const double travel = r.displacement / D;
    if (travel > 1.0 + 1e-9 && travel < 2.0 - 1e-9 && std::abs(travel - 1.5) > 0.01) continue;
    sparse.push_back(r);
  }
  summarise_pile(s, sparse, summary);
  EXPECT_EQ(summary.largest_scatter_from_D, 2.0);
  EXPECT_DOUBLE_EQ(summary.largest_scatter, summary.scatter_last_D);
  // Travel that is not a whole number of D: the last D counts among the windows. 2.5 D with
  // the roughness in the last half D.
  rows.clear();
  for (int i = 0; i <= 50; ++i) {
    PileRow r;
    r.role = simulation::MpmPhaseRole::installation;
    const double travel = 0.05 * (i + 1);
    r.displacement = travel * D;
    r.head = 1000.0 + 100.0 * travel + (travel > 2.0 ? (i % 2 == 0 ? 30.0 : -30.0) : 0.0);
    rows.push_back(r);
  }
  summarise_pile(s, rows, summary);
  EXPECT_NEAR(summary.largest_scatter_from_D, 1.55, 1e-9);
  EXPECT_DOUBLE_EQ(summary.largest_scatter, summary.scatter_last_D);
  EXPECT_GT(summary.largest_scatter, 0.005);
  // Less than 1 D of travel: no scatter.
  rows.resize(15);
  summarise_pile(s, rows, summary);
  EXPECT_TRUE(std::isnan(summary.scatter_last_D));
  EXPECT_TRUE(std::isnan(summary.largest_scatter));
}

}  // namespace
}  // namespace pilempm::scenario
