# SPDX-License-Identifier: MIT
"""Irvine's elastic catenary (Irvine, Cable Structures, 1981, section 2.3): a cable of
unstretched length L0, axial stiffness EA and weight w per unstretched length hanging between two
supports at the same height, a horizontal distance l apart. The reference for hanging ropes
(docs/verification.md; scripts/convergence_table.py, tests/python/test_catenary.py)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np


def root_of_increasing(f, target: float, lo: float, hi: float, grow: bool = True, rounds: int = 200) -> float:
    """x in [lo, hi] with f(x) = target for f increasing, by bisection; with grow, hi doubles first
    until f(hi) >= target."""
    while grow and f(hi) < target:
        hi *= 2.0
    for _ in range(rounds):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class ElasticCatenary:
    span: float      # l, horizontal distance of the supports [m]
    length: float    # L0, unstretched length [m]
    EA: float        # axial stiffness [N]
    w: float         # weight per unstretched length [N/m]

    @property
    def V(self) -> float:
        """Vertical reaction at each support: half the weight."""
        return 0.5 * self.w * self.length

    def horizontal_span(self, H: float) -> float:
        """x(L0) for a horizontal tension H."""
        return H * self.length / self.EA + 2.0 * H / self.w * math.asinh(self.V / H)

    @cached_property
    def H(self) -> float:
        """Horizontal tension: the root of x(L0) = l (bisection, once; x grows with H)."""
        if self.horizontal_span(1e-12 * self.w * self.length) > self.span:
            raise ValueError("the supports are further apart than the cable reaches")
        return root_of_increasing(self.horizontal_span, self.span, 1e-12 * self.w * self.length, self.w * self.length)

    def tension(self, s: np.ndarray | float) -> np.ndarray:
        """T(s) = sqrt(H^2 + (V - w s)^2) at unstretched arc length s from the left support."""
        H = self.H
        return np.sqrt(H * H + (self.V - self.w * np.asarray(s, dtype=float)) ** 2)

    def position(self, s: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """(x, z) at unstretched arc length s: x from the left support, z upward (<= 0)."""
        H, V, w, EA = self.H, self.V, self.w, self.EA
        s = np.asarray(s, dtype=float)
        x = H * s / EA + H / w * (np.arcsinh(V / H) - np.arcsinh((V - w * s) / H))
        z = -(w * s / EA * (V / w - s / 2) + H / w * (np.sqrt(1 + (V / H) ** 2) - np.sqrt(1 + ((V - w * s) / H) ** 2)))
        return x, z

    @property
    def sag(self) -> float:
        """Depth of the midpoint below the supports."""
        return float(-self.position(0.5 * self.length)[1])


@dataclass(frozen=True)
class MooringLine:
    """A catenary mooring line partly on the seabed (the quasi-static line of MoorPy and MoorDyn's
    static solve): unstretched length L0, axial stiffness EA, submerged weight w per unstretched
    length, anchored on the seabed, its fairlead a horizontal distance `span` from the anchor and
    `height` above the seabed. The suspended part leaves the seabed horizontally at the touch-down
    point, with the horizontal tension H all along it (Irvine's elastic catenary from a horizontal
    tangent); the grounded part lies straight. On a frictionless seabed (friction = 0) it carries H
    all along; with a seabed friction coefficient CB the friction is taken fully mobilised against
    a pull towards the fairlead (MoorPy's and MAP's model: the line was pulled out), so the
    tension falls by CB w per unit length from H at the touch-down point towards the anchor, not
    below 0, and each piece stretches by its own tension / EA."""

    span: float
    height: float
    length: float
    EA: float
    w: float
    friction: float = 0.0

    def grounded_stretch(self, H: float, grounded: float) -> float:
        """How much the grounded part (unstretched length `grounded`) is stretched: the integral of
        T / EA over it, T = max(H - CB w u, 0) at unstretched distance u from the touch-down point."""
        if self.friction <= 0.0:
            return H * grounded / self.EA
        drop = self.friction * self.w
        if drop * grounded <= H:
            return (H * grounded - 0.5 * drop * grounded**2) / self.EA
        return 0.5 * H * H / (drop * self.EA)

    def _suspended(self, H: float) -> float:
        """The suspended unstretched length that reaches the fairlead's height at tension H."""
        if self.rise(H, self.length) < self.height:
            raise ValueError("the line is too short to rest on the seabed at this tension")
        return root_of_increasing(lambda Ls: self.rise(H, Ls), self.height, 0.0, self.length, grow=False)

    def rise(self, H: float, suspended: float) -> float:
        """Height of the fairlead above the touch-down point for a suspended length at tension H."""
        a = self.w * suspended / H
        return H / self.w * (math.sqrt(1.0 + a * a) - 1.0) + self.w * suspended**2 / (2.0 * self.EA)

    def reach(self, H: float) -> float:
        """Horizontal distance anchor to fairlead at tension H."""
        Ls = self._suspended(H)
        grounded = self.length - Ls
        return (grounded + self.grounded_stretch(H, grounded) + H / self.w * math.asinh(self.w * Ls / H)
                + H * Ls / self.EA)

    @cached_property
    def H(self) -> float:
        """Horizontal tension: the root of reach(H) = span (bisection; the reach grows with H)."""
        return root_of_increasing(self.reach, self.span, 1e-9 * self.w * self.length, self.w * self.length)

    @property
    def suspended_length(self) -> float:
        return self._suspended(self.H)

    @property
    def fairlead_tension(self) -> float:
        return math.hypot(self.H, self.w * self.suspended_length)

    @property
    def touchdown(self) -> float:
        """Horizontal distance of the touch-down point from the anchor."""
        grounded = self.length - self.suspended_length
        return grounded + self.grounded_stretch(self.H, grounded)

    @property
    def anchor_tension(self) -> float:
        """The anchor's horizontal pull: H less the seabed friction over the grounded part, not
        below 0."""
        return max(self.H - self.friction * self.w * (self.length - self.suspended_length), 0.0)


def catenary_end(L0: float, H: float, V: float, EA: float, w: float, s: float | None = None) -> tuple[float, float]:
    """(x, z) at unstretched arc length s (default: the end, L0) of an elastic catenary from the
    origin: horizontal tension H, vertical force V at the origin (upward on the cable, so z rises
    while V > w s), z upward (Irvine's equations 2.17-2.18 in general form)."""
    s = L0 if s is None else s
    a0, a1 = V / H, (V - w * s) / H
    x = H * s / EA + H / w * (math.asinh(a0) - math.asinh(a1))
    z = w * s / EA * (V / w - s / 2.0) + H / w * (math.sqrt(1.0 + a0 * a0) - math.sqrt(1.0 + a1 * a1))
    return x, -z


def _length_and_lift(H: float, span: float, rise: float, EA: float, w: float, L0: float, V: float) -> tuple[float, float]:
    """Newton on (L0, V) for a catenary of horizontal tension H ending at (span, rise)."""
    for _ in range(100):
        x, z = catenary_end(L0, H, V, EA, w)
        r = np.array([x - span, z - rise])
        if abs(r[0]) + abs(r[1]) <= 1e-13 * (span + abs(rise)):
            break
        d = 1e-7 * max(L0, 1.0)
        J = np.empty((2, 2))
        for k, (dL, dV) in enumerate(((d, 0.0), (0.0, 1e-7 * max(abs(V), w * L0)))):
            xp, zp = catenary_end(L0 + dL, H, V + dV, EA, w)
            J[:, k] = ((xp - x) / (dL or dV), (zp - z) / (dL or dV))
        step = np.linalg.solve(J, r)
        L0, V = L0 - step[0], V - step[1]
    return L0, V


def unstretched_length_at(span: float, rise: float, EA: float, w: float, *, H: float | None = None,
                          sag: float | None = None) -> float:
    """The unstretched length of an elastic catenary between supports a horizontal distance `span`
    apart, the second `rise` higher (negative: lower), with weight w per unstretched length:
    given its horizontal tension H, or its sag (the vertical distance between the chord and the
    cable at mid-span)."""
    chord = math.hypot(span, rise)
    if H is not None:
        if not H > 0.0:
            raise ValueError("the horizontal tension must be > 0")
        # start from the parabola: L0 ~ chord + w^2 span^3 / (24 H^2 cos)
        L0 = chord * (1.0 + (w * span) ** 2 / (24.0 * H * H)) / (1.0 + H / EA)
        V = 0.5 * w * L0 + H * rise / span
        return _length_and_lift(H, span, rise, EA, w, L0, V)[0]
    if sag is None or not sag > 0.0:
        raise ValueError("give H > 0 or sag > 0")

    def sag_at(H: float) -> float:
        L0 = unstretched_length_at(span, rise, EA, w, H=H)
        _, V = _length_and_lift(H, span, rise, EA, w, L0, 0.5 * w * L0 + H * rise / span)
        # the arc length at mid-span (x grows with s)
        s = root_of_increasing(lambda s: catenary_end(L0, H, V, EA, w, s)[0], 0.5 * span, 0.0, L0, grow=False, rounds=100)
        return 0.5 * rise - catenary_end(L0, H, V, EA, w, s)[1]

    lo, hi = 1e-3 * w * span, w * span * span / sag  # sag falls as H grows
    while sag_at(lo) < sag:
        lo *= 0.5
    while sag_at(hi) > sag:
        hi *= 2.0
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if sag_at(mid) > sag else (lo, mid)
    return unstretched_length_at(span, rise, EA, w, H=math.sqrt(lo * hi))
