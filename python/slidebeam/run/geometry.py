# SPDX-License-Identifier: MIT
"""Reference configuration of a beam: control points and directors from the scene geometry.

Control points sit where the quadratic B-spline interpolates the reference curve at the
Greville abscissae (for a straight beam these are the Greville points themselves, so the
spline is parametrised exactly by arc length and every reference strain vanishes).
"""
from __future__ import annotations

import numpy as np

from .. import _core
from ..scene.parse import Beam


def default_d2(d1: np.ndarray) -> np.ndarray:
    """Section axis d2 when the scene gives none: the coordinate axis cyclically after the
    dominant component of d1 (x -> y, y -> z, z -> x), made orthogonal to d1. Gives the
    triads (e_X, e_Y, e_Z) for a beam along X and (e_Z, e_X, e_Y) along Z (the seed benchmark S2,
    docs/verification.md "Benchmarks")."""
    k = (int(np.argmax(np.abs(d1))) + 1) % 3
    e = np.eye(3)[k]
    v = e - e.dot(d1) * d1
    return v / np.linalg.norm(v)


def _rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Smallest rotation taking unit vector a to unit vector b (parallel transport of a frame)."""
    v = np.cross(a, b)
    c = float(a.dot(b))
    if np.linalg.norm(v) < 1e-14:
        if c > 0:
            return np.eye(3)
        raise ValueError("the centre line reverses direction; cannot transport the section frame")
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + K + K @ K / (1.0 + c)


def _arc_rotation(beam: Beam, s: float) -> np.ndarray:
    """Rotation about the arc's normal by the angle swept at arc length s. Parallel transport
    along a circle is exactly this rotation, for any angle: the minimal rotation between the
    start and current tangents is undefined where they are antiparallel (half a turn) and loses
    orthogonality near it (4e-3 at the end of a 180-degree arc, issue 22)."""
    g = beam.geometry
    assert g.kind == "arc" and g.radius is not None and g.angle_deg is not None and g.normal is not None
    phi = float(np.copysign(s / g.radius, g.angle_deg))
    n = np.asarray(g.normal)
    K = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    return np.eye(3) + np.sin(phi) * K + (1.0 - np.cos(phi)) * (K @ K)


def _tangent(beam: Beam, s: float, h: float) -> np.ndarray:
    g = beam.geometry
    a, b = max(s - h, 0.0), min(s + h, g.length)
    t = np.asarray(g.point_at(b)) - np.asarray(g.point_at(a))
    return t / np.linalg.norm(t)


def ancf_reference_coordinates(beam: Beam) -> np.ndarray:
    """(spans+1) x 6 reference coordinates (r, r') of an ANCF cable's nodes: equal elements of a
    line or an arc, r' the unit tangent (so the element coordinate is the arc length)."""
    n, L = beam.spans, beam.geometry.length
    q = np.zeros((n + 1, 6))
    for a in range(n + 1):
        q[a, 0:3] = beam.geometry.point_at(L * a / n)
        q[a, 3:6] = beam.geometry.tangent_at(L * a / n)
    return q


def _solve_banded(band: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve A x = rhs for A with two diagonals below and two above the main one, stored as
    band[j, 2 + c - j] = A[j, c]. Gaussian elimination without pivoting, which is stable for
    B-spline collocation matrices (totally positive; de Boor, A Practical Guide to Splines):
    memory and time linear in the size, where a dense solve needs (spans + 2)^2 numbers."""
    m = band.shape[0]
    b = band.copy()
    y = np.array(rhs, dtype=float)
    for j in range(m - 1):
        for i in range(j + 1, min(j + 3, m)):
            f = b[i, 2 + j - i] / b[j, 2]
            if f != 0.0:
                width = min(3, m - j)  # columns j .. j+2 of row j
                b[i, 2 + j - i : 2 + j - i + width] -= f * b[j, 2 : 2 + width]
                y[i] -= f * y[j]
    x = np.zeros_like(y)
    for j in range(m - 1, -1, -1):
        acc = y[j].copy()
        for c in range(j + 1, min(j + 3, m)):
            acc -= b[j, 2 + c - j] * x[c]
        x[j] = acc / b[j, 2]
    return x


def reference_coordinates(beam: Beam) -> np.ndarray:
    """(spans+2) x 12 reference coordinates (phi, d1, d2, d3) of the control points of a director
    beam, (spans+1) x 6 (r, r') of the nodes of an ANCF cable."""
    if beam.formulation == "ancf":
        return ancf_reference_coordinates(beam)
    n, L = beam.spans, beam.geometry.length
    xi = np.array([_core.greville(n, a) for a in range(n + 2)])
    # Collocation at the Greville abscissae (Schoenberg-Whitney holds, the system is regular).
    band = np.zeros((n + 2, 5))  # band[j, 2 + c - j] = A[j, c]: row j couples columns j-2 .. j+2
    for j, x in enumerate(xi):
        span, N, _, _ = _core.bspline_basis(n, float(x))
        band[j, 2 + span - j : 5 + span - j] = N
    X = np.array([beam.geometry.point_at(float(x) * L) for x in xi])
    P = _solve_banded(band, X)

    t0 = np.asarray(beam.geometry.tangent_at_start())
    d2_0 = np.asarray(beam.d2) if beam.d2 is not None else default_d2(t0)
    d2_0 = d2_0 - d2_0.dot(t0) * t0
    d2_0 /= np.linalg.norm(d2_0)
    frame0 = np.column_stack([t0, d2_0, np.cross(t0, d2_0)])
    q = np.zeros((n + 2, 12))
    h = 1e-7 * L
    frame, tangent = frame0, t0
    for a, x in enumerate(xi):
        s = float(x) * L
        if beam.geometry.kind == "arc":
            frame = _arc_rotation(beam, s) @ frame0
        elif beam.geometry.kind == "polyline":
            # transported from the previous point by the smallest rotation between the tangents
            # (parallel transport: a polyline may turn back on itself, a rope around a sheave);
            # at corners the tangent is the mean of both sides
            following = _tangent(beam, s, h)
            frame = _rotation_between(tangent, following) @ frame
            tangent = following
        q[a, 0:3] = P[a]
        q[a, 3:12] = frame.T.reshape(-1)
    return q
