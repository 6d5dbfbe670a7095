"""Type stub of the compiled solver module (native/python/module.cpp).

The module is pure numerics: no bpy. Units: radiance (Blender emission colour x strength).
Every array argument is C-contiguous numpy; the module copies what it keeps.
"""
from typing import Optional
import numpy as np

class Settings:
    # Relative error threshold of the refinement oracle (smaller = finer, slower).
    error_threshold: float          # default 0.05
    # Once a solve knows the light, a link's threshold follows its receiver's radiance, down to
    # this fraction of the scene-wide one (1 = scene-wide everywhere; presets: 1 / 0.1 / 0.1).
    threshold_floor: float          # default 1.0
    # Smallest element area as a fraction of the squared scene-bbox diagonal (scale invariant).
    min_area_fraction: float        # default 1e-5
    # Hard caps: refinement stops there and stats()["capped"] says so.
    max_elements: int               # default 2_000_000
    max_links: int                  # default 10_000_000
    use_clustering: bool            # default True
    # The paper's Sec. 3.5 criterion (compare parent form factors with children's sum/average).
    progressive_refinement: bool    # default True
    rays_per_link: int              # visibility rays per surface link, default 16
    max_iterations: int             # gathering iterations cap, default 5000 (stops at the tolerance)
    max_refine_rounds: int          # refine/solve alternations, default 8
    tolerance: float                # estimated remaining relative error to stop iterating
    closure_rays: int               # escape rays per leaf for the closure correction (0 = off)
    threads: int                    # 0 = all cores
    crease_angle_deg: float         # gather_rays = 0 only: corners average across faces within this angle, default 35
    # Final gather at every corner (the point and normal Cycles bakes): rays per output point;
    # 0 = the leaf element's average at the corner (a default-constructed Settings); the presets
    # give DRAFT 64, MEDIUM 512, HIGH 1024.
    gather_rays: int
    gather_min_rays: int            # at least this many rays for every link that reaches a point
    # Shared gathers: a corner within this fraction of a gathered neighbour's reach (its harmonic
    # mean distance to what it sees) takes that neighbour's bounced light and gathers only its
    # lamps and emitting surfaces; 0 = every corner gathers all. DRAFT 0.3, MEDIUM 0.08, HIGH 0.
    gather_share: float
    cycles_corner_points: bool      # corner points where Cycles bakes them (world-space step); False: scale-relative
    seed: int
    def __init__(self) -> None: ...
    @staticmethod
    def preset(name: str) -> "Settings": ...   # 'DRAFT' | 'MEDIUM' | 'HIGH'
    def validate(self) -> None: ...            # ValueError naming the bad field

class Cancelled(Exception):
    """Raised by wait() after cancel(): the job stopped and left no finished solution."""

# Every code stats()["update_fallback"] may hold: why an update solved in full (None: it did not).
update_fallbacks: tuple  # ('scene_size', 'pocket_moved', 'pocket_added_removed', 'no_light')

class LightType:
    """Blender lights that are not surfaces, and the world (native/include/radiosity/lights.h)."""
    POINT: "LightType"
    SPOT: "LightType"
    SUN: "LightType"
    SKY: "LightType"

class Light:
    """One light in Cycles' units after the add-on's conversion (addon/radiosity/core/lights.py):
    POINT/SPOT intensity = radiant intensity W/sr per colour (irradiance I cos / d^2);
    SUN intensity = irradiance W/m^2 on a surface facing it; SKY intensity = world radiance."""
    name: str
    type: LightType
    position: tuple        # world space (POINT, SPOT)
    direction: tuple       # SPOT axis / SUN travel direction (normalised on add)
    radius: float          # POINT, SPOT: emitting disk radius (soft shadows)
    angle: float           # SUN: angular diameter (radians)
    spot_size: float       # SPOT: full cone angle (radians)
    spot_blend: float      # SPOT: [0, 1]
    spot_cos_falloff: bool # SPOT: also x cos to the axis (Cycles before Blender 4.0)
    intensity: tuple       # RGB >= 0
    def __init__(self) -> None: ...
    def validate(self) -> None: ...   # ValueError naming the light
    def set_environment(self, radiance: np.ndarray) -> None:
        """SKY only: float (H, W, 3) equirectangular radiance (row 0 at the top, Blender's
        Environment Texture convention; environment.h), a factor to intensity. ValueError for
        a negative or non-finite texel."""
    @property
    def has_environment(self) -> bool: ...

class Scene:
    def __init__(self) -> None: ...
    def add_light(self, light: Light) -> int:
        """Direct light at every element with shadow rays, then bouncing. ValueError on bad input."""
    @property
    def light_count(self) -> int: ...
    def add_cluster(self, name: str, parent: int = -1) -> int:
        """A cluster (Blender collection). parent=-1: the root. Returns its id."""
    def add_object(self, name: str, cluster: int,
                   vertices: np.ndarray,      # float64 (V,3), world space
                   loop_starts: np.ndarray,   # int32 (F,)  Blender polygon.loop_start
                   loop_totals: np.ndarray,   # int32 (F,)  Blender polygon.loop_total (>=3; n-gons fan-split natively)
                   corner_verts: np.ndarray,  # int32 (C,)  Blender loop.vertex_index
                   reflectance: np.ndarray,   # float32 (F,3) in [0,1)
                   emission: np.ndarray,      # float32 (F,3) radiance >= 0
                   two_sided: Optional[np.ndarray] = None,  # bool (F,), default all True
                   occluder: bool = True,      # False: casts no shadow (area lights, as in Cycles)
                   # (C,3) per corner, output only (corner = emission + reflectance x irradiance
                   # there); None: the polygon's values (textured materials, textures.py)
                   corner_reflectance: Optional[np.ndarray] = None,
                   corner_emission: Optional[np.ndarray] = None,
                   # A texture inside polygons, for the transport: (face int32 (P,), world
                   # position float64 (P,3), area float64 (P,), reflectance (P,3) in [0,1)
                   # [, emission (P,3) >= 0]); elements take the area mean of the pieces inside
                   # them. None: uniform polygons.
                   pieces: Optional[tuple] = None,
                   # False: its colours are not read (an instance, an area light): no final
                   # gather at its corners, which read the leaves; it still lights the rest.
                   output: bool = True,
                   # uint8 (C,) in the solver's corner order: 1 where the corner's colour is read
                   # (a modifier's corner map); the others get no gather point and read the
                   # leaves. None: every corner.
                   written_corners: Optional[np.ndarray] = None,
                   ) -> int:
        """A rigid object. cluster=-1: a surface set by itself (object directly in the scene).
        Raises ValueError naming the object and polygon on NaN/inf, bad indices, rho outside [0,1),
        negative emission. Zero-area polygons are skipped (stats()['skipped_polygons'])."""
    @property
    def object_count(self) -> int: ...
    @property
    def polygon_count(self) -> int: ...

class Solver:
    def __init__(self, scene: Scene, settings: Settings) -> None: ...
    # Synchronous full solve; releases the GIL.
    def solve(self) -> None: ...
    # Asynchronous job on a native thread (poll from Blender's main thread).
    def start(self) -> None: ...
    def running(self) -> bool: ...
    def progress(self) -> float: ...          # 0..1
    def cancel(self) -> None: ...              # the job stops soon; results are not updated
    def wait(self, timeout: float = -1.0) -> bool: ...  # True when finished; re-raises a job error
    # Dynamic environments: record changes, then update()/start_update() (incremental re-solve;
    # stats()['mode'] == 'incremental'). A cancelled update leaves no finished solution.
    # matrix: float64 (4,4) row-major rigid placement relative to the geometry given to
    # add_object (world space); ValueError if not rigid (scale/shear/mirror) or not finite.
    def move_object(self, object_id: int, matrix: np.ndarray) -> None: ...
    def set_emission(self, object_id: int, emission: np.ndarray) -> None: ...      # (F,3) or (3,)
    def set_reflectance(self, object_id: int, reflectance: np.ndarray) -> None: ...  # each < 1
    def update(self) -> None: ...              # synchronous; releases the GIL
    def start_update(self) -> None: ...        # asynchronous; poll like start()
    # Results (after a finished solve).
    def corner_radiance(self, object_id: int) -> np.ndarray:  # float32 (C,3), per Blender corner
        ...
    def corner_irradiance(self, object_id: int) -> np.ndarray:
        """float32 (C,3): irradiance / pi arriving at the front side per corner ("lighting only":
        what a white diffuse surface would reflect; own emission and reflectance left out)."""
    def leaf_mesh(self, object_id: int, lighting_only: bool = False) -> dict:
        """The object's front-side leaf elements as a T-vertex free mesh: 'vertices' float64 (V,3)
        world, 'loop_totals' int32 (F,), 'corner_verts' int32 (C,), 'values' float32 (F,3) radiance
        (or irradiance / pi), 'source_face' int32 (F,) the input polygon each subdivides."""
    def set_light(self, index: int, light: Light) -> None: ...   # then update(): incremental
    # Objects added and removed after a solve, applied by the next update() (incremental: the
    # new object is linked in, a removed one's links and nodes go). Ids stay stable: add_object
    # returns the next id, a removed id keeps an empty slot (corner_radiance gives (0,3)).
    def add_object(self, name: str, cluster: int, vertices: np.ndarray, loop_starts: np.ndarray,
                   loop_totals: np.ndarray, corner_verts: np.ndarray, reflectance: np.ndarray,
                   emission: np.ndarray, two_sided: Optional[np.ndarray] = None,
                   occluder: bool = True, corner_reflectance: Optional[np.ndarray] = None,
                   corner_emission: Optional[np.ndarray] = None, pieces: Optional[tuple] = None,
                   output: bool = True, written_corners: Optional[np.ndarray] = None) -> int:
        """As Scene.add_object (world space, placed as given: later moves are relative to it).
        ValueError naming the object and polygon for bad input."""
    def remove_object(self, object_id: int) -> None: ...  # ValueError: unknown id, removed already
    def add_cluster(self, name: str, parent: int = -1) -> int: ...  # a collection for added objects
    def radiance_at(self, object_id: int, face: int, point: tuple) -> tuple: ...  # front-side radiance of the leaf at a world point
    def stats(self) -> dict: ...  # counts and seconds (native/include/radiosity/stats.h) plus 'mode': 'full' | 'incremental'
    # ... and 'update_fallback': one of update_fallbacks when an update solved in full, else None
    # Dynamic environments (AdjustSystem). Record changes, then update() / start_update().
    def move_object(self, object_id: int, matrix: np.ndarray) -> None:
        """Rigid placement (float64 4x4, row-major, world units) relative to the geometry given to
        add_object. ValueError for NaN, scale/shear or mirroring; RuntimeError before a solve."""
    def set_emission(self, object_id: int, emission: np.ndarray) -> None: ...      # (F,3) or (3,)
    def set_reflectance(self, object_id: int, reflectance: np.ndarray) -> None: ... # (F,3) or (3,), < 1
    def set_corner_materials(self, object_id: int, reflectance: Optional[np.ndarray] = None,
                             emission: Optional[np.ndarray] = None, pieces: Optional[tuple] = None) -> None:
        """(C,3) per corner or None: the output's (no update() needed); pieces as add_object's
        (None: none): the transport's, taken by the next update()."""
    def update(self) -> None: ...        # incremental re-solve (full solve if none is kept); GIL released
    def start_update(self) -> None: ...  # the same as a job: poll like start()
