"""Scene description handed to the native solver, as plain numpy arrays.

The Blender layer fills a SceneInput (clusters + objects); this module validates it, hashes it
for the solution cache and turns it into a native Scene.
"""
from dataclasses import dataclass, field
import hashlib

import numpy as np

DEFAULT_REFLECTANCE = 0.8      # objects without material: Blender's default grey
MAX_REFLECTANCE = 0.999        # rho = 1 makes the system singular (no convergence); clamp below
# The native solver works in the scene's frame (its bounding-box diagonal) snapped to a 2^-36
# grid (README "Scale"): an object smaller than this fraction of the scene's size collapses to
# zero-area polygons. One object placed absurdly far away (Blender stores an infinite location
# as 3.4e38) would make every other object vanish and the bake come out black with a misleading
# "no emitter" warning, so such a scene is refused with the objects named.
MIN_OBJECT_FRACTION = 1e-10


class InputError(ValueError):
    """Bad scene input; the message names the object and the problem."""


@dataclass
class ClusterInput:
    name: str
    parent: int = -1           # index into SceneInput.clusters, -1 = root


@dataclass
class ObjectInput:
    name: str
    cluster: int               # index into SceneInput.clusters, -1 = directly in the scene
    vertices: np.ndarray       # float64 (V,3) world space
    loop_starts: np.ndarray    # int32 (F,)
    loop_totals: np.ndarray    # int32 (F,)
    corner_verts: np.ndarray   # int32 (C,)
    reflectance: np.ndarray    # float32 (F,3)
    emission: np.ndarray       # float32 (F,3)
    # Corner permutation applied before handing to the solver (mirrored objects), or None.
    corner_perm: object = None
    # Opaque handle of the Blender layer (which mesh to write, or None = participate only).
    target: object = None
    # World matrix (float64 4x4) the vertices were transformed with, and the object-space
    # (evaluated, modifiers applied) vertices: what the incremental re-bake compares to tell a
    # rigid move from a shape change. None: vertices are taken as they are (identity).
    matrix: object = None
    local_vertices: object = None
    # Per polygon one- or two-sided (None: all two-sided) and whether it casts shadows: an
    # area light is one-sided and, as in Cycles, transparent to other light.
    two_sided: object = None
    occluder: bool = True
    # Whether its colours are read (written to a mesh): False for instances, area lights and
    # meshes that cannot be written. The solver then gathers no light at its corners (the
    # costliest phase) while it still casts and reflects light.
    output: bool = True
    # Modifiers that change the corner layout: per corner of the mesh written (the original),
    # the corner of this (evaluated) object whose value it takes (core.corners.
    # original_corner_map). None: the corners are the written mesh's own.
    corner_map: object = None
    # An instance (collection, geometry nodes, particles): the name of the object instancing it.
    # It casts and reflects light and is never written.
    instance_of: str = None
    # Textured materials (addon/radiosity/textures.py): float32 (C,3) per corner, Blender
    # order, what the material evaluates to at each corner (None: the polygon's value). Only
    # the output uses them; `reflectance`/`emission` then hold each polygon's area mean.
    corner_reflectance: object = None
    corner_emission: object = None
    # ... and, for the transport, the texture inside textured polygons: a tuple (face int32
    # (P,), world position float64 (P,3), area float64 (P,), reflectance float32 (P,3),
    # emission float32 (P,3) or None) of the pieces of a cut copy (textures.py), or None.
    # Elements take the area mean of the pieces inside them, so a checker's squares inside one
    # quad are not one mix.
    texture_pieces: object = None

    @property
    def corner_count(self):
        return int(len(self.corner_verts))

    def written_values(self, per_corner):
        """Per-corner values (evaluated order) -> the written mesh's corners."""
        if self.corner_map is None:
            return per_corner
        return per_corner[np.asarray(self.corner_map, dtype=np.int64)]

    @property
    def written_corner_count(self):
        return self.corner_count if self.corner_map is None else int(len(self.corner_map))

    @property
    def polygon_count(self):
        return int(len(self.loop_starts))


@dataclass
class SceneInput:
    clusters: list = field(default_factory=list)
    objects: list = field(default_factory=list)
    lights: list = field(default_factory=list)     # core.lights.LightInput (point/spot/sun/sky)
    lighting_only: bool = False    # output irradiance / pi instead of radiance (see README)
    adaptive_mesh: bool = False    # also return the leaf elements as meshes
    # Names of mesh objects that take part but cannot receive colours (linked library data,
    # Edit Mode, a topology-changing modifier, a shared mesh): reported, never written.
    unwritable: list = field(default_factory=list)
    # Objects of the view layer whose geometry takes part (instances and lights not counted),
    # and per instancing object how many of its instances take part (occluders only).
    scene_objects: int = 0
    instancers: dict = field(default_factory=dict)

    @property
    def instance_count(self):
        return int(sum(self.instancers.values()))
    # What evaluating textured materials and the world cost (textures.py, world.py): stats keys.
    evaluation_stats: dict = field(default_factory=dict)

    def add_cluster(self, name, parent=-1):
        self.clusters.append(ClusterInput(name, parent))
        return len(self.clusters) - 1

    @property
    def polygon_count(self):
        return sum(o.polygon_count for o in self.objects)

    def has_emitter(self):
        return (any(bool((o.emission > 0.0).any()) for o in self.objects)
                or any(max(li.intensity) > 0.0 for li in self.lights))


def clamp_reflectance(rgb):
    """Reflectance clamp [0, 0.999] (documented in README: rho>=1 never converges)."""
    return np.clip(np.asarray(rgb, dtype=np.float32), 0.0, MAX_REFLECTANCE)


def clamp_emission(rgb):
    return np.maximum(np.asarray(rgb, dtype=np.float32), 0.0)


def face_table(slot_values, material_index, default):
    """Per-face (F,3) float32 from a per-slot table and the polygons' material_index.

    Blender clamps an out-of-range material_index to the last slot; we do the same. An object
    without slots gets ``default`` on every face.
    """
    mi = np.asarray(material_index, dtype=np.int64)
    if len(slot_values) == 0:
        return np.tile(np.asarray(default, dtype=np.float32), (len(mi), 1))
    table = np.asarray(slot_values, dtype=np.float32).reshape(-1, 3)
    return table[np.clip(mi, 0, len(table) - 1)]


def validate_object(obj):
    """Cheap checks with clear messages before the native module sees the data."""
    name = obj.name
    v = obj.vertices
    if v.ndim != 2 or v.shape[1] != 3:
        raise InputError(f"object '{name}': vertex array has shape {v.shape}")
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        raise InputError(f"object '{name}': vertex {int(np.argmax(bad))} has a NaN or infinite "
                         f"coordinate ({int(bad.sum())} bad vertices)")
    F = obj.polygon_count
    if obj.loop_totals.shape != (F,) or obj.reflectance.shape != (F, 3) \
            or obj.emission.shape != (F, 3):
        raise InputError(f"object '{name}': inconsistent per-polygon array lengths")
    if F and (obj.loop_totals < 3).any():
        p = int(np.argmax(obj.loop_totals < 3))
        raise InputError(f"object '{name}': polygon {p} has fewer than 3 corners")
    if int(obj.loop_totals.sum()) != obj.corner_count:
        raise InputError(f"object '{name}': polygon corner counts do not add up")
    cv = obj.corner_verts
    if len(cv) and (cv.min() < 0 or cv.max() >= len(v)):
        raise InputError(f"object '{name}': corner refers to a vertex that does not exist")
    cm = obj.corner_map
    if cm is not None and len(cm) and (np.min(cm) < 0 or np.max(cm) >= obj.corner_count):
        raise InputError(f"object '{name}': a corner of the written mesh maps to no corner of "
                         f"the evaluated mesh")
    for label, arr in (("reflectance", obj.reflectance), ("emission", obj.emission)):
        if not np.isfinite(arr).all():
            p = int(np.argmax(~np.isfinite(arr).all(axis=1)))
            raise InputError(f"object '{name}': polygon {p} has a non-finite {label}")
    for label, arr in (("corner reflectance", obj.corner_reflectance),
                       ("corner emission", obj.corner_emission)):
        if arr is None:
            continue
        if np.shape(arr) != (obj.corner_count, 3):
            raise InputError(f"object '{name}': {label} has shape {np.shape(arr)}")
        if not np.isfinite(arr).all():
            raise InputError(f"object '{name}': a non-finite {label}")
    if obj.texture_pieces is not None:
        face, pos, area, rho, emission = obj.texture_pieces
        n = len(face)
        if np.shape(pos) != (n, 3) or np.shape(area) != (n,) or np.shape(rho) != (n, 3) \
                or (emission is not None and np.shape(emission) != (n, 3)):
            raise InputError(f"object '{name}': texture pieces of mismatched shapes")
        if n and (np.min(face) < 0 or np.max(face) >= obj.polygon_count):
            raise InputError(f"object '{name}': a reflectance piece names a missing polygon")
        if not (np.isfinite(pos).all() and np.isfinite(area).all() and np.isfinite(rho).all()
                and (emission is None or np.isfinite(emission).all())):
            raise InputError(f"object '{name}': a non-finite texture piece")


def validate_light(li):
    """Lights reach the native module as plain numbers: NaN/inf there would light nothing (or
    everything) silently, and a NaN intensity would even pass for "no emitter"."""
    fields = (("intensity", li.intensity), ("position", li.position),
              ("direction", li.direction), ("radius", (li.radius,)), ("angle", (li.angle,)),
              ("spot size", (li.spot_size,)), ("spot blend", (li.spot_blend,)))
    for label, values in fields:
        if not np.isfinite(np.asarray(values, dtype=np.float64)).all():
            raise InputError(f"light '{li.name}': its {label} has a NaN or infinite value "
                             f"({tuple(float(x) for x in np.ravel(values))})")


def _length(v):
    """Euclidean length without overflow of the squares (coordinates up to float64's range)."""
    m = float(np.max(np.abs(v)))
    return m * float(np.linalg.norm(np.asarray(v) / m)) if m > 0 else 0.0


def check_extent(scene_input):
    """Refuse a scene in which some object is too small to exist in the solver's frame because
    another one is absurdly far away (see MIN_OBJECT_FRACTION)."""
    boxes = []
    for o in scene_input.objects:
        if len(o.vertices):
            boxes.append((o.name, o.vertices.min(axis=0), o.vertices.max(axis=0)))
    if len(boxes) < 2:
        return      # one object alone is always representable (results are scale invariant)
    lo = np.min([b[1] for b in boxes], axis=0)
    hi = np.max([b[2] for b in boxes], axis=0)
    diag = _length(hi - lo)
    sizes = {n: _length(b - a) for n, a, b in boxes}
    vanish = [n for n, s in sizes.items() if 0.0 < s < MIN_OBJECT_FRACTION * diag]
    if not vanish:
        return
    # The culprit: the object farthest from where most of the scene is.
    centre = np.median([0.5 * (a + b) for _, a, b in boxes], axis=0)
    far = max(boxes, key=lambda b: float(np.linalg.norm(0.5 * (b[1] + b[2]) - centre)))
    where = 0.5 * (far[1] + far[2])
    vanish = [n for n in vanish if n != far[0]] or vanish   # the culprit may be tiny itself
    listed = ", ".join(f"'{n}'" for n in vanish[:5]) + (" …" if len(vanish) > 5 else "")
    raise InputError(
        f"object '{far[0]}' lies too far from the rest of the scene (at "
        f"({where[0]:.3g}, {where[1]:.3g}, {where[2]:.3g}); the scene spans {diag:.3g}): "
        f"{listed} would be smaller than the solver's resolution ({MIN_OBJECT_FRACTION:g} of the "
        f"scene's size); move '{far[0]}' closer, or hide it from render")


def validate(scene_input):
    if not scene_input.objects:
        raise InputError("nothing to bake: no visible, renderable mesh object with faces")
    for obj in scene_input.objects:
        validate_object(obj)
    for li in scene_input.lights:
        validate_light(li)
    check_extent(scene_input)


def fingerprint(scene_input, settings_key):
    """Digest of everything that affects the solution (geometry, materials, clusters, settings).

    Equal digest -> the kept solver's results are still valid and can simply be written again.
    """
    h = hashlib.blake2b(digest_size=20)
    h.update(repr(settings_key).encode())
    for c in scene_input.clusters:
        h.update(f"C|{c.name}|{c.parent}".encode())
    for o in scene_input.objects:
        h.update(f"O|{o.name}|{o.cluster}|{o.target is not None}|{o.occluder}|{o.output}".encode())
        if o.two_sided is not None:
            h.update(np.ascontiguousarray(o.two_sided, dtype=np.uint8).tobytes())
        if o.corner_map is not None:
            h.update(b"M" + np.ascontiguousarray(o.corner_map, dtype=np.int64).tobytes())
        for arr, dtype in ((o.vertices, np.float64), (o.loop_starts, np.int32),
                           (o.loop_totals, np.int32), (o.corner_verts, np.int32),
                           (o.reflectance, np.float32), (o.emission, np.float32)):
            a = np.ascontiguousarray(arr, dtype=dtype)
            h.update(str(a.shape).encode())
            h.update(a.tobytes())
        for label, arr in (("CR", o.corner_reflectance), ("CE", o.corner_emission)):
            if arr is not None:
                h.update(label.encode())
                h.update(np.ascontiguousarray(arr, dtype=np.float32).tobytes())
    for li in scene_input.lights:
        h.update(repr(li.key()).encode())
    return h.hexdigest()


def cluster_paths(scene_input):
    """Per cluster the '/'-joined names from the root: identifies a cluster across bakes."""
    paths = []
    for c in scene_input.clusters:
        paths.append((paths[c.parent] + "/" if c.parent >= 0 else "") + c.name)
    return paths


def object_matrix(obj):
    return np.eye(4) if obj.matrix is None else np.asarray(obj.matrix, dtype=np.float64)


SHAPE_TOLERANCE = 1e-6     # object-space vertices this close (of the object's size) are the same shape


class Shape:
    """What a rigid move leaves unchanged: cluster, topology, object-space shape. Equal when
    everything but the vertex positions is identical (a digest) and the positions agree within
    SHAPE_TOLERANCE of the object's size: an evaluated Bevel + Subdivision Surface mesh comes
    out about 1e-8 different from one evaluation to the next, and an exact comparison replaced
    every such unmoved object at each incremental bake."""
    __slots__ = ("digest", "local")

    def __init__(self, digest, local):
        self.digest = digest
        self.local = local

    def __eq__(self, other):
        if not isinstance(other, Shape):
            return NotImplemented
        if self.digest != other.digest or self.local.shape != other.local.shape:
            return False
        if self.local.size == 0:
            return True
        size = float(np.max(np.ptp(self.local, axis=0)))
        diff = float(np.max(np.abs(self.local - other.local)))
        return diff <= SHAPE_TOLERANCE * size

    __hash__ = None


def shape_digest(obj, cluster_path):
    """The object's Shape (above). Materials and the placement are not part of it (the
    incremental path updates those). Whether its colours are read is: the native object is
    made with it, so an object that becomes writable (out of Edit Mode, the first user of its
    mesh) is replaced and gathered."""
    h = hashlib.blake2b(digest_size=20)
    h.update(f"{obj.name}|{cluster_path}|{obj.corner_perm is not None}|{obj.occluder}|"
             f"{obj.output}".encode())
    if obj.two_sided is not None:
        h.update(np.ascontiguousarray(obj.two_sided, dtype=np.uint8).tobytes())
    # (The corners read are part of the native object: another corner map replaces it.)
    if obj.corner_map is not None:
        h.update(b"M" + np.ascontiguousarray(obj.corner_map, dtype=np.int64).tobytes())
    local = np.ascontiguousarray(obj.vertices if obj.local_vertices is None else obj.local_vertices,
                                 dtype=np.float64).reshape(-1, 3)
    h.update(str(local.shape).encode())
    for arr in (obj.loop_starts, obj.loop_totals, obj.corner_verts):
        a = np.ascontiguousarray(arr, dtype=np.int32)
        h.update(str(a.shape).encode())
        h.update(a.tobytes())
    return Shape(h.hexdigest(), local.copy())


def shape_digests(scene_input):
    paths = cluster_paths(scene_input)
    return {o.name: shape_digest(o, paths[o.cluster] if o.cluster >= 0 else "")
            for o in scene_input.objects}


MATRIX_TOLERANCE = 1e-7     # a world matrix this close to the one solved has not moved


def relative_move(m, solved, build):
    """None when world matrix `m` is where the solution has the object (`solved`), else `m`
    relative to the placement it was added with (`build`): what Solver.move_object takes."""
    m = np.asarray(m, dtype=np.float64).reshape(4, 4)
    if np.allclose(m, solved, rtol=0.0, atol=MATRIX_TOLERANCE):
        return None
    return np.ascontiguousarray(m @ np.linalg.inv(build))


def is_rigid(m, tol=1e-5):
    """A proper rigid motion (rotation + translation, no scale/shear/mirror)?"""
    m = np.asarray(m, dtype=np.float64)
    if m.shape != (4, 4) or not np.isfinite(m).all():
        return False
    if not np.allclose(m[3], [0, 0, 0, 1], atol=1e-9):
        return False
    r = m[:3, :3]
    return bool(np.allclose(r @ r.T, np.eye(3), atol=tol) and np.linalg.det(r) > 0)


def solver_corner_order(obj):
    """corner_verts in the order handed to the solver (reversed winding for mirrored objects)."""
    if obj.corner_perm is None:
        return obj.corner_verts
    return obj.corner_verts[obj.corner_perm]


def add_native_object(target, obj, cluster_id):
    """Hand one object to a native Scene or Solver (both have add_object); returns its id.

    Native ValueErrors (they name object and polygon) propagate to the caller unchanged.
    """
    extra = {}      # only when not the default: older modules / the stand-in lack them
    if obj.two_sided is not None:
        extra["two_sided"] = np.ascontiguousarray(obj.two_sided, dtype=np.uint8)
    if not obj.occluder:
        extra["occluder"] = False
    if not obj.output:
        extra["output"] = False
    written = written_corners(obj)
    if written is not None:
        extra["written_corners"] = written
    corners = corner_materials(obj)
    if corners[0] is not None:
        extra["corner_reflectance"] = corners[0]
    if corners[1] is not None:
        extra["corner_emission"] = corners[1]
    if obj.texture_pieces is not None:
        extra["pieces"] = native_texture_pieces(obj)
    return target.add_object(
        obj.name, cluster_id,
        np.ascontiguousarray(obj.vertices, dtype=np.float64),
        np.ascontiguousarray(obj.loop_starts, dtype=np.int32),
        np.ascontiguousarray(obj.loop_totals, dtype=np.int32),
        np.ascontiguousarray(solver_corner_order(obj), dtype=np.int32),
        np.ascontiguousarray(obj.reflectance, dtype=np.float32),
        np.ascontiguousarray(obj.emission, dtype=np.float32),
        **extra,
    )


def native_texture_pieces(obj):
    """obj.texture_pieces as the native module takes them (contiguous, clamped), or None."""
    if obj.texture_pieces is None:
        return None
    face, pos, area, rho, emission = obj.texture_pieces
    out = (np.ascontiguousarray(face, dtype=np.int32), np.ascontiguousarray(pos, dtype=np.float64),
           np.ascontiguousarray(np.maximum(area, 0.0), dtype=np.float64),
           np.ascontiguousarray(clamp_reflectance(rho), dtype=np.float64))
    if emission is not None:
        out += (np.ascontiguousarray(clamp_emission(emission), dtype=np.float64),)
    return out


def written_corners(obj):
    """Per corner in the solver's order, 1 where the written mesh reads it (a modifier's corner
    map: the solver gathers only there), as uint8; None when every corner is read."""
    if obj.corner_map is None or not obj.output:
        return None
    mask = np.zeros(obj.corner_count, dtype=np.uint8)
    mask[np.asarray(obj.corner_map, dtype=np.int64)] = 1
    if obj.corner_perm is not None:
        mask = mask[obj.corner_perm]
    return np.ascontiguousarray(mask)


def corner_materials(obj):
    """(corner reflectance, corner emission) in the solver's corner order, float64, or None."""
    out = []
    for arr in (obj.corner_reflectance, obj.corner_emission):
        if arr is not None:
            arr = np.asarray(arr, dtype=np.float64)
            if obj.corner_perm is not None:
                arr = arr[obj.corner_perm]
            arr = np.ascontiguousarray(arr)
        out.append(arr)
    return tuple(out)


def build_native_scene(native, scene_input):
    """Create the native Scene; returns (scene, cluster_ids, object_ids).

    Native ValueErrors (they name object and polygon) propagate to the caller unchanged.
    """
    scene = native.Scene()
    cluster_ids = []
    for c in scene_input.clusters:
        parent = cluster_ids[c.parent] if c.parent >= 0 else -1
        cluster_ids.append(scene.add_cluster(c.name, parent))
    object_ids = []
    for o in scene_input.objects:
        cluster = cluster_ids[o.cluster] if o.cluster >= 0 else -1
        object_ids.append(add_native_object(scene, o, cluster))
    if scene_input.lights:
        from . import lights as core_lights
        for li in scene_input.lights:
            scene.add_light(core_lights.to_native(native, li))
    return scene, cluster_ids, object_ids
