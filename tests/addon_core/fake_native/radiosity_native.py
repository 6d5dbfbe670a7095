"""A slow pure-numpy stand-in for the native module, with the API of radiosity_native.pyi.

For developing and testing the add-on's plumbing before (or without) the C++ build: per-polygon
constant radiosity, form factors by cosine-weighted Monte-Carlo rays. Every ray hits something in
a closed scene, so rows of F sum to exactly 1 and a furnace gives exactly E/(1-rho); anything
else is only roughly right (no corner smoothing). stats()["fake"] is True so tests can tell.
Not shipped in the add-on zip.
"""
import numpy as np

FAKE = True


class Settings:
    def __init__(self):
        self.error_threshold = 0.05
        self.threshold_floor = 1.0
        self.min_area_fraction = 1e-5
        self.max_elements = 2_000_000
        self.max_links = 10_000_000
        self.use_clustering = True
        self.progressive_refinement = True
        self.rays_per_link = 16
        self.max_iterations = 200
        self.tolerance = 1e-5
        self.threads = 0
        self.crease_angle_deg = 35.0
        self.seed = 1

    @staticmethod
    def preset(name):
        rays = {"DRAFT": 64, "MEDIUM": 128, "HIGH": 256}
        if name not in rays:
            raise ValueError(f"unknown preset '{name}'")
        s = Settings()
        s.rays_per_link = rays[name]
        s.error_threshold = {"DRAFT": 0.2, "MEDIUM": 0.1, "HIGH": 0.05}[name]
        return s


class LightType:
    POINT, SPOT, SUN, SKY = "POINT", "SPOT", "SUN", "SKY"


class Light:
    """Plumbing only: the stand-in ignores lights when solving."""
    def __init__(self):
        self.name, self.type = "", LightType.POINT
        self.position, self.direction, self.intensity = (0.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 0.0, 0.0)
        self.radius = self.angle = self.spot_blend = 0.0
        self.spot_size = np.pi
        self.spot_cos_falloff = False
        self.environment = None

    def set_environment(self, radiance):
        self.environment = np.array(radiance, dtype=np.float64)


class Scene:
    def __init__(self):
        self.clusters = []
        self.objects = []
        self.lights = []

    def add_light(self, light):
        if min(light.intensity) < 0:
            raise ValueError(f"light '{light.name}': negative intensity")
        self.lights.append(light)
        return len(self.lights) - 1

    @property
    def light_count(self):
        return len(self.lights)

    def add_cluster(self, name, parent=-1):
        if parent != -1 and not 0 <= parent < len(self.clusters):
            raise ValueError(f"cluster '{name}': bad parent {parent}")
        self.clusters.append((name, parent))
        return len(self.clusters) - 1

    def add_object(self, name, cluster, vertices, loop_starts, loop_totals, corner_verts,
                   reflectance, emission, two_sided=None, occluder=True,
                   corner_reflectance=None, corner_emission=None, pieces=None, output=True,
                   written_corners=None):
        v = np.array(vertices, dtype=np.float64)
        ls = np.array(loop_starts, dtype=np.int64)
        lt = np.array(loop_totals, dtype=np.int64)
        cv = np.array(corner_verts, dtype=np.int64)
        rho = np.array(reflectance, dtype=np.float64)
        em = np.array(emission, dtype=np.float64)
        bad = ~np.isfinite(v).all(axis=1)
        if bad.any():
            raise ValueError(f"object '{name}': vertex {int(np.argmax(bad))} is not finite")
        if len(cv) and (cv.min() < 0 or cv.max() >= len(v)):
            raise ValueError(f"object '{name}': corner index out of range")
        for p in range(len(ls)):
            if lt[p] < 3 or ls[p] < 0 or ls[p] + lt[p] > len(cv):
                raise ValueError(f"object '{name}', polygon {p}: bad loop range")
        badr = ~((rho >= 0) & (rho < 1)).all(axis=1)
        if badr.any():
            raise ValueError(f"object '{name}', polygon {int(np.argmax(badr))}: reflectance "
                             f"outside [0,1)")
        bade = ~((em >= 0) & np.isfinite(em)).all(axis=1)
        if bade.any():
            raise ValueError(f"object '{name}', polygon {int(np.argmax(bade))}: bad emission")
        self.objects.append(dict(name=name, v=v, ls=ls, lt=lt, cv=cv, rho=rho, em=em))
        return len(self.objects) - 1

    @property
    def object_count(self):
        return len(self.objects)

    @property
    def polygon_count(self):
        return sum(len(o["ls"]) for o in self.objects)


def _intersect(orig, dirs, a, e1, e2):
    """Closest hit triangle per ray (Möller-Trumbore, vectorised), -1 on a miss."""
    p = np.cross(dirs[:, None, :], e2[None, :, :])
    det = np.einsum("tk,rtk->rt", e1, p)
    ok = np.abs(det) > 1e-14
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = orig[:, None, :] - a[None, :, :]
    u = np.einsum("rtk,rtk->rt", s, p) * inv
    q = np.cross(s, e1[None, :, :])
    w = np.einsum("rk,rtk->rt", dirs, q) * inv
    t = np.einsum("tk,rtk->rt", e2, q) * inv
    hit = ok & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 1e-9)
    t = np.where(hit, t, np.inf)
    idx = np.argmin(t, axis=1)
    return np.where(np.isfinite(t[np.arange(len(t)), idx]), idx, -1)


class Solver:
    def __init__(self, scene, settings):
        self.scene, self.settings = scene, settings
        self._done = False
        self._cancelled = False
        self._stats = {}
        self._corner = []
        self._incremental = False
        self._base = [o["v"].copy() for o in scene.objects]

    # -- dynamic API: record the change, update() re-solves from scratch (mode "incremental") --
    def set_light(self, index, light):
        self.scene.lights[index] = light

    def corner_irradiance(self, object_id):
        return self.corner_radiance(object_id)

    def leaf_mesh(self, object_id, lighting_only=False):
        """The input polygons themselves (the stand-in has no element hierarchy)."""
        o = self.scene.objects[object_id]
        rad = self.corner_radiance(object_id)
        return {"vertices": o["v"].copy(), "loop_totals": o["lt"].astype(np.int32),
                "corner_verts": o["cv"].astype(np.int32), "values": rad[o["ls"]].astype(np.float32),
                "source_face": np.arange(len(o["ls"]), dtype=np.int32)}

    def add_object(self, name, cluster, vertices, loop_starts, loop_totals, corner_verts,
                   reflectance, emission, two_sided=None, occluder=True,
                   corner_reflectance=None, corner_emission=None, pieces=None, output=True,
                   written_corners=None):
        oid = self.scene.add_object(name, cluster, vertices, loop_starts, loop_totals,
                                    corner_verts, reflectance, emission, two_sided, occluder)
        self._base.append(self.scene.objects[oid]["v"].copy())
        return oid

    def remove_object(self, object_id):
        if not 0 <= object_id < len(self.scene.objects) or self.scene.objects[object_id].get("removed"):
            raise ValueError(f"remove_object: unknown or removed object {object_id}")
        o = self.scene.objects[object_id]
        # An empty slot: ids stay stable, and the solve draws the rays a scene without it draws.
        o.update(removed=True, v=np.zeros((0, 3)), ls=np.zeros(0, np.int64), lt=np.zeros(0, np.int64),
                 cv=np.zeros(0, np.int64), rho=np.zeros((0, 3)), em=np.zeros((0, 3)))
        self._base[object_id] = o["v"]

    def add_cluster(self, name, parent=-1):
        return self.scene.add_cluster(name, parent)

    def move_object(self, object_id, matrix):
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape != (4, 4) or not np.isfinite(m).all():
            raise ValueError("matrix must be a finite 4x4")
        r = m[:3, :3]
        if not np.allclose(r @ r.T, np.eye(3), atol=1e-6) or np.linalg.det(r) < 0:
            raise ValueError(f"object {object_id}: placement is not rigid")
        o = self.scene.objects[object_id]
        o["v"] = self._base[object_id] @ r.T + m[:3, 3]

    def _set(self, object_id, values, key):
        v = np.asarray(values, dtype=np.float64)
        o = self.scene.objects[object_id]
        if v.shape == (3,):
            v = np.tile(v, (len(o["ls"]), 1))
        if v.shape != (len(o["ls"]), 3):
            raise ValueError("values must be (F,3) or (3,)")
        if key == "rho" and not ((v >= 0) & (v < 1)).all():
            raise ValueError(f"object '{o['name']}': reflectance outside [0,1)")
        o[key] = v

    def set_emission(self, object_id, emission):
        self._set(object_id, emission, "em")

    def set_reflectance(self, object_id, reflectance):
        self._set(object_id, reflectance, "rho")

    def set_corner_materials(self, object_id, reflectance=None, emission=None, pieces=None):
        pass    # plumbing only: the stand-in's output ignores per-corner materials

    def update(self):
        # Like the real module, rays count from the last full solve on (cumulative).
        before = int(self._stats.get("rays", 0))
        self._done = False
        self.solve()
        self._stats["rays"] += before
        self._stats.update(mode="incremental", env_env_links_recomputed=0,
                           env_env_links_tested=0, env_env_links_rejected=0,
                           obj_env_links_removed=0, links_created=0, history_reactivated=0,
                           seconds_adjust=0.0)

    def start_update(self):
        self.update()

    def solve(self):
        rng = np.random.default_rng(self.settings.seed)
        tris, tri_poly, polys = [], [], []        # polys: (object, polygon, area, n, rho, em)
        for oi, o in enumerate(self.scene.objects):
            for p in range(len(o["ls"])):
                idx = o["cv"][o["ls"][p]:o["ls"][p] + o["lt"][p]]
                pts = o["v"][idx]
                tri = [(pts[0], pts[k], pts[k + 1]) for k in range(1, len(pts) - 1)]
                areas = [0.5 * np.linalg.norm(np.cross(b - a, c - a)) for a, b, c in tri]
                n = sum(np.cross(b - a, c - a) for a, b, c in tri)
                area = float(sum(areas))
                if area <= 1e-12:
                    polys.append(None)
                    continue
                polys.append((oi, p, tri, np.array(areas) / area, n / np.linalg.norm(n),
                              o["rho"][p], o["em"][p]))
                for t in tri:
                    tris.append(t)
                    tri_poly.append(len(polys) - 1)
        P = len(polys)
        tris = np.array(tris, dtype=np.float64).reshape(-1, 3, 3)
        a, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
        tri_poly = np.array(tri_poly)
        R = int(self.settings.rays_per_link)
        F = np.zeros((P, P))
        rays = 0
        for i, poly in enumerate(polys):
            if poly is None:
                continue
            _, _, tri, w, n, _, _ = poly
            k = rng.choice(len(tri), size=R, p=w)
            r1, r2 = rng.random(R), rng.random(R)
            flip = r1 + r2 > 1
            r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
            T = np.array(tri)[k]
            orig = T[:, 0] + r1[:, None] * (T[:, 1] - T[:, 0]) + r2[:, None] * (T[:, 2] - T[:, 0])
            # cosine-weighted directions around n
            t1 = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
            t1 /= np.linalg.norm(t1)
            t2 = np.cross(n, t1)
            u1, u2 = rng.random(R), rng.random(R)
            rr, phi = np.sqrt(u1), 2 * np.pi * u2
            d = (rr * np.cos(phi))[:, None] * t1 + (rr * np.sin(phi))[:, None] * t2 \
                + np.sqrt(1 - u1)[:, None] * n
            hit = _intersect(orig + 1e-7 * n, d, a, e1, e2)
            rays += R
            for j in tri_poly[hit[hit >= 0]]:
                F[i, j] += 1.0 / R
        rho = np.array([p[5] if p else np.zeros(3) for p in polys])
        E = np.array([p[6] if p else np.zeros(3) for p in polys])
        B = E.copy()
        for _ in range(int(self.settings.max_iterations)):
            nb = E + rho * (F @ B)
            if np.abs(nb - B).max() <= self.settings.tolerance * max(np.abs(nb).max(), 1e-30):
                B = nb
                break
            B = nb
        self._corner = []
        k = 0
        for o in self.scene.objects:
            out = np.zeros((len(o["cv"]), 3), dtype=np.float32)
            for p in range(len(o["ls"])):
                if polys[k] is not None:
                    out[o["ls"][p]:o["ls"][p] + o["lt"][p]] = B[k]
                k += 1
            self._corner.append(out)
        self._stats = {"fake": True,
                       "objects": sum(not o.get("removed") for o in self.scene.objects),
                       "clusters": len(self.scene.clusters),
                       "input_surfaces": self.scene.polygon_count,
                       "elements": sum(p is not None for p in polys),
                       "links": int((F > 0).sum()), "rays": rays,
                       "skipped_polygons": sum(p is None for p in polys), "mode": "full"}
        self._done = True

    def start(self):
        self.solve()

    def running(self):
        return False

    def progress(self):
        return 1.0 if self._done else 0.0

    def cancel(self):
        self._cancelled = True

    def wait(self, timeout=-1.0):
        return True

    def corner_radiance(self, object_id):
        if not self._done:
            raise RuntimeError("not solved")
        return self._corner[object_id]

    def stats(self):
        return dict(self._stats)
