"""Writhe of a closed polygon by the Gauss double integral. Float-only kernel.

Used to verify the writhe formula of docs/theory/geometry.md independently: a
discretised double helix (two strands joined at the head, led straight out
and closed by a large rectangle far away) has a well-defined writhe.

The Gauss integral ``Wr = (1/4pi) oint oint (t1 x t2) . (r1 - r2) / |r1 - r2|^3``
is evaluated exactly for a polygon with the segment-pair solid angle of
Klenin & Langowski, Biopolymers 54, 307 (2000): for segments i, j the
contribution is ``Omega_ij / 4pi`` with ``Omega`` the signed solid angle
under which one segment sees the other. The only error is the polygonisation
of the smooth curve, O(h^2) in the segment length h.
"""

from __future__ import annotations

import numpy as np


def _cross(a, b):
    """Cross product of vectors given as ``(x, y, z)`` component arrays."""
    ax, ay, az = a
    bx, by, bz = b
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


def _unit(v):
    """``v / |v|`` per element of ``(x, y, z)`` component arrays (0 where ``|v| = 0``)."""
    x, y, z = v
    norm = np.sqrt(x * x + y * y + z * z)
    inv = np.divide(1.0, norm, out=np.zeros_like(norm), where=norm > 0)
    return x * inv, y * inv, z * inv


def _asin_dot(a, b):
    d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    return np.arcsin(np.clip(d, -1.0, 1.0, out=d), out=d)


def _minus(a, b):
    return tuple(x - y for x, y in zip(a, b, strict=True))


def writhe_polygon(points, chunk: int = 400) -> float:
    """Writhe of the closed polygon through ``points`` (shape (n, 3)).

    The last point is joined to the first. Cost O(n^2) in time, O(chunk n) in
    memory. The vectors are held as three component arrays (no ``np.cross`` over a
    trailing axis of length 3: several times faster for the same arithmetic).
    """
    p = np.asarray(points, dtype=float)
    q = np.roll(p, -1, axis=0)
    n = len(p)
    p3 = tuple(p[None, :, k] for k in range(3))
    p4 = tuple(q[None, :, k] for k in range(3))
    d34 = _minus(p4, p3)
    col = np.arange(n)[None, :]
    total = 0.0
    for a in range(0, n, chunk):
        i = np.arange(a, min(a + chunk, n))
        p1 = tuple(p[i, k][:, None] for k in range(3))
        p2 = tuple(q[i, k][:, None] for k in range(3))
        r13, r14, r23, r24 = _minus(p3, p1), _minus(p4, p1), _minus(p3, p2), _minus(p4, p2)
        n1 = _unit(_cross(r13, r14))
        n2 = _unit(_cross(r14, r24))
        n3 = _unit(_cross(r24, r23))
        n4 = _unit(_cross(r23, r13))
        omega = _asin_dot(n1, n2) + _asin_dot(n2, n3) + _asin_dot(n3, n4) + _asin_dot(n4, n1)
        c = _cross(d34, _minus(p2, p1))
        sign = np.sign(c[0] * r13[0] + c[1] * r13[1] + c[2] * r13[2])
        row = i[:, None]
        keep = (col != row) & (col != (row + 1) % n) & (col != (row - 1) % n)
        total += float(np.sum(np.where(keep, omega * sign, 0.0)))
    return total / (4.0 * np.pi)


def double_helix_polygon(alpha, radius, turns, handedness=-1, points_per_turn=120):
    """Closed polygon of a uniform double helix with ``turns`` superhelical turns.

    Strand 1 is ``(R cos(h t), R sin(h t), P t / 2pi)`` for t in [0, 2 pi turns],
    strand 2 its rotation by pi about the axis; ``h = handedness`` (+1 right-,
    -1 left-handed strands). At the head (t = 0) the strands are joined by a
    half circle of radius R below the helix; at the far end both run straight
    along +z for 10^3 helix heights and are closed by a rectangle 10^4 helix
    heights wide, so that the closure adds a vanishing writhe.
    """
    pitch = 2.0 * np.pi * radius / np.tan(alpha)
    t = np.linspace(0.0, 2.0 * np.pi * turns, int(np.ceil(points_per_turn * turns)) + 1)
    s1 = np.column_stack(
        (radius * np.cos(handedness * t), radius * np.sin(handedness * t), pitch * t / (2 * np.pi))
    )
    s2 = s1 * np.array([-1.0, -1.0, 1.0])
    scale = s1[-1, 2] + radius
    z_far, x_far = 1e3 * scale, 1e4 * scale
    top1, top2 = s1[-1], s2[-1]
    offsets1 = np.array([[0, 0, z_far], [x_far, 0, z_far], [x_far, 0, z_far + x_far]])
    offsets2 = np.array([[-x_far, 0, z_far + x_far], [-x_far, 0, z_far], [0, 0, z_far]])
    closure = np.vstack((top1 + offsets1, top2 + offsets2))
    # head: from strand 2's start (-R cos 0, ...) = (-R, 0, 0) to (R, 0, 0)
    phi = np.linspace(np.pi, 2.0 * np.pi, 33)[1:-1]
    head = np.column_stack((radius * np.cos(phi), np.zeros_like(phi), radius * np.sin(phi)))
    return np.vstack((s1, closure, s2[::-1], head))
