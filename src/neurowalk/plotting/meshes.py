"""Triangle meshes of MuJoCo's geom shapes, for viewers that draw meshes (the web replay).

A :class:`Mesh` is plain arrays: vertices (n, 3) float32 in m and faces (m, 3) int32 (counter-clockwise seen from
outside). :func:`geom_mesh` gives a model's geom in its body's frame (the geom's own position and orientation
applied), so that the geoms of one body can be merged (:func:`merge`) and moved as one part.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

#: Segments around a round shape (sphere, capsule, cylinder): fine enough to look round at a robot's scale.
SEGMENTS = 16


@dataclass(frozen=True)
class Mesh:
    """A triangle mesh. vertices: (n, 3) float32, m. faces: (m, 3) int32 indices into vertices."""

    vertices: np.ndarray
    faces: np.ndarray

    def moved(self, pos: np.ndarray, quat: np.ndarray) -> Mesh:
        """The mesh rotated by unit quaternion ``quat`` (wxyz) and then shifted by ``pos`` (3,) m."""
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, np.asarray(quat, dtype=float))
        v = self.vertices @ rot.reshape(3, 3).T + np.asarray(pos)
        return Mesh(v.astype(np.float32), self.faces)


def yaw_quat(yaw: float) -> np.ndarray:
    """The unit quaternion (wxyz) of a turn by ``yaw`` rad about z."""
    return np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])


def merge(meshes: list[Mesh]) -> Mesh:
    """One mesh of all of ``meshes`` (their faces re-indexed)."""
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    return Mesh(
        np.concatenate([m.vertices for m in meshes]).astype(np.float32),
        np.concatenate([m.faces + o for m, o in zip(meshes, offsets, strict=True)]).astype(np.int32),
    )


def box_mesh(hx: float, hy: float, hz: float, centre: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Mesh:
    """A box of half sizes ``hx``, ``hy``, ``hz`` m about ``centre``."""
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    v = corners * [hx, hy, hz] + centre
    faces = [
        [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5],  # x-, x+
        [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],  # y-, y+
        [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3],  # z-, z+
    ]  # fmt: skip
    return Mesh(v.astype(np.float32), np.array(faces, dtype=np.int32))


def _lathe(profile: np.ndarray, segments: int = SEGMENTS) -> Mesh:
    """The closed surface of revolution about z of ``profile`` (k, 2): (radius, z) from the bottom up, radius 0 at
    both ends (each end one vertex, the pole)."""
    ang = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    rings = profile[1:-1]
    ring_v = np.stack(
        [rings[:, :1] * np.cos(ang), rings[:, :1] * np.sin(ang), np.repeat(rings[:, 1:], segments, 1)], -1
    )
    v = np.concatenate([[[0.0, 0.0, profile[0, 1]]], ring_v.reshape(-1, 3), [[0.0, 0.0, profile[-1, 1]]]])
    top, n = len(v) - 1, len(rings)
    faces = []
    for j in range(segments):
        k = (j + 1) % segments
        faces.append([0, 1 + k, 1 + j])  # the bottom pole's fan
        for i in range(n - 1):
            a, b = 1 + i * segments + j, 1 + i * segments + k
            faces += [[a, b, b + segments], [a, b + segments, a + segments]]
        faces.append([top, 1 + (n - 1) * segments + j, 1 + (n - 1) * segments + k])  # the top pole's fan
    return Mesh(v.astype(np.float32), np.array(faces, dtype=np.int32))


def capsule_mesh(radius: float, half_length: float, segments: int = SEGMENTS) -> Mesh:
    """A capsule along z: a cylinder of ``half_length`` m either side of the origin with half-sphere ends."""
    a = np.linspace(-np.pi / 2, 0.0, segments // 4 + 1)
    low = np.column_stack([radius * np.cos(a), -half_length + radius * np.sin(a)])
    high = np.column_stack([radius * np.cos(-a[::-1]), half_length - radius * np.sin(-a[::-1])])
    return _lathe(np.concatenate([low, high]), segments)


def ellipsoid_mesh(rx: float, ry: float, rz: float, segments: int = SEGMENTS) -> Mesh:
    """An ellipsoid of radii ``rx``, ``ry``, ``rz`` m (a sphere where they are equal)."""
    a = np.linspace(-np.pi / 2, np.pi / 2, segments // 2 + 1)
    m = _lathe(np.column_stack([np.cos(a), np.sin(a)]), segments)
    return Mesh((m.vertices * [rx, ry, rz]).astype(np.float32), m.faces)


def cylinder_mesh(
    radius: float, half_height: float, centre: tuple[float, float, float] = (0.0, 0.0, 0.0), segments: int = SEGMENTS
) -> Mesh:
    """A closed cylinder along z of ``radius`` and ``half_height`` m about ``centre``."""
    profile = np.array([[0.0, -half_height], [radius, -half_height], [radius, half_height], [0.0, half_height]])
    m = _lathe(profile, segments)
    return Mesh((m.vertices + np.asarray(centre, dtype=np.float32)).astype(np.float32), m.faces)


def geom_mesh(model: mujoco.MjModel, g: int) -> Mesh | None:
    """Geom ``g`` of ``model`` as a mesh in its body's frame; None for a shape without a surface (plane, hfield)."""
    t, size = model.geom_type[g], model.geom_size[g]
    G = mujoco.mjtGeom
    if t == G.mjGEOM_BOX:
        mesh = box_mesh(*size)
    elif t == G.mjGEOM_SPHERE:
        mesh = ellipsoid_mesh(size[0], size[0], size[0])
    elif t == G.mjGEOM_ELLIPSOID:
        mesh = ellipsoid_mesh(*size)
    elif t == G.mjGEOM_CAPSULE:
        mesh = capsule_mesh(size[0], size[1])
    elif t == G.mjGEOM_CYLINDER:
        mesh = cylinder_mesh(size[0], size[1])
    elif t == G.mjGEOM_MESH:
        i = model.geom_dataid[g]
        va, vn = model.mesh_vertadr[i], model.mesh_vertnum[i]
        fa, fn = model.mesh_faceadr[i], model.mesh_facenum[i]
        mesh = Mesh(model.mesh_vert[va : va + vn].astype(np.float32), model.mesh_face[fa : fa + fn].astype(np.int32))
    else:
        return None
    return mesh.moved(model.geom_pos[g], model.geom_quat[g])
