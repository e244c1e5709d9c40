// SPDX-License-Identifier: MIT
#include "kernels/sliding.hpp"

#include "kernels/ancf_sliding.hpp"
#include "kernels/bspline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slidebeam::sliding {

int span_of(int n_spans, double L, double s) { return bspline::find_span(n_spans, s / L); }

void add_basis(int n_spans, double L, int span, double s, int k, double f, Weights& w) {
  const auto b = bspline::basis_on_span(n_spans, span, s / L);
  const double scale = k == 0 ? 1.0 : (k == 1 ? 1.0 / L : 1.0 / (L * L));  // d/ds = (1/L) d/dxi
  for (int a = 0; a < 3; ++a) {
    const double v = k == 0 ? b.N[a] : (k == 1 ? b.dN[a] : b.ddN[a]);
    w.w[static_cast<size_t>(span + a - w.lo)] += f * scale * v;
  }
}

std::array<int, 2> touched_cps(int n_spans, double L, double s0, double s1) {
  // spans of both ends, not of min/max: a non-finite s (a diverging iterate) compares false
  const int a = span_of(n_spans, L, s0), b = span_of(n_spans, L, s1);
  return {std::min(a, b), std::max(a, b) + 2};
}

void difference_quotient(int n_spans, double L, double s0, double s1, Weights& D, Weights& dD) {
  const auto r = touched_cps(n_spans, L, s0, s1);
  D.reset(r[0], r[1] - r[0] + 1);
  dD.reset(r[0], r[1] - r[0] + 1);
  const double lo = std::min(s0, s1), hi = std::max(s0, s1), ds = hi - lo;
  if (ds == 0.0) {
    const int e = span_of(n_spans, L, s0);
    add_basis(n_spans, L, e, s0, 1, 1.0, D);
    add_basis(n_spans, L, e, s0, 2, 0.5, dD);
    return;
  }
  // pieces [a, b] between consecutive interior knots inside (lo, hi)
  double a = lo;
  while (a < hi) {
    int e = span_of(n_spans, L, a);
    // right end of span e (interior knots only; the last span extends to +inf); a knot that
    // rounding left at or below a belongs to the piece before
    double b = e + 1 < n_spans ? L * (e + 1) / n_spans : hi;
    while (b <= a && e + 1 < n_spans) b = ++e + 1 < n_spans ? L * (e + 1) / n_spans : hi;
    b = std::min(b, hi);
    if (b <= a) break;
    const int span = span_of(n_spans, L, 0.5 * (a + b));
    const double len = (b - a) / ds, mid = 0.5 * (a + b);
    add_basis(n_spans, L, span, mid, 1, len, D);
    add_basis(n_spans, L, span, mid, 2, len * std::abs(mid - s0) / ds, dD);
    a = b;
  }
}

std::array<double, 2> project_on_span(int n_spans, double L, const double* x, int stride, int e, const double p[3]) {
  auto eval = [&](double s, double c[3], double dc[3], double ddc[3]) {
    const auto b = bspline::basis_on_span(n_spans, e, s / L);
    for (int k = 0; k < 3; ++k) c[k] = dc[k] = ddc[k] = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double* xa = x + static_cast<size_t>(stride) * static_cast<size_t>(e + a);
      for (int k = 0; k < 3; ++k) {
        c[k] += b.N[a] * xa[k];
        dc[k] += b.dN[a] / L * xa[k];
        ddc[k] += b.ddN[a] / (L * L) * xa[k];
      }
    }
  };
  const double sa = L * e / n_spans, sb = L * (e + 1) / n_spans;
  return closest_on_piece(sa, sb, L, p, eval);
}

std::array<double, 2> project(int n_spans, double L, const double* x, int stride, const double p[3]) {
  double best_s = 0.0, best_d = std::numeric_limits<double>::infinity();
  for (int e = 0; e < n_spans; ++e) {
    const auto r = project_on_span(n_spans, L, x, stride, e, p);
    if (r[1] < best_d) best_d = r[1], best_s = r[0];
  }
  return {best_s, best_d};
}

int Curve::span_of(double s) const {
  return kind == Kind::Hermite ? hermite::element_of(n_spans, L, s) : sliding::span_of(n_spans, L, s);
}

void Curve::add_basis(int span, double s, int k, double f, Weights& w) const {
  if (kind == Kind::Hermite) hermite::add_basis(n_spans, L, span, s, k, f, w);
  else sliding::add_basis(n_spans, L, span, s, k, f, w);
}

std::array<int, 2> Curve::touched_blocks(double s0, double s1) const {
  return kind == Kind::Hermite ? hermite::touched_blocks(n_spans, L, s0, s1) : sliding::touched_cps(n_spans, L, s0, s1);
}

void Curve::difference_quotient(double s0, double s1, Weights& D, Weights& dD) const {
  if (kind == Kind::Hermite) hermite::difference_quotient(n_spans, L, s0, s1, D, dD);
  else sliding::difference_quotient(n_spans, L, s0, s1, D, dD);
}

std::array<double, 2> Curve::project_on_span(const double* x, int stride, int e, const double p[3]) const {
  return kind == Kind::Hermite ? hermite::project_on_element(n_spans, L, x, stride, e, p)
                               : sliding::project_on_span(n_spans, L, x, stride, e, p);
}

std::array<double, 2> Curve::project(const double* x, int stride, const double p[3]) const {
  double best_s = 0.0, best_d = std::numeric_limits<double>::infinity();
  for (int e = 0; e < n_spans; ++e) {
    const auto r = project_on_span(x, stride, e, p);
    if (r[1] < best_d) best_d = r[1], best_s = r[0];
  }
  return {best_s, best_d};
}

void Track::append(const Curve& c, bool reversed) {
  Piece p;
  p.curve = c;
  p.reversed = reversed;
  if (!pieces.empty()) {
    const Piece& last = pieces.back();
    p.begin = last.begin + last.curve.L;
    p.first_block = last.first_block + last.curve.n_blocks();
    p.first_span = last.first_span + last.curve.n_spans;
    p.first_cp = last.first_cp + last.curve.n_cp();
  }
  pieces.push_back(p);
}

int Track::piece_of(double s) const {
  const int n = static_cast<int>(pieces.size());
  for (int p = 0; p + 1 < n; ++p)
    if (s <= pieces[static_cast<size_t>(p)].begin + pieces[static_cast<size_t>(p)].curve.L) return p;
  return n - 1;
}

int Track::piece_holding(int Piece::*first, int index) const {
  int p = 0;
  while (p + 1 < static_cast<int>(pieces.size()) && index >= pieces[static_cast<size_t>(p) + 1].*first) ++p;
  return p;
}

double Track::local_s(int piece, double s) const {
  const Piece& p = pieces[static_cast<size_t>(piece)];
  return p.reversed ? p.begin + p.curve.L - s : s - p.begin;
}

int Track::track_block(int piece, int local) const {
  const Piece& p = pieces[static_cast<size_t>(piece)];
  return p.reversed ? p.first_block + p.curve.n_blocks() - 1 - local : p.first_block + local;
}

namespace {
int local_index(const Track::Piece& p, int track_index, int first, int count) {
  return p.reversed ? count - 1 - (track_index - first) : track_index - first;
}
}  // namespace

int Track::cp_of_block(int block) const {
  const Piece& p = pieces[static_cast<size_t>(piece_of_block(block))];
  return p.curve.cp_of_block(local_index(p, block, p.first_block, p.curve.n_blocks()));
}

int Track::offset_of_block(int block) const {
  const Piece& p = pieces[static_cast<size_t>(piece_of_block(block))];
  return p.curve.offset_of_block(local_index(p, block, p.first_block, p.curve.n_blocks()));
}

int Track::local_cp(int cp) const {
  const Piece& p = pieces[static_cast<size_t>(piece_of_cp(cp))];
  return local_index(p, cp, p.first_cp, p.curve.n_cp());
}

int Track::span_of(double s) const {
  if (single()) return pieces[0].curve.span_of(s);
  const int p = piece_of(s);
  return pieces[static_cast<size_t>(p)].first_span + pieces[static_cast<size_t>(p)].curve.span_of(local_s(p, s));
}

void Track::scatter(int piece, const Weights& local, double f, Weights& w) const {
  for (size_t i = 0; i < local.w.size(); ++i) {
    const int t = track_block(piece, local.lo + static_cast<int>(i));
    w.w[static_cast<size_t>(t - w.lo)] += f * local.w[i];
  }
}

void Track::add_basis(int span, double s, int k, double f, Weights& w) const {
  if (single()) {
    pieces[0].curve.add_basis(span, s, k, f, w);
    return;
  }
  const int p = piece_of_span(span);
  const Piece& piece = pieces[static_cast<size_t>(p)];
  const int e = span - piece.first_span;
  const auto r = piece.curve.span_blocks(e);
  Weights local;
  local.reset(r[0], r[1] - r[0] + 1);
  piece.curve.add_basis(e, local_s(p, s), k, 1.0, local);
  scatter(p, local, piece.reversed && k % 2 == 1 ? -f : f, w);  // d/ds = -d/dsigma on a reversed piece
}

std::array<int, 2> Track::touched_blocks(double s0, double s1) const {
  if (single()) return pieces[0].curve.touched_blocks(s0, s1);
  std::array<int, 2> out{std::numeric_limits<int>::max(), std::numeric_limits<int>::min()};
  for (double s : {s0, s1}) {
    const int p = piece_of(s);
    const double sigma = local_s(p, s);
    const auto r = pieces[static_cast<size_t>(p)].curve.touched_blocks(sigma, sigma);
    const int a = track_block(p, r[0]), b = track_block(p, r[1]);
    out[0] = std::min({out[0], a, b});
    out[1] = std::max({out[1], a, b});
  }
  return out;
}

std::array<int, 2> Track::touched_cps(double s0, double s1) const {
  if (single()) return pieces[0].curve.touched_cps(s0, s1);
  const auto r = touched_blocks(s0, s1);
  auto track_cp = [&](int block) {
    const int p = piece_of_block(block);
    const Piece& piece = pieces[static_cast<size_t>(p)];
    const int c = cp_of_block(block);
    return piece.reversed ? piece.first_cp + piece.curve.n_cp() - 1 - c : piece.first_cp + c;
  };
  return {track_cp(r[0]), track_cp(r[1])};
}

void Track::difference_quotient(double s0, double s1, Weights& D, Weights& dD) const {
  if (single()) {
    pieces[0].curve.difference_quotient(s0, s1, D, dD);
    return;
  }
  const auto r = touched_blocks(s0, s1);
  D.reset(r[0], r[1] - r[0] + 1);
  dD.reset(r[0], r[1] - r[0] + 1);
  const int pa = piece_of(s0), pb = piece_of(s1);
  Weights Dl, dDl;
  if (pa == pb) {
    const Piece& piece = pieces[static_cast<size_t>(pa)];
    piece.curve.difference_quotient(local_s(pa, s0), local_s(pa, s1), Dl, dDl);
    scatter(pa, Dl, piece.reversed ? -1.0 : 1.0, D);
    scatter(pa, dDl, 1.0, dD);
    return;
  }
  // [s0, s1] split at the junctions into parts [u, v] (u on s0's side): D = sum_p w_p D_p with
  // w_p = (v - u) / ds; d D_A / d s1 = -D_A / ds on the parts before s1's piece, and
  // D_p (u - s0) / ds^2 + w_p dD_p/dv on that piece
  const double ds = s1 - s0;
  const int step = pb > pa ? 1 : -1;
  for (int p = pa;; p += step) {
    const Piece& piece = pieces[static_cast<size_t>(p)];
    const double start = piece.begin, end = piece.begin + piece.curve.L;
    const double u = p == pa ? s0 : (step > 0 ? start : end);
    const double v = p == pb ? s1 : (step > 0 ? end : start);
    piece.curve.difference_quotient(local_s(p, u), local_s(p, v), Dl, dDl);
    const double w = (v - u) / ds, sign = piece.reversed ? -1.0 : 1.0;
    scatter(p, Dl, sign * w, D);
    if (p == pb) {
      scatter(p, Dl, sign * (u - s0) / (ds * ds), dD);
      scatter(p, dDl, w, dD);
      break;
    }
    scatter(p, Dl, -sign * w / ds, dD);
  }
}

}  // namespace slidebeam::sliding
