// SPDX-License-Identifier: MIT
#pragma once
/// @file Parallel closest-point search of points on beam centre lines (the initial projection of
/// sliders onto their carriers). Every rank answers every query for the knot spans it owns
/// (owns_span: the distribution of assembly), visiting them through a tree of bounding boxes (a
/// quadratic B-spline span lies in the convex hull of its three control points, a cubic Hermite
/// element of an ANCF cable in that of its four Bezier points, so the box of those points
/// bounds it), so a query costs O(log spans) on each rank instead of O(spans); a
/// min-reduction over ranks then gives every rank every answer. Queries come from the scene,
/// which every rank holds, so they need no exchange; the answers are O(queries) per rank.

#include <mpi.h>

#include <limits>
#include <vector>

namespace slidebeam {

class Model;

struct ClosestPointQuery {
  int carrier = -1;         ///< beam index
  double point[3] = {0, 0, 0};
};

struct ClosestPoint {
  double s = 0.0;  ///< arc length on the carrier
  double distance = std::numeric_limits<double>::infinity();
};

/// Closest points (reference configuration) of all queries; the same queries on every rank
/// (collective). Ties go to the lowest knot span, as in a serial search.
std::vector<ClosestPoint> closest_points(const Model& model, const std::vector<ClosestPointQuery>& queries);

}  // namespace slidebeam
