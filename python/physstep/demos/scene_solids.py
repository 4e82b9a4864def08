"""The solids of a scene file, drawn by the generic scene demo (``physstep demo --scene``).

The World gives the solids' poses; their shapes are read from the file's ``[[solids]]``
tables (the loader has accepted it). In 2D each shape is drawn as it is (circles with a
radius line that shows the turn, boxes, capsules, polygons, segments, the ground line of a
plane), filled; in 3D as the demo's orthographic projection (boxes and hulls as wire frames,
spheres as discs, capsules as their two end spheres and sides, a plane as a square patch, a
mesh as its edges). Dynamic solids are orange, static and kinematic ones grey.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pygame

import physstep
from physstep.demos import base
from physstep.demos.racket import rotation

DYNAMIC, DYNAMIC_EDGE = (205, 150, 80), (240, 200, 140)
STILL, STILL_EDGE = (44, 49, 62), (140, 147, 165)
#: Segments of a circle's arc in a capsule's outline.
ARC = 12
#: A plane is drawn as a square patch this many times the view's size across.
PLANE_PATCH = 0.6
#: Meshes with more triangles than this are drawn as their vertices only.
MESH_EDGES = 4000


@dataclass(frozen=True)
class Solid:
    """A solid as the file describes it: its shape table and whether it moves."""

    shape: dict[str, Any]
    dynamic: bool


def read(doc: dict[str, Any]) -> list[Solid]:
    """The solids of a parsed scene file, in the World's order."""
    return [Solid(dict(s["shape"]), s.get("kind", "dynamic") == "dynamic") for s in doc.get("solids", [])]


def reach(shape: dict[str, Any]) -> float | None:
    """How far a shape reaches from its origin, m; None for a plane or a mesh (drawn, not
    fitted: they are the ground)."""
    kind = shape["kind"]
    if kind == "circle":
        return float(shape["radius"])
    if kind == "box":
        return float(np.linalg.norm(shape["half"]))
    if kind == "capsule":
        return float(shape["half_height"]) + float(shape["radius"])
    if kind == "polygon":
        return float(np.linalg.norm(np.array(shape["points"], dtype=float), axis=-1).max())
    if kind == "segment":
        ends = np.array([shape["a"], shape["b"]], dtype=float)
        return float(np.linalg.norm(ends, axis=1).max()) + float(shape.get("radius", 0.0))
    return None


def _turn2(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _capsule2(half_height: float, radius: float) -> np.ndarray:
    """A 2D capsule's outline along y in its own frame."""
    top = [(radius * math.cos(t), half_height + radius * math.sin(t)) for t in np.linspace(0, math.pi, ARC)]
    bottom = [
        (radius * math.cos(t), -half_height + radius * math.sin(t))
        for t in np.linspace(math.pi, 2 * math.pi, ARC)
    ]
    return np.array(top + bottom)


def _round_segment2(a: np.ndarray, b: np.ndarray, radius: float) -> np.ndarray:
    """The outline of segment ``a``-``b`` thickened by ``radius`` (2D)."""
    d = b - a
    theta = math.atan2(d[1], d[0])
    half = [
        a + radius * np.array([math.cos(t), math.sin(t)])
        for t in np.linspace(theta + math.pi / 2, theta + 1.5 * math.pi, ARC)
    ]
    other = [
        b + radius * np.array([math.cos(t), math.sin(t)])
        for t in np.linspace(theta - math.pi / 2, theta + math.pi / 2, ARC)
    ]
    return np.array(half + other)


Screen = Callable[[Any], tuple[int, int]]
Pixel = Callable[[Any], tuple[float, float]]


def clip(poly: list[tuple[float, float]], rect: pygame.Rect) -> list[tuple[int, int]]:
    """Polygon ``poly`` (pixels, any size) cut to ``rect`` widened by a few pixels
    (Sutherland-Hodgman): a 200 m ground drawn at a box's scale keeps its shape."""
    r = rect.inflate(8, 8)
    edges: tuple[tuple[Callable[[tuple[float, float]], bool], Callable[..., tuple[float, float]]], ...] = (
        (lambda p: p[0] >= r.left, lambda a, b: _cross(a, b, 0, r.left)),
        (lambda p: p[0] <= r.right, lambda a, b: _cross(a, b, 0, r.right)),
        (lambda p: p[1] >= r.top, lambda a, b: _cross(a, b, 1, r.top)),
        (lambda p: p[1] <= r.bottom, lambda a, b: _cross(a, b, 1, r.bottom)),
    )
    out = list(poly)
    for inside, cross in edges:
        pts, out = out, []
        for k, b in enumerate(pts):
            a = pts[k - 1]
            if inside(b):
                if not inside(a):
                    out.append(cross(a, b))
                out.append(b)
            elif inside(a):
                out.append(cross(a, b))
    return [(round(x), round(y)) for x, y in out]


def _cross(a: tuple[float, float], b: tuple[float, float], axis: int, at: float) -> tuple[float, float]:
    """Where segment ``a``-``b`` crosses coordinate ``axis`` = ``at``."""
    t = (at - a[axis]) / (b[axis] - a[axis])
    x, y = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
    return (at, y) if axis == 0 else (x, at)


def draw_2d(
    surf: pygame.Surface,
    screen: Screen,
    pixel: Pixel,
    rect: pygame.Rect,
    scale: float,
    solids: list[Solid],
    poses: tuple[np.ndarray, np.ndarray],
    extent: float,
) -> None:
    """The 2D solids at ``poses`` (positions and orientations, as
    :func:`physstep.demos.base.solid_poses` gives them); ``screen`` maps a world point to the
    panel (clipped to what pygame draws), ``pixel`` the same unclipped (polygons are cut to
    ``rect``), ``scale`` is pixels a metre, ``extent`` the view's size (m: how long a plane's
    line is drawn)."""
    for solid, p, a in zip(solids, *poses, strict=False):
        shape, kind = solid.shape, solid.shape["kind"]
        angle = float(np.ravel(a)[0])
        turn = _turn2(angle)
        fill, edge = (DYNAMIC, DYNAMIC_EDGE) if solid.dynamic else (STILL, STILL_EDGE)
        if kind == "circle":
            r = float(shape["radius"])
            c = screen(p)
            pygame.draw.circle(surf, fill, c, max(2, round(r * scale)))
            pygame.draw.circle(surf, edge, c, max(2, round(r * scale)), 2)
            pygame.draw.line(surf, edge, c, screen(p + turn @ np.array([r, 0.0])), 2)
            continue
        if kind == "plane":
            n = turn @ np.array(shape["normal"], dtype=float)
            along = np.array([-n[1], n[0]]) / float(np.linalg.norm(n)) * extent * 4
            pygame.draw.line(surf, edge, screen(p - along), screen(p + along), 3)
            continue
        if kind == "box":
            hx, hy = (float(h) for h in shape["half"])
            local = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
        elif kind == "capsule":
            local = _capsule2(float(shape["half_height"]), float(shape["radius"]))
        elif kind == "polygon":
            local = np.array(shape["points"], dtype=float).reshape(-1, 2)
        elif kind == "segment":
            ends = np.array([shape["a"], shape["b"]], dtype=float)
            r = float(shape.get("radius", 0.0))
            if r == 0.0:
                pygame.draw.line(surf, edge, screen(p + turn @ ends[0]), screen(p + turn @ ends[1]), 2)
                continue
            local = _round_segment2(ends[0], ends[1], r)
        else:
            continue
        pts = clip([pixel(p + turn @ q) for q in local], rect)
        if len(pts) >= 3:
            pygame.draw.polygon(surf, fill, pts)
            pygame.draw.polygon(surf, edge, pts, 2)


def _hull2(pts: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The convex hull of screen points (monotone chain), counter-clockwise."""
    p = sorted(set(pts))
    if len(p) < 3:
        return p

    def cross(o: tuple[int, int], a: tuple[int, int], b: tuple[int, int]) -> int:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[int, int]] = []
    upper: list[tuple[int, int]] = []
    for q in p:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], q) <= 0:
            lower.pop()
        lower.append(q)
    for q in reversed(p):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], q) <= 0:
            upper.pop()
        upper.append(q)
    return lower[:-1] + upper[:-1]


def draw_3d(
    surf: pygame.Surface,
    screen: Screen,
    scale: float,
    wire: Callable[[list[Any], tuple[int, int, int]], None],
    solids: list[Solid],
    poses: tuple[np.ndarray, np.ndarray],
    extent: float,
) -> None:
    """The 3D solids at ``poses`` (as :func:`draw_2d` takes them) in the demo's projection
    (``screen``, ``scale`` pixels a metre, ``wire`` draws a box from its 8 corners,
    ``extent`` the view's size, m)."""
    for solid, p, q in zip(solids, *poses, strict=False):
        shape, kind = solid.shape, solid.shape["kind"]
        r = rotation(q)
        edge = DYNAMIC_EDGE if solid.dynamic else STILL_EDGE
        if kind == "box":
            half = np.array(shape["half"], dtype=float)
            wire([p + r @ (half * [sx, sy, sz]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], edge)
        elif kind == "circle":
            c = screen(p)
            rad = max(2, round(float(shape["radius"]) * scale))
            pygame.draw.circle(surf, DYNAMIC if solid.dynamic else STILL, c, rad)
            pygame.draw.circle(surf, edge, c, rad, 2)
            pygame.draw.line(surf, edge, c, screen(p + r[:, 0] * float(shape["radius"])), 2)
        elif kind == "capsule":
            h, radius = float(shape["half_height"]), float(shape["radius"])
            ends = [screen(p + r @ np.array([0.0, s * h, 0.0])) for s in (-1, 1)]
            px = max(2, round(radius * scale))
            for c in ends:
                pygame.draw.circle(surf, edge, c, px, 2)
            d = np.array(ends[1], dtype=float) - np.array(ends[0], dtype=float)
            n = np.array([-d[1], d[0]]) / max(1e-9, float(np.linalg.norm(d))) * px
            for s in (-1, 1):
                a, b = np.array(ends[0]) + s * n, np.array(ends[1]) + s * n
                pygame.draw.aaline(surf, edge, (float(a[0]), float(a[1])), (float(b[0]), float(b[1])))
        elif kind == "polygon":
            pts = [screen(p + r @ v) for v in np.array(shape["points"], dtype=float).reshape(-1, 3)]
            hull = _hull2(pts)
            if len(hull) >= 3:
                pygame.draw.polygon(surf, edge, hull, 2)
            for c in pts:
                pygame.draw.circle(surf, edge, c, 2)
        elif kind == "segment":
            a, b = (p + r @ np.array(shape[k], dtype=float) for k in ("a", "b"))
            pygame.draw.line(
                surf, edge, screen(a), screen(b), max(2, round(2 * float(shape.get("radius", 0)) * scale))
            )
        elif kind == "plane":
            n = r @ np.array(shape["normal"], dtype=float)
            n /= float(np.linalg.norm(n))
            t1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
            t1 /= float(np.linalg.norm(t1))
            t2 = np.cross(n, t1)
            size = extent * PLANE_PATCH
            for k in np.linspace(-1, 1, 7):
                pygame.draw.aaline(
                    surf, STILL_EDGE, screen(p + size * (k * t1 - t2)), screen(p + size * (k * t1 + t2))
                )
                pygame.draw.aaline(
                    surf, STILL_EDGE, screen(p + size * (k * t2 - t1)), screen(p + size * (k * t2 + t1))
                )
        elif kind == "mesh":
            v = np.array(shape["vertices"], dtype=float).reshape(-1, 3) @ r.T + p
            pts = [screen(c) for c in v]
            tris = np.array(shape["triangles"], dtype=int).reshape(-1, 3)
            if len(tris) > MESH_EDGES:
                for c in pts:
                    surf.set_at(c, edge)
                continue
            for t in tris:
                pygame.draw.aalines(surf, edge, True, [pts[int(k)] for k in t])


def hud_rows(w: physstep.World) -> list[tuple[str, str, tuple[int, int, int]]]:
    """The solids' lines of the HUD: how many, the contacts touching and the deepest."""
    if not w.solid_count:
        return []
    touching = int(np.count_nonzero(w.contacts()["depths"] >= 0.0))
    return [
        ("solids", f"{w.solid_count}", base.TEXT),
        ("contacts", f"{touching} (max {w.max_penetration * 1000:.2f} mm in)", base.TEXT),
    ]
