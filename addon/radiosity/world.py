"""The world as Cycles renders it: an equirectangular radiance map, and the sun disc of a Sky
Texture as a sun light of its own.

A world whose Background is driven by nodes (Sky Texture, an HDRI Environment Texture, any
tree) is rendered by Cycles with a panoramic (equirectangular) camera in a temporary scene that
uses a copy of the world; scene, camera, world copy, image and file are deleted before
returning. Each pixel is the mean radiance over its patch of directions (a one-pixel box
filter), so the map preserves energy; the camera is turned so that the map's pixel (i, j) is
the pixel (i, j) of an Environment Texture's image (Blender's convention, checked by
tests/blender/test_textures_world.py), which is the native solver's (environment.h).

A Sky Texture's sun disc (about half a degree) is far smaller than a map pixel: sampled in
the map, its energy would fall on a pixel or two with the noise of few samples. So the map is
rendered with the disc off, and the disc becomes a sun light: its direction and irradiance are
measured by rendering a small window of directions around it with the disc on and off (the
difference is the disc alone, whatever the nodes after the Sky Texture do to it), and its
angular diameter is the node's sun size.

Any other small bright spot (an HDRI's sun) falls inside a pixel that few map samples hit, so
its energy is the luck of those samples: the pixels that carry the most light are rendered
again in small windows, 16 x 16 times finer (_refine_hot_spots; docs/decisions.md, "Reference
and materials").

Limits: a spot the map's samples miss altogether is missed (a real sun, half a degree wide,
is hit several times; a spot under about a fifth of a degree may not be);
the world is seen by camera rays (a Light Path node that tells camera rays from diffuse
ones gives the camera's answer); a sun disc inside a node group is not found (it stays in the
map, with the map's resolution).
"""
import math
import os
import shutil
import tempfile
import time

import bpy
import numpy as np

from . import eval_cache
from .core import lights as core_lights

MAP_WIDTH, MAP_HEIGHT = 512, 256
MAP_SAMPLES = 16
SUN_PIXELS = 64             # the sun window's side in pixels
SUN_SAMPLES = 16
# Hot spots (_refine_hot_spots): a pixel carrying HOT_FRACTION of the map's light or more.
HOT_FRACTION = 0.002
HOT_WINDOWS = 4
HOT_SUB = 16
HOT_SAMPLES = 16


def _pano_settings(cam_data):
    """The object that holds the panorama settings (3.x: cycles properties; 4.x: the camera)."""
    return cam_data if hasattr(cam_data, "panorama_type") else cam_data.cycles


def _disable_world_importance(world):
    c = world.cycles
    if hasattr(c, "sampling_method"):
        c.sampling_method = "NONE"
    elif hasattr(c, "sample_as_light"):
        c.sample_as_light = False


class _Renderer:
    """A temporary scene with a panoramic camera looking at a world."""

    def __init__(self, world):
        self.dir = tempfile.mkdtemp(prefix="radiosity_world_")
        # A render makes Blender's "Render Result" image if there is none: ours goes again.
        self.results_before = {i.name_full for i in bpy.data.images if i.type == "RENDER_RESULT"}
        self.scene = bpy.data.scenes.new("radiosity_world_tmp")
        self.world = world
        self.scene.world = world
        self.cam_data = bpy.data.cameras.new("radiosity_world_tmp")
        self.cam_data.type = "PANO"
        _pano_settings(self.cam_data).panorama_type = "EQUIRECTANGULAR"
        self.cam = bpy.data.objects.new("radiosity_world_tmp", self.cam_data)
        self.scene.collection.objects.link(self.cam)
        self.scene.camera = self.cam
        # Turned so that the render's pixel (i, j) is an Environment Texture's pixel (i, j).
        self.cam.rotation_euler = (math.pi / 2, 0.0, -math.pi / 2)
        sc = self.scene
        sc.render.engine = "CYCLES"
        sc.render.resolution_percentage = 100
        sc.render.film_transparent = False
        sc.render.use_compositing = False
        sc.render.use_sequencer = False
        sc.render.image_settings.file_format = "OPEN_EXR"
        sc.render.image_settings.color_depth = "32"
        sc.view_settings.view_transform = "Standard"
        c = sc.cycles
        c.device = "CPU"
        c.use_adaptive_sampling = False
        c.use_denoising = False
        c.seed = 0
        c.pixel_filter_type = "BOX"
        c.filter_width = 1.0
        self.count = 0

    def render(self, width, height, samples, lon=(-math.pi, math.pi), lat=(-math.pi / 2, math.pi / 2)):
        """Mean radiance per pixel, (height, width, 3), row 0 at the top (largest latitude).
        `lon` is the camera's longitude range: world azimuth atan2(y, x) = -longitude."""
        sc = self.scene
        p = _pano_settings(self.cam_data)
        p.longitude_min, p.longitude_max = lon
        p.latitude_min, p.latitude_max = lat
        sc.render.resolution_x, sc.render.resolution_y = width, height
        sc.cycles.samples = samples
        self.count += 1
        path = os.path.join(self.dir, f"world{self.count}.exr")
        sc.render.filepath = path
        with bpy.context.temp_override(scene=sc):
            bpy.ops.render.render(write_still=True, scene=sc.name)
        img = bpy.data.images.load(path)
        try:
            w, h = img.size
            px = np.empty(w * h * img.channels, dtype=np.float32)
            img.pixels.foreach_get(px)
            px = px.reshape(h, w, img.channels)[::-1, :, :3]
        finally:
            bpy.data.images.remove(img)
        return np.ascontiguousarray(px, dtype=np.float64)

    def close(self):
        for img in [i for i in bpy.data.images if i.type == "RENDER_RESULT"
                    and i.name_full not in self.results_before]:
            bpy.data.images.remove(img)
        bpy.data.objects.remove(self.cam, do_unlink=True)
        bpy.data.cameras.remove(self.cam_data, do_unlink=True)
        bpy.data.scenes.remove(self.scene, do_unlink=True)
        shutil.rmtree(self.dir, ignore_errors=True)


def _sky_nodes_with_sun(tree):
    return [n for n in tree.nodes if n.bl_idname == "ShaderNodeTexSky"
            and getattr(n, "sun_disc", False) and not getattr(n, "mute", False)]


def _nishita_sun_direction(node):
    """Where Cycles puts the sun of a Sky Texture (elevation above the horizon, rotation about
    +Z from +Y toward +X; found by rendering, Blender 3.4); the window render measures it."""
    el, rot = float(node.sun_elevation), float(node.sun_rotation)
    return np.array([math.cos(el) * math.sin(rot), math.cos(el) * math.cos(rot), math.sin(el)])


def _window(direction, half):
    """(lon, lat) ranges of a window of half-width `half` (radians) around a direction."""
    d = direction / np.linalg.norm(direction)
    lat = math.asin(max(-1.0, min(1.0, float(d[2]))))
    phi = math.atan2(float(d[1]), float(d[0]))
    lat_rng = (max(-math.pi / 2, lat - half), min(math.pi / 2, lat + half))
    c = math.cos(min(abs(lat) + half, math.pi / 2))
    if c < 0.2:
        lon_rng = (-math.pi, math.pi)           # near a pole: the whole ring
    else:
        dl = min(math.pi, half / c)
        lon_rng = (-phi - dl, -phi + dl)
    return lon_rng, lat_rng


def _window_geometry(lon_rng, lat_rng, width, height):
    """Per pixel of a window render: its direction (h, w, 3) and solid angle (h, w)."""
    lat_edges = np.linspace(lat_rng[1], lat_rng[0], height + 1)
    lon_edges = np.linspace(lon_rng[0], lon_rng[1], width + 1)
    omega_row = (lon_edges[1] - lon_edges[0]) * (np.sin(lat_edges[:-1]) - np.sin(lat_edges[1:]))
    lat_c = 0.5 * (lat_edges[:-1] + lat_edges[1:])
    phi_c = -0.5 * (lon_edges[:-1] + lon_edges[1:])
    cl = np.cos(lat_c)[:, None]
    dirs = np.stack([cl * np.cos(phi_c)[None, :], cl * np.sin(phi_c)[None, :],
                     np.broadcast_to(np.sin(lat_c)[:, None], (height, width))], axis=-1)
    return dirs, np.broadcast_to(omega_row[:, None], (height, width))


def _measure_sun(renderer, nodes, world_name):
    """The sun discs of `nodes` (switched on for the measurement, off again after) as one sun
    light: irradiance at normal incidence, direction, angular diameter."""
    guess = _nishita_sun_direction(nodes[0])
    size = max(float(getattr(nodes[0], "sun_size", 0.01)), 1e-4)
    half = max(2.0 * size, math.radians(1.0))

    def disc_in(lon_rng, lat_rng, width, height):
        for n in nodes:
            n.sun_disc = True
        on = renderer.render(width, height, SUN_SAMPLES, lon_rng, lat_rng)
        for n in nodes:
            n.sun_disc = False
        off = renderer.render(width, height, SUN_SAMPLES, lon_rng, lat_rng)
        return np.maximum(on - off, 0.0)

    lon_rng, lat_rng = _window(guess, half)
    disc = disc_in(lon_rng, lat_rng, SUN_PIXELS, SUN_PIXELS)
    if disc.max() <= 0.0:
        # Not where the guess put it (another sky model?): look along the whole ring of its
        # elevation, then measure around what is found there.
        el = math.asin(float(guess[2]))
        ring = (max(-math.pi / 2, el - 2 * half), min(math.pi / 2, el + 2 * half))
        full = (-math.pi, math.pi)
        width = int(min(8192, max(512, 4 * math.pi / size)))
        found = disc_in(full, ring, width, 16)
        if found.max() <= 0.0:
            return None     # below the horizon, or a disc of no light
        dirs, _ = _window_geometry(full, ring, width, 16)
        i, j = np.unravel_index(int(np.argmax(found.mean(axis=-1))), found.shape[:2])
        lon_rng, lat_rng = _window(dirs[i, j], half)
        disc = disc_in(lon_rng, lat_rng, SUN_PIXELS, SUN_PIXELS)
    dirs, omega = _window_geometry(lon_rng, lat_rng, SUN_PIXELS, SUN_PIXELS)
    flux = (disc * omega[..., None]).reshape(-1, 3).sum(axis=0)   # irradiance facing the sun
    if flux.max() <= 0.0:
        return None
    w = (disc.mean(axis=-1) * omega).reshape(-1)
    centre = (dirs.reshape(-1, 3) * w[:, None]).sum(axis=0)
    centre /= np.linalg.norm(centre)
    return core_lights.LightInput(
        f"{world_name} (sun disc)", core_lights.SUN, tuple(float(x) for x in flux),
        direction=tuple(float(-x) for x in centre), angle=size)


def _map_flux(env):
    """Per pixel of a full map: mean radiance (channel mean) x solid angle."""
    h, w = env.shape[:2]
    lat = np.pi * (0.5 - np.arange(h + 1) / h)
    omega = 2 * np.pi / w * (np.sin(lat[:-1]) - np.sin(lat[1:]))
    return env.mean(axis=-1) * omega[:, None]


def _refine_hot_spots(renderer, env):
    """Pixels that carry much of the map's light (an HDRI's sun: a fraction of a pixel, hit by
    a few of its samples, so its energy is noise) are rendered again, each with its 8
    neighbours, HOT_SUB x HOT_SUB times finer and averaged back: energy-exact to the window's
    many samples. Returns how many windows were rendered."""
    h, w = env.shape[:2]
    flux = _map_flux(env)
    total = float(flux.sum())
    if total <= 0.0:
        return 0
    done = np.zeros((h, w), bool)
    windows = 0
    for idx in np.argsort(flux, axis=None)[::-1][:4 * HOT_WINDOWS]:
        i, j = np.unravel_index(int(idx), (h, w))
        if flux[i, j] < HOT_FRACTION * total or windows >= HOT_WINDOWS:
            break
        if done[i, j]:
            continue
        i0, j0 = int(np.clip(i - 1, 0, h - 3)), int(np.clip(j - 1, 0, w - 3))
        lon = (np.pi * (2.0 * j0 / w - 1.0), np.pi * (2.0 * (j0 + 3) / w - 1.0))
        lat = (np.pi * (0.5 - (i0 + 3) / h), np.pi * (0.5 - i0 / h))
        fine = renderer.render(3 * HOT_SUB, 3 * HOT_SUB, HOT_SAMPLES, lon, lat)
        env[i0:i0 + 3, j0:j0 + 3] = fine.reshape(3, HOT_SUB, 3, HOT_SUB, 3).mean(axis=(1, 3))
        done[i0:i0 + 3, j0:j0 + 3] = True
        windows += 1
    return windows


def render_world(world):
    """(map (H, W, 3) float32, sun LightInput or None, stats) of a world with a node tree. The
    result is kept (eval_cache.py): the same world is not rendered again (a live re-bake)."""
    t0 = time.perf_counter()
    key = (f"W|{world.name_full}|{eval_cache.tree_key(world.node_tree)}|{tuple(world.color)}|"
           f"{MAP_WIDTH}x{MAP_HEIGHT}x{MAP_SAMPLES}|{bpy.app.version_string}")
    hit = eval_cache.get(key)
    if hit is not None:
        env, sun, stats = hit
        return env, sun, dict(stats, world_cached=True,
                              world_seconds=round(time.perf_counter() - t0, 4))
    copy = world.copy()
    renderer = None
    try:
        _disable_world_importance(copy)
        renderer = _Renderer(copy)
        nodes = _sky_nodes_with_sun(copy.node_tree) if copy.node_tree is not None else []
        sun = _measure_sun(renderer, nodes, world.name) if nodes else None
        for n in nodes:
            n.sun_disc = False
        env = renderer.render(MAP_WIDTH, MAP_HEIGHT, MAP_SAMPLES)
        hot = _refine_hot_spots(renderer, env)
    finally:
        if renderer is not None:
            renderer.close()
        bpy.data.worlds.remove(copy, do_unlink=True)
    env = np.maximum(np.nan_to_num(env, nan=0.0, posinf=0.0), 0.0).astype(np.float32)
    stats = {"world_map": [MAP_WIDTH, MAP_HEIGHT], "world_sun": sun is not None,
             "world_hot_spots": hot,
             "world_seconds": round(time.perf_counter() - t0, 4)}
    eval_cache.put(key, (env, sun, stats))
    return env, sun, stats
