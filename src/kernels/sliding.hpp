// SPDX-License-Identifier: MIT
#pragma once
/// @file The carrier curve of a sliding joint: basis weights of its control points at a sliding
/// coordinate, the exact discrete derivative in s across knots, and the closest-point projection.
/// Pure functions of the carrier's knot vector (n_spans, length L; xi = s / L); no PETSc.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace slidebeam::sliding {

/// Weights of carrier control points lo .. lo + size - 1 (all other control points: 0).
struct Weights {
  int lo = 0;
  std::vector<double> w;
  void reset(int lo_cp, int n) {
    lo = lo_cp;
    w.assign(static_cast<std::size_t>(n), 0.0);
  }
  double at(int cp) const { return (cp < lo || cp >= lo + static_cast<int>(w.size())) ? 0.0 : w[static_cast<std::size_t>(cp - lo)]; }
};

/// Span of s (clamped to the first/last span; beyond the ends the end span's polynomial extends).
int span_of(int n_spans, double L, double s);

/// w += f * d^k N_A / ds^k (s), A over the 3 control points of span `span` (k = 0, 1, 2).
void add_basis(int n_spans, double L, int span, double s, int k, double f, Weights& w);

/// Exact discrete derivative of the basis between s0 and s1 (docs/theory.md, "The exact discrete
/// derivative across knots"):
///   D_A = (N_A(s1) - N_A(s0)) / (s1 - s0)   and   dD_A / ds1,
/// evaluated without dividing by s1 - s0: [s0, s1] is split at knots, D is the length-weighted
/// mean of N'_A at the pieces' midpoints, and dD/ds1 = (1/ds^2) int N''(t) |t - s0| dt is summed
/// piecewise (N'' is constant on a span). Within one span D = N'((s0+s1)/2), dD/ds1 = N''/2.
/// D and dD are reset to the control points the interval touches.
void difference_quotient(int n_spans, double L, double s0, double s1, Weights& D, Weights& dD);

/// First and last carrier control point touched by [min(s0,s1), max(s0,s1)] (span range + 2).
std::array<int, 2> touched_cps(int n_spans, double L, double s0, double s1);

/// Closest point to p of one piece [sa, sb] of a curve of length L, given
/// eval(s, c, dc, ddc) (position and first two derivatives): start from the nearest of 9
/// samples, then Newton on f(s) = (c - p) . c' = 0 kept inside the piece. Returns {s, distance}.
/// Shared by the B-spline spans and the Hermite elements.
template <class Eval>
std::array<double, 2> closest_on_piece(double sa, double sb, double L, const double p[3], Eval&& eval) {
  constexpr int kSamples = 8;
  double s = sa, dmin = std::numeric_limits<double>::infinity();
  double c[3], dc[3], ddc[3];
  for (int i = 0; i <= kSamples; ++i) {
    const double si = sa + (sb - sa) * i / kSamples;
    eval(si, c, dc, ddc);
    const double d = std::hypot(c[0] - p[0], c[1] - p[1], c[2] - p[2]);
    if (d < dmin) dmin = d, s = si;
  }
  for (int it = 0; it < 50; ++it) {
    eval(s, c, dc, ddc);
    double f = 0, df = 0;
    for (int k = 0; k < 3; ++k) {
      f += (c[k] - p[k]) * dc[k];
      df += dc[k] * dc[k] + (c[k] - p[k]) * ddc[k];
    }
    if (df <= 0) break;
    const double sn = std::clamp(s - f / df, sa, sb);
    const bool done = std::abs(sn - s) <= 1e-15 * L;
    s = sn;
    if (done) break;
  }
  eval(s, c, dc, ddc);
  return {s, std::hypot(c[0] - p[0], c[1] - p[1], c[2] - p[2])};
}

/// Closest point of span e of the curve sum_A N_A(s) x_A to p (samples, then Newton on
/// (c(s) - p) . c'(s) = 0 inside the span). Returns {s, distance}.
std::array<double, 2> project_on_span(int n_spans, double L, const double* x, int stride, int e, const double p[3]);

/// Closest point of the curve sum_A N_A(s) x_A (x_A: control point positions, 3 values each
/// with the given stride) to the point p: search every span (samples, then Newton on
/// (c(s) - p) . c'(s) = 0 inside the span). Returns {s, distance}.
std::array<double, 2> project(int n_spans, double L, const double* x, int stride, const double p[3]);

/// Carrier centre-line basis: c(s) = sum_j N_j(s) y_j over coordinate 3-blocks y_j ("curve
/// blocks") of the carrier's control points.
///  - BSpline (director beam): block j = phi of control point j, 3 blocks per span (e .. e + 2),
///    N'' constant on a span.
///  - Hermite (ANCF cable): block 2a = r of node a, block 2a + 1 = r' of node a, 4 blocks per
///    element (2e .. 2e + 3), N'' linear on an element.
/// Weights are indexed by block. The exact discrete derivative and everything else follow the
/// free functions above (B-spline) or sliding::hermite (Hermite).
struct Curve {
  enum class Kind { BSpline, Hermite };
  Kind kind = Kind::BSpline;
  int n_spans = 1;  ///< knot spans or elements
  double L = 1.0;

  int blocks_per_cp() const { return kind == Kind::Hermite ? 2 : 1; }
  int n_blocks() const { return kind == Kind::Hermite ? 2 * (n_spans + 1) : n_spans + 2; }
  int n_cp() const { return kind == Kind::Hermite ? n_spans + 1 : n_spans + 2; }
  /// Control point (node) of block j and the offset of its 3-block in that point's coordinates.
  int cp_of_block(int j) const { return j / blocks_per_cp(); }
  int offset_of_block(int j) const { return kind == Kind::Hermite ? 3 * (j % 2) : 0; }

  int span_of(double s) const;
  /// First and last block of span e.
  std::array<int, 2> span_blocks(int e) const {
    return kind == Kind::Hermite ? std::array<int, 2>{2 * e, 2 * e + 3} : std::array<int, 2>{e, e + 2};
  }
  /// w += f * d^k N_j / ds^k (s) over the blocks of span `span` (k = 0, 1, 2).
  void add_basis(int span, double s, int k, double f, Weights& w) const;
  /// First and last block touched by [min(s0,s1), max(s0,s1)].
  std::array<int, 2> touched_blocks(double s0, double s1) const;
  /// First and last control point (node) touched by [min(s0,s1), max(s0,s1)].
  std::array<int, 2> touched_cps(double s0, double s1) const {
    const auto r = touched_blocks(s0, s1);
    return {cp_of_block(r[0]), cp_of_block(r[1])};
  }
  void difference_quotient(double s0, double s1, Weights& D, Weights& dD) const;
  /// Closest point of span e; x: the control points' coordinates with the given stride
  /// (director: phi first; ANCF: r, r'). Returns {s, distance}.
  std::array<double, 2> project_on_span(const double* x, int stride, int e, const double p[3]) const;
  std::array<double, 2> project(const double* x, int stride, const double p[3]) const;
};


/// A track: the centre lines of several carriers joined end to end, one curve in the arc length
/// s over the track (a carriage running from one track rope onto the next). Piece p is the
/// curve of one carrier over s in [begin_p, begin_p + L_p], drawn forwards (local sigma =
/// s - begin_p) or reversed (sigma = begin_p + L_p - s: the carrier's end meets the track's
/// start side). Curve blocks are numbered along s: piece after piece, a reversed piece's in
/// reverse, so any interval of s touches a contiguous range of track blocks.
///
/// Basis functions of different pieces are distinct (the pieces' end blocks are unknowns of
/// their own, held together by the joint between the carriers). The discrete derivative is the
/// length-weighted mean of the pieces' own over the parts of [s0, s1] they hold, so that
/// sum_A D_A y_A (s1 - s0) = c(s1) - c(s0) exactly wherever the pieces' ends meet; it is
/// bounded (no division by s1 - s0 beyond the pieces' own). A single forward piece is its
/// Curve, bit for bit.
struct Track {
  struct Piece {
    Curve curve;
    double begin = 0.0;  ///< s of the piece's start on the track
    bool reversed = false;
    int first_block = 0;  ///< track index of the piece's first block along s
    int first_span = 0;   ///< track index of the piece's first span (spans keep the curve's numbering)
    int first_cp = 0;     ///< track index of the piece's first control point along s
  };
  std::vector<Piece> pieces;

  /// Append a carrier's curve; reversed: drawn from the track's far side.
  void append(const Curve& c, bool reversed);
  bool single() const { return pieces.size() == 1 && !pieces[0].reversed; }
  double length() const { return pieces.back().begin + pieces.back().curve.L; }
  int n_blocks() const { return pieces.back().first_block + pieces.back().curve.n_blocks(); }
  int n_cp() const { return pieces.back().first_cp + pieces.back().curve.n_cp(); }
  /// Piece of s (clamped: beyond the ends the end pieces extend; a junction belongs to the piece
  /// before it), of a track span, of a track block, of a track control point.
  int piece_of(double s) const;
  int piece_of_span(int span) const { return piece_holding(&Piece::first_span, span); }
  int piece_of_block(int block) const { return piece_holding(&Piece::first_block, block); }
  int piece_of_cp(int cp) const { return piece_holding(&Piece::first_cp, cp); }
  /// The carrier's own coordinates of a track block: control point (node) and the offset of the
  /// 3-block in that point's coordinates.
  int cp_of_block(int block) const;
  int offset_of_block(int block) const;
  /// The carrier's own control point of a track control point.
  int local_cp(int cp) const;
  double local_s(int piece, double s) const;

  int span_of(double s) const;
  void add_basis(int span, double s, int k, double f, Weights& w) const;
  std::array<int, 2> touched_blocks(double s0, double s1) const;
  std::array<int, 2> touched_cps(double s0, double s1) const;
  void difference_quotient(double s0, double s1, Weights& D, Weights& dD) const;

 private:
  /// The last piece whose first index (span, block or control point) is at most `index`.
  int piece_holding(int Piece::*first, int index) const;
  /// Track block of a piece's local block.
  int track_block(int piece, int local) const;
  /// w += weights given over local blocks of piece p.
  void scatter(int piece, const Weights& local, double f, Weights& w) const;
};

}  // namespace slidebeam::sliding
