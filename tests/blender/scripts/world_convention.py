"""The world map's directions (world.py) against Blender's: a world whose colour is its own
direction, an Environment Texture image, and a bake of a cube under a world bright only
toward +X (test_textures_world.py)."""
import math
import sys

import bpy
import numpy as np

import rt_common as rt

rt.setup()
from radiosity import world as world_map  # noqa: E402  (the installed add-on)



def image_world(name, image):
    """A world whose Background colour is `image` as an Environment Texture, nearest texel."""
    w = rt.node_world(name)
    tex = w.node_tree.nodes.new("ShaderNodeTexEnvironment")
    tex.image = image
    tex.interpolation = "Closest"
    w.node_tree.links.new(tex.outputs["Color"], w.node_tree.nodes["Background"].inputs["Color"])
    return w


out = {"ok": True}
# 1. Colour = direction + (1, 1, 1): every map pixel against the native convention
#    (environment.h: phi = pi (1 - 2u), lat = pi (v - 1/2), row 0 at the top).
w = rt.node_world("Direction")
nt = w.node_tree
bg = nt.nodes["Background"]
tc = nt.nodes.new("ShaderNodeTexCoord")
add = nt.nodes.new("ShaderNodeVectorMath")
add.operation = "ADD"
add.inputs[1].default_value = (1.0, 1.0, 1.0)
nt.links.new(tc.outputs["Generated"], add.inputs[0])
nt.links.new(add.outputs[0], bg.inputs["Color"])
env, sun, stats = world_map.render_world(w)
H, W = env.shape[:2]
v = 1.0 - (np.arange(H) + 0.5) / H
u = (np.arange(W) + 0.5) / W
phi = math.pi * (1.0 - 2.0 * u)[None, :]
lat = math.pi * (v - 0.5)[:, None]
expect = np.stack([np.cos(lat) * np.cos(phi), np.cos(lat) * np.sin(phi),
                   np.broadcast_to(np.sin(lat), (H, W))], axis=-1)
err = np.abs(env - 1.0 - expect)
out["direction_err_median"] = float(np.median(err))
out["direction_err_p99"] = float(np.percentile(err, 99))
out["world_seconds"] = stats["world_seconds"]
out["map_shape"] = list(env.shape)

# 2. An Environment Texture image comes back pixel for pixel (same convention as Blender's).
img = bpy.data.images.new("Env", 16, 8, float_buffer=True, alpha=False)
img.colorspace_settings.name = "Non-Color"
px = np.zeros((8, 16, 4), np.float32)
px[..., 0] = np.arange(16)[None, :] + 1.0
px[..., 1] = np.arange(8)[:, None] + 1.0     # Blender rows from the bottom
px[..., 3] = 1.0
img.pixels.foreach_set(px.ravel())
img.pack()
w2 = image_world("Image", img)
env2, _, _ = world_map.render_world(w2)
# Map row 0 is the top: image row (from the bottom) 7 - i // (H / 8); column j // (W / 16).
col = np.floor((np.arange(W) + 0.5) * 16 / W)[None, :] + 1.0
row = 8.0 - np.floor((np.arange(H) + 0.5) * 8 / H)[:, None]
inside = np.ones((H, W), bool)
# Pixels that straddle two image texels (the map is finer) may mix them: judge the others.
inside[:, (np.arange(W) * 16 // W) != ((np.arange(W) + 1) * 16 - 1) // W] = False
out["env_image_match"] = float(np.mean(
    (np.abs(env2[..., 0] - col) < 1e-3)[inside] & (np.abs(env2[..., 1] - row) < 1e-3)[inside]))

# 3. An HDRI whose sun is one texel of a 2048 x 1024 image (0.18 degrees, radiance 4e5, over
#    a sky of 0.5): the map must carry its light (luminance x solid angle) without the noise of
#    the few map samples that hit it.
HW, HH, SI, SJ = 999, 499, 151, 701
hdr = bpy.data.images.new("Hdri", HW, HH, float_buffer=True, alpha=False)
hdr.colorspace_settings.name = "Non-Color"
px = np.full((HH, HW, 4), 0.5, np.float32)
px[..., 3] = 1.0
px[HH - 1 - SI, SJ, :3] = 400000.0      # Blender rows from the bottom
hdr.pixels.foreach_set(px.ravel())
hdr.pack()
w4 = image_world("Hdri", hdr)
env4, _, st4 = world_map.render_world(w4)
lat_e = np.pi * (0.5 - np.arange(HH + 1) / HH)
om_img = 2 * np.pi / HW * (np.sin(lat_e[:-1]) - np.sin(lat_e[1:]))
sun_flux = (400000.0 - 0.5) * om_img[SI]
sky_flux = 0.5 * 4 * np.pi
got = float(world_map._map_flux(env4).sum())
out["hdri_flux_ratio"] = got / (sun_flux + sky_flux)
out["hdri_sun_share"] = sun_flux / (sun_flux + sky_flux)
out["hdri_hot_spots"] = st4["world_hot_spots"]
world_map.HOT_WINDOWS = 0
env5, _, _ = world_map.render_world(w4.copy())
out["hdri_flux_ratio_unrefined"] = float(world_map._map_flux(env5).sum()) / (sun_flux + sky_flux)

# 3. A bake: a white cube on no floor under a world bright toward +X only.

w3 = rt.node_world("HalfX")
nt3 = w3.node_tree
tc3 = nt3.nodes.new("ShaderNodeTexCoord")
sep = nt3.nodes.new("ShaderNodeSeparateXYZ")
gt = nt3.nodes.new("ShaderNodeMath")
gt.operation = "GREATER_THAN"
gt.inputs[1].default_value = 0.0
nt3.links.new(tc3.outputs["Generated"], sep.inputs[0])
nt3.links.new(sep.outputs["X"], gt.inputs[0])
nt3.links.new(gt.outputs[0], nt3.nodes["Background"].inputs["Strength"])
nt3.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
bpy.context.scene.world = w3
verts, faces = rt.box((0, 0, 0), (1, 1, 1))
cube = rt.mesh_object("Cube", verts, faces, None, rt.diffuse_material("White", (0.5, 0.5, 0.5)))
bpy.context.scene.radiosity.preset = "MEDIUM"
ok, err, reports = rt.bake()
out.update(bake_ok=ok, err=err, reports=reports)
if ok:
    c = rt.corner_colors(cube)[:, :3]
    normals = np.array([tuple(p.normal) for p in cube.data.polygons])
    face_of = np.repeat(np.arange(6), 4)
    # +X face sees the bright half: E = pi L -> radiance 0.5; -X sees none of it; +-Y, +-Z half.
    out["faces"] = {str(tuple(int(round(x)) for x in normals[f])): float(c[face_of == f].mean())
                    for f in range(6)}
rt.result(**out)
