"""Build the example scenes from code and save them as .blend files.

    blender -b --factory-startup --python example_blends/make_examples.py -- [--out DIR] [--only NAME ...]

Writes box_room.blend, chair_room.blend, full_room.blend, cornell_box.blend and furnace.blend
(default: next to this script). Run it with the oldest Blender we support (3.4) so every newer
Blender opens the files. See README.md in this folder for what each scene is.

Conventions (the README explains why):
- An *input surface* is one planar polygon as a modeller would draw it (a floor, one face of a
  box) before it is cut into a grid of quads for vertex-colour detail. Every polygon carries the
  index of its input surface in the INT face attribute "radiosity_surface" (per object), each
  object its count in obj["radiosity_input_surfaces"], the scene the total in
  scene["radiosity_input_surfaces"].
- An *object* (the paper's dynamic object; the solver's cluster) is a mesh in a collection of its
  own. The room's surfaces and the light are meshes directly in the scene collection: the static
  environment, not objects. scene["radiosity_input_objects"] holds the count.
- Materials are node trees Cycles bakes exactly as the pure diffuse model: Diffuse BSDF
  (roughness 0 = Lambert) for reflectors, Emission for lights (a light reflects nothing), Add
  Shader(Diffuse, Emission) where a surface both reflects and emits (the furnace).
"""
import math
import os
import sys

import bpy
from mathutils import Euler, Matrix, Vector

HERE = os.path.dirname(os.path.abspath(__file__))

# --------------------------------------------------------------------------- geometry helpers


def v(*a):
    return Vector(a)


def newell_normal(pts):
    n = Vector((0.0, 0.0, 0.0))
    for i, p in enumerate(pts):
        q = pts[(i + 1) % len(pts)]
        n.x += (p.y - q.y) * (p.z + q.z)
        n.y += (p.z - q.z) * (p.x + q.x)
        n.z += (p.x - q.x) * (p.y + q.y)
    return n


class Surface:
    """One input surface: a planar convex polygon plus which side its normal faces."""

    def __init__(self, corners, material, toward=None, away_from=None, normal=None):
        pts = [Vector(c) for c in corners]
        centroid = sum(pts, Vector()) / len(pts)
        if normal is not None:
            want = Vector(normal)
        elif toward is not None:
            want = Vector(toward) - centroid
        else:
            want = centroid - Vector(away_from)
        if newell_normal(pts).dot(want) < 0.0:
            pts.reverse()
        self.corners = pts
        self.material = material
        self.normal = want


def box_surfaces(lo, hi, material, inward=False):
    """The 6 faces of an axis-aligned box; normals outward (or inward for a room)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    c = (Vector(lo) + Vector(hi)) / 2
    quads = [
        [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],  # bottom
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # top
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # -y
        [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],  # +y
        [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)],  # -x
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # +x
    ]
    if inward:
        return [Surface(q, material, toward=c) for q in quads]
    return [Surface(q, material, away_from=c) for q in quads]


def prism_surfaces(outline, z0, z1, material):
    """A vertical prism over a convex XY outline: top, bottom and one side per edge."""
    n = len(outline)
    bot = [(x, y, z0) for x, y in outline]
    top = [(x, y, z1) for x, y in outline]
    c = sum((Vector(p) for p in bot + top), Vector()) / (2 * n)
    out = [Surface(top, material, away_from=c), Surface(bot, material, away_from=c)]
    for i in range(n):
        j = (i + 1) % n
        out.append(Surface([bot[i], bot[j], top[j], top[i]], material, away_from=c))
    return out


def subdivide(surface, target):
    """Cut a surface into quads of about `target` edge length. Returns (points, polygons)."""
    pts = surface.corners
    if len(pts) == 4:
        p0, p1, p2, p3 = pts
        nu = max(1, min(64, round(max((p1 - p0).length, (p2 - p3).length) / target)))
        nv = max(1, min(64, round(max((p3 - p0).length, (p2 - p1).length) / target)))
        verts = []
        for j in range(nv + 1):
            t = j / nv
            for i in range(nu + 1):
                s = i / nu
                verts.append((p0 * (1 - s) + p1 * s) * (1 - t) + (p3 * (1 - s) + p2 * s) * t)
        polys = []
        for j in range(nv):
            for i in range(nu):
                a = j * (nu + 1) + i
                polys.append([a, a + 1, a + nu + 2, a + nu + 1])
        return verts, polys
    # Other convex polygons: rings of scaled copies of the outline, a fan at the centre.
    n = len(pts)
    per_edge = [max(1, round((pts[(i + 1) % n] - pts[i]).length / target)) for i in range(n)]
    boundary = []
    for i in range(n):
        a, b = pts[i], pts[(i + 1) % n]
        for k in range(per_edge[i]):
            boundary.append(a.lerp(b, k / per_edge[i]))
    c = sum(pts, Vector()) / n
    rings = max(1, round(max((p - c).length for p in pts) / target))
    m = len(boundary)
    verts = [c]
    for r in range(1, rings + 1):
        f = r / rings
        verts.extend(c + (p - c) * f for p in boundary)
    polys = []
    for i in range(m):
        polys.append([0, 1 + i, 1 + (i + 1) % m])
    for r in range(1, rings):
        inner, outer = 1 + (r - 1) * m, 1 + r * m
        for i in range(m):
            k = (i + 1) % m
            polys.append([inner + i, outer + i, outer + k, inner + k])
    return verts, polys


# --------------------------------------------------------------------------- Blender helpers


def node_material(name):
    """A new material whose node tree holds only its output node; the caller adds the shader."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    return mat, nt, nt.nodes.new("ShaderNodeOutputMaterial")


def lambert_node(nt, rgb, location):
    """A Diffuse BSDF node of reflectance `rgb` with roughness 0: the pure Lambert model."""
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    bsdf.location = location
    return bsdf


def diffuse_material(name, rgb):
    mat, nt, out = node_material(name)
    bsdf = lambert_node(nt, rgb, (-250, 0))
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    mat.diffuse_color = (*rgb, 1.0)
    return mat


def emission_material(name, radiance, reflectance=None):
    """Emission colour x strength = radiance. With `reflectance`, the surface also reflects."""
    strength = max(radiance)
    color = tuple(c / strength for c in radiance)
    mat, nt, out = node_material(name)
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (*color, 1.0)
    em.inputs["Strength"].default_value = strength
    em.location = (-250, -150)
    if reflectance is None:
        nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
        mat.diffuse_color = (*color, 1.0)
    else:
        bsdf = lambert_node(nt, reflectance, (-250, 100))
        add = nt.nodes.new("ShaderNodeAddShader")
        add.location = (-50, 0)
        nt.links.new(bsdf.outputs["BSDF"], add.inputs[0])
        nt.links.new(em.outputs["Emission"], add.inputs[1])
        nt.links.new(add.outputs["Shader"], out.inputs["Surface"])
        mat.diffuse_color = (*reflectance, 1.0)
    return mat


def make_object(name, surfaces, target, collection, origin=(0, 0, 0), rotation_z_deg=0.0):
    """A mesh object from world-space surfaces (as placed at `origin`, rotated `rotation_z_deg`)."""
    origin = Vector(origin)
    to_local = (Matrix.Translation(origin) @ Euler((0, 0, math.radians(rotation_z_deg))).to_matrix().to_4x4()).inverted()
    mats = []
    verts, polys, mat_idx, surf_idx = [], [], [], []
    for s_i, s in enumerate(surfaces):
        if s.material not in mats:
            mats.append(s.material)
        pv, pp = subdivide(s, target)
        base = len(verts)
        verts.extend(to_local @ p for p in pv)
        for poly in pp:
            polys.append([base + k for k in poly])
            mat_idx.append(mats.index(s.material))
            surf_idx.append(s_i)
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(p) for p in verts], [], polys)
    for m in mats:
        me.materials.append(m)
    me.polygons.foreach_set("material_index", mat_idx)
    attr = me.attributes.new("radiosity_surface", "INT", "FACE")
    attr.data.foreach_set("value", surf_idx)
    me.update()
    assert me.validate(verbose=True) is False, name
    ob = bpy.data.objects.new(name, me)
    ob.location = origin
    ob.rotation_euler = (0.0, 0.0, math.radians(rotation_z_deg))
    ob["radiosity_input_surfaces"] = len(surfaces)
    collection.objects.link(ob)
    # The grid's winding must agree with each surface's intended side.
    for p in me.polygons:
        want = to_local.inverted().to_3x3() @ p.normal
        s = surfaces[surf_idx[p.index]]
        assert want.dot(s.normal) > 0, (name, p.index)
    return ob


def object_collection(scene, name):
    coll = bpy.data.collections.new(name)
    scene.collection.children.link(coll)
    return coll


def new_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    for coll in list(bpy.data.collections):
        bpy.data.collections.remove(coll)
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = 256
    cy.preview_samples = 32
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.use_preview_denoising = False
    cy.max_bounces = 64
    cy.diffuse_bounces = 64
    cy.glossy_bounces = 0
    cy.transmission_bounces = 0
    cy.volume_bounces = 0
    cy.transparent_max_bounces = 8
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.caustics_reflective = False
    cy.caustics_refractive = False
    scene.render.bake.target = "VERTEX_COLORS"
    scene.render.resolution_x = 800
    scene.render.resolution_y = 600
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.display_settings.display_device = "sRGB"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    world = bpy.data.worlds.new("World") if not bpy.data.worlds else bpy.data.worlds[0]
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    if bg is None:
        world.node_tree.nodes.clear()
        out = world.node_tree.nodes.new("ShaderNodeOutputWorld")
        bg = world.node_tree.nodes.new("ShaderNodeBackground")
        world.node_tree.links.new(bg.outputs["Background"], out.inputs["Surface"])
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 0.0
    world.color = (0.0, 0.0, 0.0)
    scene.world = world
    return scene


def add_camera(scene, location, look_at, lens_deg=70.0, resolution=(800, 600)):
    cam = bpy.data.cameras.new("Camera")
    cam.angle = math.radians(lens_deg)
    cam.sensor_fit = "AUTO"
    ob = bpy.data.objects.new("Camera", cam)
    ob.location = location
    d = Vector(look_at) - Vector(location)
    ob.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(ob)
    scene.camera = ob
    scene.render.resolution_x, scene.render.resolution_y = resolution
    # clip so the far wall of a few-hundred-unit room is in range
    cam.clip_start = 0.01 if d.length < 10 else 1.0
    cam.clip_end = max(100.0, 10 * d.length)
    return ob


def look_through_camera():
    """Every 3D viewport of every workspace opens looking through the scene camera.

    The factory layout's viewport stands about 15 units from the origin: inside these rooms
    (hundreds of units across) it faces a bare wall, so a user opening the file saw grey."""
    for screen in bpy.data.screens:
        for area in screen.areas:
            for space in area.spaces:
                if space.type == "VIEW_3D" and space.region_3d is not None:
                    space.region_3d.view_perspective = "CAMERA"


def footprint(ob):
    """XY corners of the object's bounding box in world space (for overlap checks)."""
    corners = [ob.matrix_world @ Vector(c) for c in ob.bound_box]
    # keep the convex hull (4 points of a rotated box)
    return convex_hull_2d(set((round(c.x, 6), round(c.y, 6)) for c in corners))


def convex_hull_2d(points):
    """Convex hull of distinct XY points, counter-clockwise (Andrew's monotone chain)."""
    pts = sorted(points)
    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def overlap_2d(a, b):
    """Separating-axis test for convex XY polygons."""
    for poly in (a, b):
        for i in range(len(poly)):
            p, q = poly[i], poly[(i + 1) % len(poly)]
            ax = (q[1] - p[1], p[0] - q[0])
            pa = [ax[0] * x + ax[1] * y for x, y in a]
            pb = [ax[0] * x + ax[1] * y for x, y in b]
            if max(pa) <= min(pb) or max(pb) <= min(pa):
                return False
    return True


def check_move(scene, room_lo, room_hi):
    """Objects must not intersect each other or leave the room, before or after the move."""
    mv = scene["radiosity_move"]
    ob = bpy.data.objects[mv["object"]]
    movers = [o for o in scene.objects if o.type == "MESH" and o.users_collection[0] != scene.collection]
    before = (ob.location.copy(), ob.rotation_euler.copy())
    for state in ("before", "after"):
        if state == "after":
            ob.location = Vector(mv["location"])
            ob.rotation_euler.z = before[1].z + math.radians(mv["rotation_z_deg"])
        bpy.context.view_layer.update()
        fps = {o.name: footprint(o) for o in movers}
        for o in movers:
            for x, y in fps[o.name]:
                assert room_lo[0] < x < room_hi[0] and room_lo[1] < y < room_hi[1], (state, o.name)
            zs = [(o.matrix_world @ Vector(c)).z for c in o.bound_box]
            assert min(zs) >= room_lo[2] - 1e-6 and max(zs) < room_hi[2], (state, o.name)
            for p in movers:
                if p.name < o.name:
                    assert not overlap_2d(fps[o.name], fps[p.name]), (state, o.name, p.name)
    ob.location, ob.rotation_euler = before
    bpy.context.view_layer.update()


def finish(scene, name, out_dir, expected_surfaces, expected_objects):
    meshes = [o for o in scene.objects if o.type == "MESH"]
    n_surf = sum(o["radiosity_input_surfaces"] for o in meshes)
    n_obj = sum(1 for o in meshes if o.users_collection[0] != scene.collection)
    assert n_surf == expected_surfaces, (name, n_surf)
    assert n_obj == expected_objects, (name, n_obj)
    scene["radiosity_input_surfaces"] = n_surf
    scene["radiosity_input_objects"] = n_obj
    corners = sum(len(o.data.loops) for o in meshes)
    polys = sum(len(o.data.polygons) for o in meshes)
    assert corners < 20000, (name, corners)
    path = os.path.join(out_dir, name + ".blend")
    look_through_camera()
    bpy.context.preferences.filepaths.save_version = 0  # no .blend1 backups next to the files
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
    print(f"[make_examples] {name}: {n_surf} input surfaces, {n_obj} objects, "
          f"{len(meshes)} meshes, {polys} polygons, {corners} corners -> {path}")


# --------------------------------------------------------------------------- rooms


def room_surfaces(size, wall, floor, ceiling):
    """Floor, ceiling and four walls of a room [0,X]x[0,Y]x[0,Z], normals facing in."""
    X, Y, Z = size
    s = box_surfaces((0, 0, 0), (X, Y, Z), wall, inward=True)
    s[0].material = floor
    s[1].material = ceiling
    # order: floor, ceiling, walls
    return s


def ceiling_light(center, size, height, material):
    cx, cy = center
    hx, hy = size[0] / 2, size[1] / 2
    q = [(cx - hx, cy - hy, height), (cx + hx, cy - hy, height),
         (cx + hx, cy + hy, height), (cx - hx, cy + hy, height)]
    return [Surface(q, material, normal=(0, 0, -1))]


def standard_room(size, light_size, target):
    """A new scene holding the room [0,X]x[0,Y]x[0,Z] of `size` and its ceiling light."""
    scene = new_scene()
    wall = diffuse_material("Wall", (0.7, 0.7, 0.7))
    floor = diffuse_material("Floor", (0.55, 0.5, 0.45))
    ceiling = diffuse_material("Ceiling", (0.8, 0.8, 0.8))
    light = emission_material("CeilingLight", (12.0, 12.0, 12.0))
    make_object("Room", room_surfaces(size, wall, floor, ceiling), target, scene.collection)
    # 1 unit below the ceiling: both sides emit, so the ceiling above it is lit as in Cycles.
    make_object("CeilingLight", ceiling_light((size[0] / 2, size[1] / 2), light_size, size[2] - 1.0, light),
                max(light_size) / 4, scene.collection)
    return scene


def finish_room(scene, name, out_dir, size, eye, look_at, expected_surfaces, expected_objects):
    """The rooms' common end: check the move against the room, add the camera, save."""
    check_move(scene, (0, 0, 0), size)
    add_camera(scene, eye, look_at, 75.0)
    finish(scene, name, out_dir, expected_surfaces, expected_objects)


def chair_surfaces(origin, w, d, seat_h, seat_t, leg, H, material):
    """A chair of 11 boxes (66 surfaces), back towards +y, feet at z=0, origin at its bbox centre.

    4 legs, the seat, 2 back posts over the rear legs, 2 back rails between the posts and
    2 side stretchers between front and rear legs.
    """
    ox, oy = origin[0], origin[1]
    x0, x1, y0, y1 = ox - w / 2, ox + w / 2, oy - d / 2, oy + d / 2
    boxes = []
    leg_top = seat_h - seat_t
    for lx in (x0, x1 - leg):
        for ly in (y0, y1 - leg):
            boxes.append(((lx, ly, 0), (lx + leg, ly + leg, leg_top)))
    boxes.append(((x0, y0, leg_top), (x1, y1, seat_h)))
    for lx in (x0, x1 - leg):
        boxes.append(((lx, y1 - leg, seat_h), (lx + leg, y1, H)))
    rail_t = leg * 0.6
    ry0 = y1 - leg / 2 - rail_t / 2
    back = H - seat_h
    for z0, z1 in ((H - 0.22 * back, H), (seat_h + 0.40 * back, seat_h + 0.55 * back)):
        boxes.append(((x0 + leg, ry0, z0), (x1 - leg, ry0 + rail_t, z1)))
    sz0 = 0.22 * leg_top
    for lx in (x0, x1 - leg):
        sx0 = lx + leg / 2 - rail_t / 2
        boxes.append(((sx0, y0 + leg, sz0), (sx0 + rail_t, y1 - leg, sz0 + rail_t)))
    out = []
    for lo, hi in boxes:
        out += box_surfaces(lo, hi, material)
    assert len(out) == 66
    return out


def build_box_room(out_dir):
    size = (300.0, 300.0, 250.0)
    scene = standard_room(size, (80.0, 80.0), 12.5)
    # Box1: 80 x 80 x 100 centred at (114.4, 129.2, 50); Box2: 60 x 60 x 160 near the far corner.
    red = diffuse_material("BoxRed", (0.65, 0.12, 0.08))
    blue = diffuse_material("BoxBlue", (0.12, 0.25, 0.6))
    for name, c, half, mat in (("Box1", (114.4, 129.2, 50.0), (40.0, 40.0, 50.0), red),
                               ("Box2", (65.0, 245.0, 80.0), (30.0, 30.0, 80.0), blue)):
        lo = tuple(c[i] - half[i] for i in range(3))
        hi = tuple(c[i] + half[i] for i in range(3))
        make_object(name, box_surfaces(lo, hi, mat), 10.0, object_collection(scene, name), origin=c)
    scene["radiosity_move"] = {"object": "Box1", "location": (150.0, 190.0, 50.0), "rotation_z_deg": 0.0}
    # The paper's second test on this scene: the light dimmed from (12,12,12) to (2,2,2).
    scene["radiosity_dim"] = {"object": "CeilingLight", "radiance": (2.0, 2.0, 2.0)}
    finish_room(scene, "box_room", out_dir, size, (285.0, 12.0, 215.0), (120.0, 180.0, 40.0), 19, 2)


def build_chair_room(out_dir):
    size = (400.0, 400.0, 250.0)
    scene = standard_room(size, (100.0, 100.0), 16.0)
    wood = diffuse_material("ChairWood", (0.5, 0.3, 0.15))
    # A high-backed chair 184 tall: its origin (bbox centre) is the paper's z = 92.
    origin = (150.0, 270.0, 92.0)
    surf = chair_surfaces(origin, 90.0, 80.0, 85.0, 8.0, 8.0, 184.0, wood)
    make_object("Chair", surf, 8.0, object_collection(scene, "Chair"), origin=origin)
    scene["radiosity_move"] = {"object": "Chair", "location": (120.0, 150.0, 92.0), "rotation_z_deg": 25.0}
    finish_room(scene, "chair_room", out_dir, size, (385.0, 15.0, 215.0), (160.0, 230.0, 50.0), 73, 1)


def build_full_room(out_dir):
    size = (400.0, 400.0, 250.0)
    scene = standard_room(size, (100.0, 100.0), 20.0)
    wood = diffuse_material("ChairWood", (0.5, 0.3, 0.15))
    table_mat = diffuse_material("TableTop", (0.6, 0.45, 0.3))
    cab_mat = diffuse_material("Cabinet", (0.75, 0.72, 0.6))
    handle = diffuse_material("Handle", (0.1, 0.1, 0.1))
    # Chairs 115 tall: origin (bbox centre) at the paper's z = 57.5. 66 surfaces each.
    chair_args = (48.0, 46.0, 48.0, 5.0, 5.0, 115.0, wood)
    origin = (220.0, 295.3, 57.5)
    make_object("Chair", chair_surfaces(origin, *chair_args), 6.0, object_collection(scene, "Chair"),
                origin=origin)
    origin2 = (190.0, 130.0, 57.5)
    make_object("Chair2", chair_surfaces(origin2, *chair_args), 6.0, object_collection(scene, "Chair2"),
                origin=origin2)
    bpy.data.objects["Chair2"].rotation_euler.z = math.pi  # faces the table from the other side
    # Table (34 surfaces): a top with chamfered corners (an octagonal prism: 10) on 4 legs (24).
    tc, tw, td, ch, top_z, top_t, leg = (200.0, 215.0), 130.0, 80.0, 12.0, 75.0, 5.0, 6.0
    x0, x1, y0, y1 = tc[0] - tw / 2, tc[0] + tw / 2, tc[1] - td / 2, tc[1] + td / 2
    outline = [(x0 + ch, y0), (x1 - ch, y0), (x1, y0 + ch), (x1, y1 - ch),
               (x1 - ch, y1), (x0 + ch, y1), (x0, y1 - ch), (x0, y0 + ch)]
    table = prism_surfaces(outline, top_z - top_t, top_z, table_mat)
    inset = 12.0
    for lx in (x0 + inset, x1 - inset - leg):
        for ly in (y0 + inset, y1 - inset - leg):
            table += box_surfaces((lx, ly, 0.0), (lx + leg, ly + leg, top_z - top_t), wood)
    assert len(table) == 34
    make_object("Table", table, 8.0, object_collection(scene, "Table"), origin=(tc[0], tc[1], top_z / 2))
    # Cabinet (30 surfaces) against the +x wall: plinth, body, top slab, two door handles.
    cab = []
    cab += box_surfaces((351.0, 63.0, 0.0), (395.0, 157.0, 8.0), handle)
    cab += box_surfaces((348.0, 60.0, 8.0), (398.0, 160.0, 116.0), cab_mat)
    cab += box_surfaces((345.0, 58.0, 116.0), (398.0, 162.0, 122.0), cab_mat)
    for hy in (103.0, 113.0):
        cab += box_surfaces((344.0, hy, 78.0), (348.0, hy + 4.0, 100.0), handle)
    assert len(cab) == 30
    make_object("Cabinet", cab, 10.0, object_collection(scene, "Cabinet"), origin=(371.5, 110.0, 61.0))
    scene["radiosity_move"] = {"object": "Chair", "location": (120.0, 300.0, 57.5), "rotation_z_deg": 25.0}
    finish_room(scene, "full_room", out_dir, size, (15.0, 15.0, 220.0), (230.0, 230.0, 40.0), 203, 4)


def build_cornell_box(out_dir):
    """The Cornell Program of Computer Graphics data (mm, y up) in metres, z up."""
    scene = new_scene()

    def P(x, y, z):  # (x, y, z)_cornell mm -> (x, -z, y) m; a proper rotation, windings kept
        return (x * 0.001, -z * 0.001, y * 0.001)

    white = diffuse_material("White", (0.725, 0.71, 0.68))
    red = diffuse_material("Red", (0.63, 0.065, 0.05))
    green = diffuse_material("Green", (0.14, 0.45, 0.091))
    light = emission_material("Light", (17.0, 12.0, 4.0))
    inside = P(278.0, 274.4, 279.6)
    room = [
        Surface([P(552.8, 0, 0), P(0, 0, 0), P(0, 0, 559.2), P(549.6, 0, 559.2)], white, toward=inside),
        Surface([P(556, 548.8, 0), P(556, 548.8, 559.2), P(0, 548.8, 559.2), P(0, 548.8, 0)], white,
                toward=inside),
        Surface([P(549.6, 0, 559.2), P(0, 0, 559.2), P(0, 548.8, 559.2), P(556, 548.8, 559.2)], white,
                toward=inside),
        Surface([P(0, 0, 559.2), P(0, 0, 0), P(0, 548.8, 0), P(0, 548.8, 559.2)], green, toward=inside),
        Surface([P(552.8, 0, 0), P(549.6, 0, 559.2), P(556, 548.8, 559.2), P(556, 548.8, 0)], red,
                toward=inside),
    ]
    make_object("CornellBox", room, 0.035, scene.collection)
    ly = 548.8 - 1.0  # 1 mm under the ceiling
    lamp = [Surface([P(343, ly, 227), P(343, ly, 332), P(213, ly, 332), P(213, ly, 227)], light,
                    normal=(0, 0, -1))]
    make_object("Light", lamp, 0.0325, scene.collection)

    def block(name, top, height):
        # The data's 5 faces per block (top and 4 sides; no bottom on the floor).
        tops = [P(x, height, z) for x, z in top]
        bots = [P(x, 0.0, z) for x, z in top]
        c = sum((Vector(p) for p in tops + bots), Vector()) / 8
        surf = [Surface(tops, white, away_from=c)]
        for i in range(4):
            j = (i + 1) % 4
            surf.append(Surface([bots[i], bots[j], tops[j], tops[i]], white, away_from=c))
        base = sum((Vector(p) for p in bots), Vector()) / 4
        return make_object(name, surf, 0.035, object_collection(scene, name), origin=tuple(base))

    short = block("ShortBlock", [(130, 65), (82, 225), (240, 272), (290, 114)], 165.0)
    block("TallBlock", [(423, 247), (265, 296), (314, 456), (472, 406)], 330.0)
    # Short block 8 cm to the right (+x) and 4 cm towards the camera: clear of the tall block.
    to = short.location + Vector((0.08, 0.04, 0.0))
    scene["radiosity_move"] = {"object": "ShortBlock", "location": tuple(round(c, 6) for c in to),
                               "rotation_z_deg": 0.0}
    check_move_cornell(scene)
    # The data's camera: (278, 273, -800) looking +z, 39.3077 deg field of view, square image.
    add_camera(scene, P(278, 273, -800), P(278, 273, 0), 39.3077, (512, 512))
    finish(scene, "cornell_box", out_dir, 16, 2)


def check_move_cornell(scene):
    """The blocks' footprints are not boxes: test the real convex outlines."""
    def outline(ob):
        ring = []
        for vtx in ob.data.vertices:
            w = ob.matrix_world @ vtx.co
            if abs(w.z) < 1e-9:
                ring.append((w.x, w.y))
        # convex hull of the floor-level points
        return convex_hull_2d(set((round(x, 7), round(y, 7)) for x, y in ring))
    short, tall = bpy.data.objects["ShortBlock"], bpy.data.objects["TallBlock"]
    bpy.context.view_layer.update()
    keep = short.location.copy()
    assert not overlap_2d(outline(short), outline(tall))
    short.location = Vector(scene["radiosity_move"]["location"])
    bpy.context.view_layer.update()
    assert not overlap_2d(outline(short), outline(tall))
    for x, y in outline(short):
        assert 0.0 < x < 0.5496 and -0.5592 < y < 0.0
    short.location = keep
    bpy.context.view_layer.update()


def build_furnace(out_dir):
    """A closed cube, inward normals, rho = 0.5, emission 1 everywhere: B = 1/(1-0.5) = 2."""
    scene = new_scene()
    mat = emission_material("Furnace", (1.0, 1.0, 1.0), reflectance=(0.5, 0.5, 0.5))
    make_object("Furnace", box_surfaces((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0), mat, inward=True), 0.125,
                scene.collection)
    scene["radiosity_expected_radiance"] = 2.0
    add_camera(scene, (0.8, -0.8, -0.5), (-1.0, 1.0, 0.6), 80.0)
    finish(scene, "furnace", out_dir, 6, 0)


BUILDERS = {
    "box_room": build_box_room,
    "chair_room": build_chair_room,
    "full_room": build_full_room,
    "cornell_box": build_cornell_box,
    "furnace": build_furnace,
}


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    out_dir, only = HERE, []
    i = 0
    while i < len(argv):
        if argv[i] == "--out":
            out_dir = os.path.abspath(argv[i + 1])
            i += 2
        elif argv[i] == "--only":
            only.append(argv[i + 1])
            i += 2
        else:
            raise SystemExit(f"make_examples.py: unknown argument {argv[i]!r}")
    for name in only:
        if name not in BUILDERS:
            raise SystemExit(f"make_examples.py: no scene {name!r} (have {', '.join(BUILDERS)})")
    os.makedirs(out_dir, exist_ok=True)
    for name, build in BUILDERS.items():
        if not only or name in only:
            build(out_dir)


if __name__ == "__main__":
    try:
        main()
    except BaseException:
        import traceback
        traceback.print_exc()
        sys.exit(1)
