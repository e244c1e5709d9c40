// SPDX-License-Identifier: MIT
#include "search/closest_point_search.hpp"

#include "kernels/ancf_sliding.hpp"
#include "kernels/sliding.hpp"
#include "model/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace slidebeam {

namespace {

struct Box {
  std::array<double, 3> lo{}, hi{};
  void grow(const Box& b) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
  }
  /// Distance from p to the box (0 inside): a lower bound of the distance to anything in it.
  double distance(const double p[3]) const {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double d = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
      d2 += d * d;
    }
    return std::sqrt(d2);
  }
};

/// The spans [first, first + n) of one carrier owned by this rank, in an implicit binary tree
/// of boxes (node i has children 2i+1, 2i+2 over halves of its span range).
class SpanTree {
 public:
  SpanTree(const Beam& beam, int first, int n)
      : beam_(&beam),
        curve_{beam.is_ancf() ? sliding::Curve::Kind::Hermite : sliding::Curve::Kind::BSpline, beam.n_spans(), beam.length()},
        stride_(beam.coordinates_per_cp()),
        first_(first),
        n_(n) {
    if (n_ > 0) {
      boxes_.resize(static_cast<size_t>(4 * n_));
      build(0, first_, first_ + n_);
    }
  }
  /// Best (distance, s, span) so far, improved by the spans of this tree.
  void search(const double p[3], ClosestPoint& best, int& best_span) const {
    if (n_ > 0) visit(0, first_, first_ + n_, p, best, best_span);
  }

 private:
  const Box& build(size_t node, int lo, int hi) {
    Box& b = boxes_[node];
    if (hi - lo == 1) {
      // B-spline span: the convex hull of its 3 control points; Hermite element: of its 4 Bezier
      // points r1, r1 + Le r1'/3, r2 - Le r2'/3, r2
      const double* q = beam_->q_ref().data();
      std::vector<std::array<double, 3>> pts;
      if (beam_->is_ancf()) {
        const auto bz = sliding::hermite::bezier_points(beam_->n_spans(), beam_->length(), q, stride_, lo);
        pts.assign(bz.begin(), bz.end());
      } else {
        for (int a = 0; a < 3; ++a) pts.push_back({q[12 * (lo + a)], q[12 * (lo + a) + 1], q[12 * (lo + a) + 2]});
      }
      b.lo = b.hi = pts[0];
      for (const auto& pt : pts)
        for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], pt[k]), b.hi[k] = std::max(b.hi[k], pt[k]);
      return b;
    }
    const int mid = lo + (hi - lo) / 2;
    b = build(2 * node + 1, lo, mid);
    b.grow(build(2 * node + 2, mid, hi));
    return b;
  }
  void visit(size_t node, int lo, int hi, const double p[3], ClosestPoint& best, int& best_span) const {
    // strictly farther boxes cannot win; equal ones can, on the tie-break by span
    if (boxes_[node].distance(p) > best.distance) return;
    if (hi - lo == 1) {
      const auto r = curve_.project_on_span(beam_->q_ref().data(), stride_, lo, p);
      if (r[1] < best.distance || (r[1] == best.distance && lo < best_span)) {
        best = ClosestPoint{r[0], r[1]};
        best_span = lo;
      }
      return;
    }
    const int mid = lo + (hi - lo) / 2;
    // nearer half first: it tightens the bound for the other
    const bool left_first = boxes_[2 * node + 1].distance(p) <= boxes_[2 * node + 2].distance(p);
    if (left_first) {
      visit(2 * node + 1, lo, mid, p, best, best_span);
      visit(2 * node + 2, mid, hi, p, best, best_span);
    } else {
      visit(2 * node + 2, mid, hi, p, best, best_span);
      visit(2 * node + 1, lo, mid, p, best, best_span);
    }
  }

  const Beam* beam_;
  sliding::Curve curve_;
  int stride_;
  int first_, n_;
  std::vector<Box> boxes_;
};

}  // namespace

std::vector<ClosestPoint> closest_points(const Model& model, const std::vector<ClosestPointQuery>& queries) {
  // This rank's spans of each queried carrier: span e belongs to the owner of
  // Beam::span_owner_cp(e) (control point e+1 of a director beam, node e of an ANCF cable), a
  // contiguous range of spans.
  std::map<int, SpanTree> trees;
  for (const auto& q : queries) {
    if (trees.count(q.carrier)) continue;
    const Beam& b = model.beam(q.carrier);
    int first = -1, n = 0;
    for (int e = 0; e < b.n_spans(); ++e)
      if (model.dof_map().owns_cp(b.first_cp() + b.span_owner_cp(e))) {
        if (first < 0) first = e;
        ++n;
      }
    trees.emplace(q.carrier, SpanTree(b, std::max(first, 0), n));
  }
  const size_t nq = queries.size();
  std::vector<ClosestPoint> local(nq);
  struct DistanceSpan {
    double distance;
    int span;
  };
  // MPI_DOUBLE_INT MINLOC: the smallest distance, ties to the smallest span (= lowest rank)
  std::vector<DistanceSpan> key(nq);
  for (size_t i = 0; i < nq; ++i) {
    int span = std::numeric_limits<int>::max();
    trees.at(queries[i].carrier).search(queries[i].point, local[i], span);
    key[i] = {local[i].distance, span};
  }
  MPI_Comm comm = model.comm();
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (size == 1 || nq == 0) return local;
  std::vector<DistanceSpan> win(nq);
  MPI_Allreduce(key.data(), win.data(), static_cast<int>(nq), MPI_DOUBLE_INT, MPI_MINLOC, comm);
  std::vector<double> s(nq, 0.0);
  for (size_t i = 0; i < nq; ++i)
    if (key[i].span == win[i].span && key[i].distance == win[i].distance) s[i] = local[i].s;
  MPI_Allreduce(MPI_IN_PLACE, s.data(), static_cast<int>(nq), MPI_DOUBLE, MPI_SUM, comm);
  std::vector<ClosestPoint> out(nq);
  for (size_t i = 0; i < nq; ++i) out[i] = ClosestPoint{s[i], win[i].distance};
  return out;
}

}  // namespace slidebeam
