// SPDX-License-Identifier: MIT
// The parallel closest-point search (bounding-box trees over each rank's spans, min-reduction
// over ranks) finds what a serial search over every span finds, on any number of ranks (run at
// np = 1 and 2), including points off the curve and ties between spans.
#include "kernels/bspline.hpp"
#include "kernels/sliding.hpp"
#include "model/model.hpp"
#include "search/closest_point_search.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace slidebeam;

namespace {
// A helix-like carrier: control points at Greville abscissae of a curve that winds and climbs.
BeamSpec wound_carrier(const std::string& name, int spans) {
  BeamSpec s;
  s.name = name;
  s.n_spans = spans;
  s.length = 10.0;
  s.section = {5e3, 2e3, 2.5e3, 40.0, 60.0, 80.0, 1.0, 0.1, 0.2};
  for (int a = 0; a < spans + 2; ++a) {
    const double xi = bspline::greville(spans, a);
    const double v[12] = {std::cos(6 * xi), std::sin(6 * xi), 2 * xi, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.q_ref.insert(s.q_ref.end(), v, v + 12);
  }
  return s;
}

/// 200 points near and far from a carrier wound about the z axis (radius r0 + up to 2, height up
/// to `height`), deterministic.
std::vector<ClosestPointQuery> scattered_queries(int carrier, double r0, double height) {
  std::vector<ClosestPointQuery> queries;
  for (int i = 0; i < 200; ++i) {
    ClosestPointQuery q;
    q.carrier = carrier;
    const double t = 0.05 * i, r = r0 + 2.0 * std::fabs(std::sin(3.1 * i));
    q.point[0] = r * std::cos(7 * t);
    q.point[1] = r * std::sin(5 * t);
    q.point[2] = height * std::fmod(0.37 * i, 1.0) + 0.3 * std::sin(i);
    queries.push_back(q);
  }
  return queries;
}
}  // namespace

TEST(ClosestPointSearch, MatchesTheSerialSearchOverEverySpan) {
  Model m(PETSC_COMM_WORLD);
  m.add_beam(wound_carrier("short", 3));  // a short beam first, so the carrier's points start mid-rank
  m.add_beam(wound_carrier("carrier", 64));
  m.finalize();
  const Beam& C = m.beam(1);
  std::vector<ClosestPointQuery> queries = scattered_queries(1, 1.0, 2.0);  // up to 3 radii off
  ClosestPointQuery start;  // the curve's first point: the ends and the axis are exact cases
  start.carrier = 1;
  start.point[0] = 1.0;
  queries.push_back(start);
  const auto found = closest_points(m, queries);
  ASSERT_EQ(found.size(), queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    const auto ref = sliding::project(C.n_spans(), C.length(), C.q_ref().data(), 12, queries[i].point);
    EXPECT_EQ(found[i].distance, ref[1]) << "query " << i;
    EXPECT_EQ(found[i].s, ref[0]) << "query " << i;
  }
  EXPECT_EQ(found.back().s, 0.0);
  EXPECT_LT(found.back().distance, 1e-14);
}

namespace {
// An ANCF cable wound like the carrier above: nodes (r, r') of a helix, r' its unit tangent.
BeamSpec wound_cable(const std::string& name, int elements) {
  BeamSpec s;
  s.name = name;
  s.formulation = Formulation::Ancf;
  s.n_spans = elements;
  const double a = 1.0, c = 0.3;  // radius, rise per radian
  const double turns = 2.0 * std::acos(-1.0) * 1.5, speed = std::hypot(a, c);
  s.length = speed * turns;
  s.section = {5e3, 0, 0, 0, 60.0, 60.0, 1.0, 0, 0};
  for (int n = 0; n <= elements; ++n) {
    const double t = turns * n / elements;
    const double v[6] = {a * std::cos(t), a * std::sin(t), c * t, -a * std::sin(t) / speed, a * std::cos(t) / speed, c / speed};
    s.q_ref.insert(s.q_ref.end(), v, v + 6);
  }
  return s;
}
}  // namespace

TEST(ClosestPointSearch, AncfCarrierMatchesTheSerialSearchOverEveryElement) {
  Model m(PETSC_COMM_WORLD);
  m.add_beam(wound_carrier("director", 5));  // a director beam first: mixed block sizes
  m.add_beam(wound_cable("cable", 40));
  m.finalize();
  const Beam& C = m.beam(1);
  const sliding::Curve curve{sliding::Curve::Kind::Hermite, C.n_spans(), C.length()};
  std::vector<ClosestPointQuery> queries = scattered_queries(1, 0.2, 3.0);
  ClosestPointQuery on;  // a point of the cable: distance ~0 at its s
  on.carrier = 1;
  const double t_on = 2.0 * std::acos(-1.0) * 1.5 * 0.6137;
  on.point[0] = std::cos(t_on);
  on.point[1] = std::sin(t_on);
  on.point[2] = 0.3 * t_on;
  queries.push_back(on);
  const auto found = closest_points(m, queries);
  ASSERT_EQ(found.size(), queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    const auto ref = curve.project(C.q_ref().data(), 6, queries[i].point);
    EXPECT_EQ(found[i].distance, ref[1]) << "query " << i;
    EXPECT_EQ(found[i].s, ref[0]) << "query " << i;
  }
  EXPECT_NEAR(found.back().s, 0.6137 * C.length(), 1e-4);  // Hermite interpolation of the helix
  EXPECT_LT(found.back().distance, 1e-4);
}
