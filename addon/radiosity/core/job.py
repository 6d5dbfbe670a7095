"""Job control around the native solver; the solution a job keeps lives in its scene's session
(core.session), under the job's cache_key.

A SolveJob goes: prepare() (validate, hash, maybe hit the cache, build the native scene) ->
start() (native thread) or run() (synchronous) -> poll()/pump() until finished -> results().
Nothing here touches Blender, so the same object drives the modal operator (polled from a timer),
the background/batch bake (run()) and the headless tests (pump()).
"""
from dataclasses import dataclass, field
import time

import numpy as np

from . import scene_data, session
from .corners import radiance_to_rgba

IDLE, RUNNING, DONE, CANCELLED, FAILED = "IDLE", "RUNNING", "DONE", "CANCELLED", "FAILED"


# Native stats that count work since the last full solve (not per update).
CUMULATIVE_WORK = ("rays", "links_evaluated")


@dataclass
class CachedSolution:
    fingerprint: object      # digest of the solved input; None while an update is pending
    scene: object            # native Scene the solver was built from
    solver: object           # native Solver (kept: the incremental path updates it in place)
    radiance: list           # per SceneInput object: float32 (C,3) in Blender corner order
    native_stats: dict
    clusters: int
    objects: int
    input_surfaces: int
    # -- what the incremental path needs (per object name) --
    settings_key: object = None
    object_ids: dict = field(default_factory=dict)       # name -> native object id
    cluster_ids: dict = field(default_factory=dict)      # cluster path (names from the root) -> native id
    shapes: dict = field(default_factory=dict)           # name -> scene_data.Shape
    build_matrices: dict = field(default_factory=dict)   # name -> world matrix at add_object
    matrices: dict = field(default_factory=dict)         # name -> placement last solved
    reflectance: dict = field(default_factory=dict)      # name -> (F,3) last solved
    emission: dict = field(default_factory=dict)
    corner_materials: dict = field(default_factory=dict)  # name -> (corner rho, corner emission) or Nones
    names: list = field(default_factory=list)            # object order of `radiance`
    lights: list = field(default_factory=list)           # LightInput.key() per native light, last solved
    leaf_meshes: list = None                             # per object: leaf_mesh dict or None
    # name -> {"target", "corner_perm", "corner_map"}: where its colours go (core.preview)
    outputs: dict = field(default_factory=dict)
    in_use: bool = False     # an incremental job owns the solver right now
    bake_stats: dict = None  # stats.summary of the bake that solved `radiance` (the panel)


@dataclass
class _Edit:
    """What an incremental bake hands the kept solver, worked out before it touches it."""
    names: list = field(default_factory=list)           # the objects' names now, in order
    added: list = field(default_factory=list)           # ObjectInput, new since the last bake
    removed: list = field(default_factory=list)         # names gone since
    changed: list = field(default_factory=list)         # names to replace (removed, added anew)
    moves: list = field(default_factory=list)           # (native id, relative move)
    emissions: list = field(default_factory=list)       # (native id, (F,3) float64)
    reflectances: list = field(default_factory=list)    # (native id, (F,3) float64)
    corner_changes: list = field(default_factory=list)  # (native id, ObjectInput): textures
    light_changes: list = field(default_factory=list)   # indices of lights changed in place

    def replaced(self, scene_input):
        """The ObjectInput of each object to replace."""
        by_name = {o.name: o for o in scene_input.objects}
        return [by_name[n] for n in self.changed]

    def empty(self):
        return not (self.moves or self.emissions or self.reflectances or self.corner_changes
                    or self.light_changes or self.added or self.removed or self.changed)


class SolveJob:
    def __init__(self, native, scene_input, settings, settings_key, cache_key=None,
                 use_cache=True):
        self.native = native
        self.scene_input = scene_input
        self.settings = settings
        self.settings_key = settings_key
        self.cache_key = cache_key
        self.use_cache = use_cache
        self.state = IDLE
        self.error = None
        self.cached = None          # CachedSolution when the cache was hit
        self.fingerprint = None
        self.scene = self.solver = None
        self.cluster_ids = self.object_ids = None
        self._radiance = None
        self.shapes = {}
        self.incremental = None     # the CachedSolution being updated in place, if any
        self.changes = {}
        self.full_reason = None
        self._native_stats = None
        self.native_full = False    # the native update solved in full (its warning says why)
        self.update_fallback = None  # ... and why, as the solver's code (stats.FALLBACK_WORDS)
        self._work_before = {}      # cumulative native work counters before an update
        session.track(self)

    # -- setup -------------------------------------------------------------------------------
    def prepare(self):
        """Validate and hash; on a cache hit no native work is needed at all.

        With a kept solution of the same objects, topology and settings, only the changed
        placements and materials are handed to the kept solver (``mode == "incremental"``);
        anything else builds a new native scene (``full_reason`` says why).
        """
        scene_data.validate(self.scene_input)
        self.fingerprint = scene_data.fingerprint(self.scene_input, self.settings_key)
        self.shapes = scene_data.shape_digests(self.scene_input)
        hit = None
        if self.cache_key is not None:
            hit = session.kept(self.cache_key)
        if not self.use_cache:
            self.full_reason = "full bake requested"
        elif hit is None:
            self.full_reason = "no kept solution"
        elif hit.fingerprint is not None and hit.fingerprint == self.fingerprint:
            self.cached = hit
            return self
        else:
            self.full_reason = self._try_incremental(hit)
            if self.full_reason is None:
                return self
        self.scene, self.cluster_ids, self.object_ids = scene_data.build_native_scene(
            self.native, self.scene_input)
        self.solver = self.native.Solver(self.scene, self.settings)
        return self

    # -- incremental ---------------------------------------------------------------------------
    def _try_incremental(self, hit):
        """Queue the changes on the kept solver; returns None, or why a full solve is needed."""
        edit = _Edit()
        # Every change is worked out, and every reason to solve in full found, before the kept
        # solver is touched.
        for step in (self._check_kept, self._find_objects, self._find_edits,
                     self._check_replaced_share, self._find_light_changes):
            why = step(hit, edit)
            if why is not None:
                return why
        if edit.empty() and edit.names == hit.names:
            # Only something that does not affect the solve differs (e.g. which meshes can be
            # written): the kept radiance is still the answer.
            hit.fingerprint = self.fingerprint
            self.cached = hit
            return None
        # From here on the kept solver no longer matches hit.fingerprint.
        hit.fingerprint = None
        try:
            self._apply_edit(hit, edit)
        except ValueError as exc:
            session.forget_kept(self.cache_key)
            return f"the solver refused the change ({exc})"
        self._adopt(hit, edit)
        return None

    def _check_kept(self, hit, edit):
        """Whether the kept solver can be updated for these settings at all."""
        if not hasattr(hit.solver, "update"):
            return "the native module has no dynamic update"
        if hit.in_use:
            return "the kept solution is being updated by another bake"
        if hit.settings_key != self.settings_key:
            return "settings changed"
        return None

    def _find_objects(self, hit, edit):
        """The objects added, removed and replaced since the last bake."""
        edit.names = [o.name for o in self.scene_input.objects]
        if len(edit.names) != len(set(edit.names)):
            return "duplicate object names"
        # Objects added or deleted since the last bake are linked in / taken out by the kept
        # solver (a deletion: hidden, excluded, or gone from the view layer).
        edit.added = [o for o in self.scene_input.objects if o.name not in hit.object_ids]
        edit.removed = sorted(set(hit.object_ids) - set(edit.names))
        can_replace = hasattr(hit.solver, "add_object")
        if (edit.added or edit.removed) and not can_replace:
            parts = []
            if edit.added:
                parts.append("added: " + ", ".join(o.name for o in edit.added))
            if edit.removed:
                parts.append("removed: " + ", ".join(edit.removed))
            return ("objects added or removed since the last bake (" + "; ".join(parts)
                    + "); the native module cannot add or remove objects")
        # An object whose mesh (modifiers included) or collection changed, or that was scaled,
        # sheared or mirrored, is replaced: removed and added again under its name.
        edit.changed = [n for n in edit.names
                        if n in hit.shapes and self.shapes[n] != hit.shapes[n]]
        if edit.changed and not can_replace:
            return ("geometry, modifiers or collection changed: " + ", ".join(edit.changed[:5])
                    + (" …" if len(edit.changed) > 5 else ""))
        return None

    def _find_edits(self, hit, edit):
        """The moves and material changes of the objects kept as they are; an object that was
        not moved rigidly joins the replaced ones."""
        can_replace = hasattr(hit.solver, "add_object")
        for o in self.scene_input.objects:
            if o.name not in hit.object_ids or o.name in edit.changed:
                continue        # added or replaced: given as it is now
            oid = hit.object_ids[o.name]
            rel = scene_data.relative_move(scene_data.object_matrix(o), hit.matrices[o.name],
                                           hit.build_matrices[o.name])
            if rel is not None:
                if not scene_data.is_rigid(rel):
                    if not can_replace:
                        return f"'{o.name}' was scaled, sheared or mirrored (not a rigid move)"
                    edit.changed.append(o.name)
                    continue
                edit.moves.append((oid, rel))
            if not np.array_equal(o.emission, hit.emission[o.name]):
                edit.emissions.append((oid, np.ascontiguousarray(o.emission, dtype=np.float64)))
            if not np.array_equal(o.reflectance, hit.reflectance[o.name]):
                edit.reflectances.append(
                    (oid, np.ascontiguousarray(o.reflectance, dtype=np.float64)))
            # A texture's values at the corners (textures.py): the output's, not the solve's.
            old = hit.corner_materials.get(o.name, (None, None))
            if any((a is None) != (b is None) or (a is not None and not np.array_equal(a, b))
                   for a, b in zip((o.corner_reflectance, o.corner_emission), old)):
                if not hasattr(hit.solver, "set_corner_materials"):
                    return "the native module cannot change textured materials"
                edit.corner_changes.append((oid, o))
        return None

    def _check_replaced_share(self, hit, edit):
        """Replacing most of the scene costs more than solving it afresh."""
        polygons = {o.name: o.polygon_count for o in self.scene_input.objects}
        if (edit.changed
                and 2 * sum(polygons[n] for n in edit.changed) > self.scene_input.polygon_count):
            return ("most of the scene changed shape, collection or scale: "
                    + ", ".join(edit.changed[:5]) + (" …" if len(edit.changed) > 5 else ""))
        return None

    def _find_light_changes(self, hit, edit):
        """Point/spot/sun lights and the world: the same lights (by name and kind, in order)
        are updated in place; any other change of the light list needs a full solve."""
        new_keys = [li.key() for li in self.scene_input.lights]
        if [k[:2] for k in new_keys] != [k[:2] for k in hit.lights]:
            return "lights added, removed or changed type since the last bake"
        edit.light_changes = [i for i, (a, b) in enumerate(zip(new_keys, hit.lights)) if a != b]
        if edit.light_changes and not hasattr(hit.solver, "set_light"):
            return "the native module cannot change lights"
        return None

    def _apply_edit(self, hit, edit):
        """Hands `edit` to the kept solver (which raises ValueError on a change it refuses)."""
        for name in edit.removed + edit.changed:
            hit.solver.remove_object(hit.object_ids[name])
            for d in (hit.object_ids, hit.shapes, hit.build_matrices):
                d.pop(name, None)
        paths = scene_data.cluster_paths(self.scene_input)
        for o in edit.added + edit.replaced(self.scene_input):
            cid = self._native_cluster(hit, o.cluster, paths)
            hit.object_ids[o.name] = scene_data.add_native_object(hit.solver, o, cid)
            hit.shapes[o.name] = self.shapes[o.name]
            # Later moves are relative to the placement it was added with.
            hit.build_matrices[o.name] = scene_data.object_matrix(o)
        for oid, rel in edit.moves:
            hit.solver.move_object(oid, rel)
        for oid, e in edit.emissions:
            hit.solver.set_emission(oid, e)
        for oid, r in edit.reflectances:
            hit.solver.set_reflectance(oid, r)
        for oid, o in edit.corner_changes:
            rho, emission = scene_data.corner_materials(o)
            pieces = scene_data.native_texture_pieces(o)
            if pieces is None:
                hit.solver.set_corner_materials(oid, rho, emission)
            else:
                hit.solver.set_corner_materials(oid, rho, emission, pieces=pieces)
        if edit.light_changes:
            from . import lights as core_lights
            for i in edit.light_changes:
                hit.solver.set_light(i, core_lights.to_native(self.native,
                                                              self.scene_input.lights[i]))

    def _adopt(self, hit, edit):
        """This job now runs the kept solver's update and owns it until it ends."""
        hit.in_use = True
        self.incremental = hit
        self.changes = {"moved": len(edit.moves), "emission_changed": len(edit.emissions),
                        "reflectance_changed": len(edit.reflectances),
                        "texture_changed": len(edit.corner_changes),
                        "lights_changed": len(edit.light_changes),
                        "added": len(edit.added), "removed": len(edit.removed),
                        "replaced": len(edit.changed)}
        self.scene, self.solver = hit.scene, hit.solver
        self.object_ids = [hit.object_ids[n] for n in edit.names]

    def _native_cluster(self, hit, index, paths):
        """Native id of SceneInput cluster `index` in the kept solver (-1: the root), made with
        its parents when the kept solution has no such collection yet."""
        if index < 0:
            return -1
        path = paths[index]
        if path not in hit.cluster_ids:
            c = self.scene_input.clusters[index]
            parent = self._native_cluster(hit, c.parent, paths)
            hit.cluster_ids[path] = hit.solver.add_cluster(c.name, parent)
        return hit.cluster_ids[path]

    def _release(self, ok):
        """End of an incremental job: on failure/cancel the kept solver has no valid solution."""
        hit = self.incremental
        if hit is None:
            return
        hit.in_use = False
        if not ok and self.cache_key is not None and session.kept(self.cache_key) is hit:
            session.forget_kept(self.cache_key)

    @property
    def mode(self):
        return "incremental" if self.incremental is not None and not self.native_full else "full"

    @property
    def is_cached(self):
        return self.cached is not None

    def kept(self):
        """The cache entry that holds this job's result, or None (not kept, or dropped since)."""
        entry = session.kept(self.cache_key) if self.cache_key is not None else None
        if entry is None:
            return None
        if self.cached is not None:
            return entry if entry is self.cached else None
        return entry if entry.radiance is self._radiance else None

    # -- running -------------------------------------------------------------------------------
    def _launch(self, incremental_call, full_call):
        """Calls the native update (kept solution) or full solve; False when cached."""
        if self.cached is not None:
            self.state = DONE
            return False
        self.state = RUNNING
        if self.incremental is not None:
            # The native solver counts rays and link evaluations from its last full solve on;
            # last_stats reports what this update did (see _per_update_work).
            before = self.solver.stats()
            self._work_before = {k: int(before.get(k, 0)) for k in CUMULATIVE_WORK}
        try:
            (incremental_call if self.incremental is not None else full_call)()
        except Exception as exc:
            self.state, self.error = FAILED, exc
            self._release(False)
            raise
        return True

    def run(self):
        """Synchronous solve (background mode, batch, live pump)."""
        if self._launch(lambda: self.solver.update(), lambda: self.solver.solve()):
            self._finish()
        return self

    def start(self):
        """Asynchronous solve on the native thread; poll() from Blender's main thread."""
        self._launch(lambda: self.solver.start_update(), lambda: self.solver.start())
        return self

    def poll(self):
        """Progress 0..1; moves to DONE/FAILED when the native job has ended."""
        if self.state != RUNNING:
            return 1.0 if self.state == DONE else 0.0
        if self.solver.running():
            return float(self.solver.progress())
        self._collect(0.0)
        return 1.0 if self.state == DONE else 0.0

    def pump(self, timeout=None):
        """Block until the job ends (or timeout seconds); True when it finished successfully."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.state == RUNNING:
            remaining = -1.0 if deadline is None else max(0.0, deadline - time.monotonic())
            if self._collect(remaining):
                break
            if deadline is not None and time.monotonic() >= deadline:
                return False
        if self.state == FAILED:
            raise self.error
        return self.state == DONE

    def _collect(self, timeout):
        try:
            finished = self.solver.wait(timeout)
        except Exception as exc:
            self.state, self.error = FAILED, exc
            self._release(False)
            return True
        if finished and self.state == RUNNING:
            self._finish()
        return finished

    def _per_update_work(self, native_stats):
        """Native stats of an incremental job with the work counters of this update only.

        The native counters are cumulative since the kept solver's last full solve (the native
        tests and benches take differences), so an update would otherwise report the rays of
        the first solve plus every update since. When the native update solved in full instead
        (stats "mode" is "full", a warning says why) its counters start from zero already."""
        if self.incremental is None:
            return native_stats
        if native_stats.get("mode") == "full":
            self.native_full = True
            # The code goes into last_stats with full_reason (bake.py), for this job only: a
            # cached rewrite of its colours solves nothing.
            code = self.update_fallback = native_stats.pop("update_fallback", None)
            # The solver's warning for it is its last; a scene dark now or before has none.
            said = native_stats.get("warnings", None) or []
            dark = not said or code in (None, "no_light")
            self.full_reason = "the solver solved in full: " + (
                "the scene has, or had, no light" if dark else said[-1])
            return native_stats
        for key, before in self._work_before.items():
            if key in native_stats:
                total = int(native_stats[key])
                native_stats[key + "_cumulative"] = total
                native_stats[key] = max(total - before, 0)
        return native_stats

    def cancel(self):
        if self.state == RUNNING:
            self.solver.cancel()
            try:
                self.solver.wait(-1.0)
            except Exception as exc:
                # wait() re-raises how the job ended: Cancelled, as asked, or a failure that
                # came first, which is kept like any other for the caller to report.
                if not isinstance(exc, getattr(self.native, "Cancelled", ())):
                    self.error = exc
        if self.state in (RUNNING, IDLE):
            self.state = CANCELLED
            self._release(False)

    def _finish(self):
        # Copy the results out right away so a cache entry never depends on later solver state.
        try:
            self._radiance = []
            self._leaf_meshes = [] if self.scene_input.adaptive_mesh else None
            lighting = self.scene_input.lighting_only
            for obj, oid in zip(self.scene_input.objects, self.object_ids):
                rad = (self.solver.corner_irradiance(oid) if lighting
                       else self.solver.corner_radiance(oid))
                if self._leaf_meshes is not None:
                    self._leaf_meshes.append(
                        self.solver.leaf_mesh(oid, lighting) if obj.target is not None else None)
                rad = rad.astype("float32", copy=True)
                if obj.corner_perm is not None:
                    # Solver order -> Blender order (the permutation is its own inverse).
                    rad = rad[obj.corner_perm]
                self._radiance.append(rad)
            native_stats = self._per_update_work(dict(self.solver.stats()))
        except Exception as exc:
            self.state, self.error = FAILED, exc
            self._release(False)
            raise
        self.state = DONE
        self._native_stats = native_stats
        si = self.scene_input
        hit = self.incremental
        if hit is not None:
            hit.in_use = False
            if self.cache_key is not None and session.kept(self.cache_key) is not hit:
                return      # dropped meanwhile (clear, undo): do not resurrect it
            entry = hit
            entry.radiance = self._radiance
            entry.leaf_meshes = self._leaf_meshes
            entry.native_stats = native_stats
            entry.fingerprint = self.fingerprint
        else:
            if self.cache_key is None:
                return
            entry = CachedSolution(
                self.fingerprint, self.scene, self.solver, self._radiance, native_stats,
                len(si.clusters), len(si.objects), si.polygon_count,
                settings_key=self.settings_key,
                object_ids={o.name: oid for o, oid in zip(si.objects, self.object_ids)},
                cluster_ids=dict(zip(scene_data.cluster_paths(si), self.cluster_ids or [])),
                shapes=dict(self.shapes),
                build_matrices={o.name: scene_data.object_matrix(o) for o in si.objects},
                leaf_meshes=self._leaf_meshes)
        entry.clusters, entry.objects, entry.input_surfaces = \
            len(si.clusters), len(si.objects), si.polygon_count
        entry.names = [o.name for o in si.objects]
        entry.outputs = {o.name: {"target": o.target, "corner_perm": o.corner_perm,
                                  "corner_map": o.corner_map} for o in si.objects}
        entry.lights = [li.key() for li in si.lights]
        entry.matrices = {o.name: scene_data.object_matrix(o) for o in si.objects}
        entry.reflectance = {o.name: np.array(o.reflectance, copy=True) for o in si.objects}
        entry.emission = {o.name: np.array(o.emission, copy=True) for o in si.objects}
        entry.corner_materials = {
            o.name: tuple(None if a is None else np.array(a, copy=True)
                          for a in (o.corner_reflectance, o.corner_emission))
            for o in si.objects}
        if self.cache_key is not None:
            session.keep(self.cache_key, entry)

    # -- results -------------------------------------------------------------------------------
    def radiance(self):
        if self.state != DONE:
            raise RuntimeError(f"job is {self.state}, no results")
        return self.cached.radiance if self.cached is not None else self._radiance

    def rgba(self):
        """[(ObjectInput, flat RGBA)] for every object that has a write target.

        Everything is converted (and checked) before the caller writes a single mesh.
        """
        out = []
        for obj, rad in zip(self.scene_input.objects, self.radiance()):
            if obj.target is not None:
                if len(rad) != obj.corner_count:
                    raise ValueError(f"radiance has {len(rad)} corners, mesh has "
                                     f"{obj.corner_count}")
                out.append((obj, radiance_to_rgba(obj.written_values(rad),
                                                  obj.written_corner_count)))
        return out

    def srgb_bytes(self, exposure):
        """[(ObjectInput, uint8 (C,4))] sRGB byte copies (see core.srgb) for every object with a
        write target, all converted before the caller writes a single mesh."""
        from .srgb import radiance_to_srgb_bytes
        out = []
        for obj, rad in zip(self.scene_input.objects, self.radiance()):
            if obj.target is not None:
                if len(rad) != obj.corner_count:
                    raise ValueError(f"radiance has {len(rad)} corners, mesh has {obj.corner_count}")
                out.append((obj, radiance_to_srgb_bytes(obj.written_values(rad), exposure)))
        return out

    def leaf_meshes(self):
        """Per object the native leaf_mesh dict (adaptive-mesh output), or None."""
        if self.cached is not None:
            return self.cached.leaf_meshes
        return getattr(self, "_leaf_meshes", None)

    def native_stats(self):
        if self.cached is not None:
            return dict(self.cached.native_stats)
        if getattr(self, "_native_stats", None) is not None:
            return dict(self._native_stats)
        return {}

    def fallback_counts(self):
        return {"objects": len(self.scene_input.objects),
                "clusters": len(self.scene_input.clusters),
                "input_surfaces": self.scene_input.polygon_count}
