"""Scenes of the corner-exact acceptance tests (test_corner_exact.py), built identically by the
tests and by tests/blender/scripts/make_corner_references.py, and the in-Blender runner the tests
call.

Each corner of our output must hold the radiance at its vertex seen with its face's normal, as a
Cycles COMBINED bake to a corner colour attribute does (CONTRACT.md, NOTES.md), not an area
average of the element around it. The scenes put corners where the two differ most:

  contact  a closed box standing on a gridded floor: 9 floor vertices under the box, 16 exactly
           on its footprint's edge; lit by a two-sided emitting plane (a mesh lamp).
  lamp     a two-sided emitting quad 1 mm under a 12x12 gridded ceiling, rotated 17 degrees so
           its rim cuts the grid; nothing else in the scene (black world), so the ceiling's
           radiance is exactly rho x L x F(point, lamp) (Lambert's contour formula).
  leg      a 4 x 4 x 70 cm leg (sides split every 5 cm along its length) on a floor, lit by a
           point light.
  factory  Blender's factory-startup scene (cube, 1000 W point light, grey world), untouched.
  room     an open room (floor, back and left walls; no ceiling, open to the front and right so
           the sun gets in) with a cube, lit by a point, a spot, an area and a sun light.

and gaps under objects (test_gaps.py), where the floor under an object gets only what comes in
through the gap:

  gap_cube           a 2 m cube 1 mm over a gridded floor under a uniform sky-blue world.
  gap_slab           a 3.2 x 3.2 x 0.5 m slab 15 cm over a gridded floor, lit by Blender's
                     default point light (1000 W at (4.08, 1, 5.9)) from one side.
  gap_slab_instance  the same slab as a collection instance (only the floor is baked).
  gap_slab_1cm       the slab 1 cm over the floor.

and a closed box (test_gaps.py: no excess light where nothing leaves the scene):

  closed_box         a 5.5 m Cornell-type box closed on all six sides (gridded walls, a red and
                     a green one, two white blocks) lit by a two-sided emitting square 1 mm
                     under its gridded ceiling.

Runner (what the tests call, in either flavour; conftest's run_blender passes --zip/--tmp):

    ... corner_scenes.py -- --zip Z --tmp T --case contact --preset HIGH --out T/contact.npz

bakes the scene with the add-on and writes, per corner in ORDER[case] order: ours (RGB), the
vertex position and the face normal (world), a global vertex id, and whether it is an emitter's
corner; prints RESULT {ok, fake, stats, tag, info}.
"""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "scripts"))
import rt_common as rt  # noqa: E402

CASES = ("contact", "lamp", "leg", "factory", "room", "gap_cube", "gap_slab", "gap_slab_instance", "gap_slab_1cm",
         "closed_box")

# Objects whose corners are compared, in the order of the stored references.
ORDER = {
    "contact": ("Floor", "Box", "Lamp"),
    "lamp": ("Ceiling", "Lamp"),
    "leg": ("Floor", "Leg"),
    "factory": ("Cube",),
    "room": ("Floor", "BackWall", "LeftWall", "Cube"),
    "gap_cube": ("Floor", "Cube"),
    "gap_slab": ("Floor", "Slab"),
    "gap_slab_instance": ("Floor",),
    "gap_slab_1cm": ("Floor", "Slab"),
    "closed_box": ("Floor", "Ceiling", "Back", "Front", "Left", "Right", "Short", "Tall", "Lamp"),
}
EMITTERS = {"contact": ("Lamp",), "lamp": ("Lamp",), "closed_box": ("Lamp",)}

# contact: the box's footprint lies on floor grid lines (floor [-1.5, 1.5]^2 in 15 x 15 quads,
# lines at odd tenths), so 3 x 3 floor vertices are under it and 4 x 4 - 3 x 3 = 16 on its edge.
CONTACT_BOX_LO = (-0.3, -0.5, 0.0)
CONTACT_BOX_HI = (0.5, 0.3, 0.6)
# gaps: the object's footprint on the floor (the floor's grid lines miss its edges: floor
# quads straddle them) and its height over the floor.
GAP_CUBE_HALF, GAP_CUBE_LIFT = 1.0, 0.001
GAP_SLAB_HALF, GAP_SLAB_LIFT, GAP_SLAB_LIFT_1CM = 1.6, 0.15, 0.01
GAP_SKY = (0.4, 0.6, 1.0)
# lamp: ceiling plane, reflectance, lamp outline and radiance (see build_lamp).
LAMP_CEILING_Z = 2.5
LAMP_GAP = 0.001
LAMP_RHO = (0.8, 0.7, 0.6)
LAMP_RADIANCE = (5.0, 4.5, 4.0)
LAMP_SIZE = (0.9, 0.6)
LAMP_CENTRE = (0.13, -0.07)
LAMP_ANGLE_DEG = 17.0

DESCRIPTION = {
    "contact": "black world; Floor 3x3 m at z=0 in 15x15 quads, rho 0.5; Box (welded, 4x4x3 quads "
               "per side) x[-0.3,0.5] y[-0.5,0.3] z[0,0.6], rho (0.7,0.35,0.2), closed (bottom on "
               "the floor); Lamp: 0.7x0.7 emission quad, radiance 12, centre (1.0,0.8,1.6), "
               "normal -z (both sides emit)",
    "lamp": "black world; Ceiling 3x3 m at z=2.5 in 12x12 quads, normal -z, rho (0.8,0.7,0.6); "
            "Lamp 0.9x0.6 emission quad, radiance (5,4.5,4), centre (0.13,-0.07), 1 mm under the "
            "ceiling, rotated 17 deg about z, normal -z (both sides emit)",
    "leg": "black world; Floor 2x2 m at z=0 in 10x10 quads, rho 0.5; Leg (welded) x[0.08,0.12] "
           "y[0.03,0.07] z[0,0.7], sides in 14 quads along z, closed, rho (0.6,0.5,0.4); point "
           "light 150 W radius 0.05 at (0.9,-0.7,1.4)",
    "factory": "bpy.ops.wm.read_factory_settings(use_empty=False): Cube (Principled, base 0.8), "
               "Light (point 1000 W, radius 0.1), World (background 0.0509 grey)",
    "gap_cube": "uniform world (0.4, 0.6, 1.0) strength 1; Floor 8x8 m at z=0 in 20x20 quads, rho 0.6; "
                "Cube (one quad a side) x,y[-1,1] z[0.001,2.001], rho 0.8",
    "gap_slab": "black world; Floor 10x10 m at z=0 in 25x25 quads, rho 0.6; Slab (one quad a side) "
                "x,y[-1.6,1.6] z[0.15,0.65], rho 0.8; point light 1000 W radius 0.1 at (4.08,1,5.9)",
    "gap_slab_instance": "as gap_slab, the slab in a collection excluded from the view layer and "
                         "shown by an Empty instancing it",
    "gap_slab_1cm": "as gap_slab, the slab at z[0.01,0.51]",
    "closed_box": "black world; box [0,5.5]^3 closed, inward normals: Floor, Back (y=5.5), Front (y=0), "
                  "Ceiling (10x10 quads) and walls (8x8 quads), rho 0.73, Left (x=0) (0.63,0.06,0.05), "
                  "Right (x=5.5) (0.14,0.45,0.09); Short block [1.3,2.95]x[0.65,2.3]x[0,1.65] (2x2x2 "
                  "quads), Tall block [2.65,4.3]x[2.95,4.6]x[0,3.3] (2x2x4), rho 0.73; Lamp: 1.3x1.3 "
                  "emission quad, radiance 15, centre (2.75,2.75), 1 mm under the ceiling, normal -z",
    "room": "black world; open room: Floor 4x4 m (8x8 quads, rho 0.6), BackWall y=2 and LeftWall "
            "x=-2 (4 m x 2.5 m, 8x5 quads, rho (0.7,0.65,0.6) and (0.5,0.6,0.7)); Cube 0.6 m "
            "(2x2 quads per side, welded) at (0.3,0.4,0.3) turned 20 deg about z, rho "
            "(0.7,0.3,0.2); point 200 W r 0.1 at (-1,-0.8,1.8) colour (1,0.85,0.7); spot 500 W "
            "r 0.05 size 50 deg blend 0.2 at (1.2,-1.5,2.2) aimed at (-0.2,1.0,0.6); area square "
            "0.8 m 120 W at (0,0.8,2.3) facing down; sun 2 W/m2 angle 2 deg rotation (50,0,35) deg",
}


def version_tag():
    """Reference generation: Blender 3.x (v3) and 4.0+ (v4) differ in area and spot light units
    and in the Principled BSDF (see addon/radiosity/core/lights.py and make_corner_references)."""
    return "v4" if bpy.app.version >= (4, 0, 0) else "v3"


def welded_box(lo, hi, n):
    """Closed axis-aligned box [lo, hi] with outward normals, side quads split n = (nx, ny, nz)
    times along each axis, vertices shared between sides (as a subdivided Blender cube)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    verts, index, faces = [], {}, []

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]

    for axis in range(3):
        a1, a2 = [k for k in range(3) if k != axis]
        for sign in (-1, 1):
            n1, n2 = n[a1], n[a2]
            for j in range(n2):
                for i in range(n1):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.empty(3)
                        p[axis] = hi[axis] if sign > 0 else lo[axis]
                        p[a1] = lo[a1] + (hi[a1] - lo[a1]) * (i + di) / n1
                        p[a2] = lo[a2] + (hi[a2] - lo[a2]) * (j + dj) / n2
                        quad.append(vid(p))
                    e1 = np.zeros(3); e1[a1] = 1
                    e2 = np.zeros(3); e2[a2] = 1
                    if np.cross(e1, e2)[axis] * sign < 0:
                        quad = quad[::-1]
                    faces.append(tuple(quad))
    return verts, faces


def _quad_mesh(name, corners, material, collection=None):
    return rt.mesh_object(name, corners, [(0, 1, 2, 3)], collection, material)


def build_contact():
    rt.black_world()
    floor = rt.mesh_object("Floor", *rt.grid((-1.5, -1.5, 0), (3, 0, 0), (0, 3, 0), 15), None,
                           rt.diffuse_material("Floor", (0.5, 0.5, 0.5)))
    box = rt.mesh_object("Box", *welded_box(CONTACT_BOX_LO, CONTACT_BOX_HI, (4, 4, 3)), None,
                         rt.diffuse_material("Box", (0.7, 0.35, 0.2)))
    c, h = np.array([1.0, 0.8, 1.6]), 0.35
    lamp = _quad_mesh("Lamp", [c + (-h, -h, 0), c + (-h, h, 0), c + (h, h, 0), c + (h, -h, 0)],
                      rt.emission_material("Lamp", (1, 1, 1), 12.0))          # normal -z
    return [floor, box, lamp], {"footprint_lo": CONTACT_BOX_LO[:2], "footprint_hi": CONTACT_BOX_HI[:2]}


def lamp_polygon():
    """World outline of the lamp (4 x 3), normal -z."""
    hx, hy = LAMP_SIZE[0] / 2, LAMP_SIZE[1] / 2
    t = math.radians(LAMP_ANGLE_DEG)
    rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    local = np.array([(-hx, -hy), (-hx, hy), (hx, hy), (hx, -hy)])     # clockwise from +z
    xy = local @ rot.T + np.asarray(LAMP_CENTRE)
    return np.column_stack([xy, np.full(4, LAMP_CEILING_Z - LAMP_GAP)])


def build_lamp():
    rt.black_world()
    z = LAMP_CEILING_Z
    ceiling = rt.mesh_object("Ceiling", *rt.grid((-1.5, -1.5, z), (0, 3, 0), (3, 0, 0), 12), None,
                             rt.diffuse_material("Ceiling", LAMP_RHO))          # u x v = -z
    strength = max(LAMP_RADIANCE)
    lamp = _quad_mesh("Lamp", list(lamp_polygon()),
                      rt.emission_material("Lamp", tuple(c / strength for c in LAMP_RADIANCE), strength))
    return [ceiling, lamp], {"lamp_polygon": lamp_polygon().tolist(), "rho": LAMP_RHO,
                             "radiance": LAMP_RADIANCE}


def add_light(name, kind, settings, location, rotation_deg=(0, 0, 0), aim=None):
    light = bpy.data.lights.new(name, kind)
    for k, v in settings.items():
        setattr(light, k, v)
    obj = bpy.data.objects.new(name, light)
    obj.location = location
    if aim is not None:         # point the light's -Z at `aim`
        d = np.asarray(aim, float) - np.asarray(location, float)
        from mathutils import Vector
        obj.rotation_euler = Vector(tuple(d)).to_track_quat("-Z", "Y").to_euler()
    else:
        obj.rotation_euler = tuple(math.radians(a) for a in rotation_deg)
    return rt.link(obj)


def build_leg():
    rt.black_world()
    floor = rt.mesh_object("Floor", *rt.grid((-1, -1, 0), (2, 0, 0), (0, 2, 0), 10), None,
                           rt.diffuse_material("Floor", (0.5, 0.5, 0.5)))
    leg = rt.mesh_object("Leg", *welded_box((0.08, 0.03, 0.0), (0.12, 0.07, 0.7), (1, 1, 14)), None,
                         rt.diffuse_material("Leg", (0.6, 0.5, 0.4)))
    add_light("Point", "POINT", {"energy": 150.0, "shadow_soft_size": 0.05}, (0.9, -0.7, 1.4))
    return [floor, leg], {}


def build_factory():
    bpy.ops.wm.read_factory_settings(use_empty=False)
    return [bpy.data.objects["Cube"]], {}


def build_room():
    rt.black_world()
    floor = rt.mesh_object("Floor", *rt.grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), 8), None,
                           rt.diffuse_material("Floor", (0.6, 0.6, 0.6)))
    # rt.grid's n splits both directions equally: build the 8 x 5 walls by hand.
    def wall(name, origin, u, v, nu, nv, rho):
        origin, u, v = (np.asarray(x, float) for x in (origin, u, v))
        verts = [origin + (i / nu) * u + (j / nv) * v for j in range(nv + 1) for i in range(nu + 1)]
        faces = [(j * (nu + 1) + i, j * (nu + 1) + i + 1, (j + 1) * (nu + 1) + i + 1,
                  (j + 1) * (nu + 1) + i) for j in range(nv) for i in range(nu)]
        return rt.mesh_object(name, verts, faces, None, rt.diffuse_material(name, rho))
    back = wall("BackWall", (-2, 2, 0), (4, 0, 0), (0, 0, 2.5), 8, 5, (0.7, 0.65, 0.6))    # -y
    left = wall("LeftWall", (-2, -2, 0), (0, 4, 0), (0, 0, 2.5), 8, 5, (0.5, 0.6, 0.7))    # +x
    cube = rt.mesh_object("Cube", *welded_box((-0.3, -0.3, 0.0), (0.3, 0.3, 0.6), (2, 2, 2)), None,
                          rt.diffuse_material("Cube", (0.7, 0.3, 0.2)))
    cube.location = (0.3, 0.4, 0.0)
    cube.rotation_euler = (0.0, 0.0, math.radians(20.0))
    add_light("Point", "POINT", {"energy": 200.0, "shadow_soft_size": 0.1, "color": (1.0, 0.85, 0.7)},
              (-1.0, -0.8, 1.8))
    add_light("Spot", "SPOT", {"energy": 500.0, "shadow_soft_size": 0.05, "spot_size": math.radians(50),
                               "spot_blend": 0.2}, (1.2, -1.5, 2.2), aim=(-0.2, 1.0, 0.6))
    add_light("Area", "AREA", {"shape": "SQUARE", "size": 0.8, "energy": 120.0}, (0.0, 0.8, 2.3))
    add_light("Sun", "SUN", {"energy": 2.0, "angle": math.radians(2.0)}, (0, 0, 4), (50, 0, 35))
    bpy.context.view_layer.update()
    return [floor, back, left, cube], {}


def build_closed_box():
    rt.black_world()
    w = 5.5
    white, red, green = (0.73, 0.73, 0.73), (0.63, 0.06, 0.05), (0.14, 0.45, 0.09)

    def wall(name, origin, u, v, n, rho):                         # normal u x v, inward
        return rt.mesh_object(name, *rt.grid(origin, u, v, n), None, rt.diffuse_material(name, rho))
    objs = [wall("Floor", (0, 0, 0), (w, 0, 0), (0, w, 0), 8, white),
            wall("Ceiling", (0, 0, w), (0, w, 0), (w, 0, 0), 10, white),
            wall("Back", (0, w, 0), (w, 0, 0), (0, 0, w), 8, white),
            wall("Front", (0, 0, 0), (0, 0, w), (w, 0, 0), 8, white),
            wall("Left", (0, 0, 0), (0, w, 0), (0, 0, w), 8, red),
            wall("Right", (w, 0, 0), (0, 0, w), (0, w, 0), 8, green)]
    objs.append(rt.mesh_object("Short", *welded_box((1.3, 0.65, 0), (2.95, 2.3, 1.65), (2, 2, 2)), None,
                               rt.diffuse_material("Short", white)))
    objs.append(rt.mesh_object("Tall", *welded_box((2.65, 2.95, 0), (4.3, 4.6, 3.3), (2, 2, 4)), None,
                               rt.diffuse_material("Tall", white)))
    c, h = np.array([2.75, 2.75, w - 0.001]), 0.65
    objs.append(_quad_mesh("Lamp", [c + (-h, -h, 0), c + (-h, h, 0), c + (h, h, 0), c + (h, -h, 0)],
                           rt.emission_material("Lamp", (1, 1, 1), 15.0)))        # normal -z
    return objs, {}


def _gap_floor(half, n):
    return rt.mesh_object("Floor", *rt.grid((-half, -half, 0), (2 * half, 0, 0), (0, 2 * half, 0), n), None,
                          rt.diffuse_material("Floor", (0.6, 0.6, 0.6)))


def build_gap_cube():
    world = rt.node_world("Sky")
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (*GAP_SKY, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = world
    floor = _gap_floor(4.0, 20)
    h, z = GAP_CUBE_HALF, GAP_CUBE_LIFT
    cube = rt.mesh_object("Cube", *welded_box((-h, -h, z), (h, h, z + 2 * h), (1, 1, 1)), None,
                          rt.diffuse_material("Cube", (0.8, 0.8, 0.8)))
    return [floor, cube], {"half": h, "lift": z}


def build_gap_slab(lift=GAP_SLAB_LIFT, instance=False):
    rt.black_world()
    floor = _gap_floor(5.0, 25)
    h = GAP_SLAB_HALF
    coll = rt.new_collection("SlabSet") if instance else None
    slab = rt.mesh_object("Slab", *welded_box((-h, -h, lift), (h, h, lift + 0.5), (1, 1, 1)), coll,
                          rt.diffuse_material("Slab", (0.8, 0.8, 0.8)))
    add_light("Light", "POINT", {"energy": 1000.0, "shadow_soft_size": 0.1}, (4.08, 1.0, 5.9))
    objs = [floor, slab]
    if instance:
        bpy.context.view_layer.layer_collection.children["SlabSet"].exclude = True
        inst = bpy.data.objects.new("SlabInstance", None)
        inst.instance_type = "COLLECTION"
        inst.instance_collection = coll
        rt.link(inst)
        objs = [floor]
    bpy.context.view_layer.update()
    return objs, {"half": h, "lift": lift}


BUILD = {"contact": build_contact, "lamp": build_lamp, "leg": build_leg, "factory": build_factory,
         "room": build_room, "gap_cube": build_gap_cube, "gap_slab": build_gap_slab,
         "gap_slab_instance": lambda: build_gap_slab(instance=True),
         "gap_slab_1cm": lambda: build_gap_slab(lift=GAP_SLAB_LIFT_1CM), "closed_box": build_closed_box}


def build(case):
    """Build `case` into the current (empty factory) scene; returns (objects in ORDER, info)."""
    objs, info = BUILD[case]()
    assert tuple(o.name for o in objs) == ORDER[case], [o.name for o in objs]
    return objs, info


def cycles_sample_points(me, co, loop_verts):
    """Where Cycles' vertex-colour bake evaluates each corner. Blender hands Cycles the corner's
    vertex as barycentric (1,0,0)-like coordinates of the first triangle (mesh loop-triangle order)
    holding the corner; Cycles then nudges a point lying exactly on a vertex towards that
    triangle's centroid by min(|centroid - P|, max(max|P|, 1) x 1e-4) "to avoid self-intersection"
    (integrator_init_from_bake / bake_offset_towards_center, Blender 3.x to 5.0). `co`: world
    vertex positions (our objects' meshes are placed so that world = what Cycles stores)."""
    me.calc_loop_triangles()
    tris = np.empty(len(me.loop_triangles) * 3, np.int64)
    me.loop_triangles.foreach_get("loops", tris)
    tris = tris.reshape(-1, 3)
    first = np.full(len(loop_verts), len(tris), np.int64)
    np.minimum.at(first, tris.ravel(), np.repeat(np.arange(len(tris)), 3))
    assert (first < len(tris)).all()
    centroid = co[loop_verts[tris[first]]].mean(axis=1)
    p = co[loop_verts]
    to_c = centroid - p
    dist = np.linalg.norm(to_c, axis=1, keepdims=True)
    step = np.minimum(dist, np.maximum(np.abs(p).max(axis=1, keepdims=True), 1.0) * 1e-4)
    return p + to_c / np.maximum(dist, 1e-30) * step


def corner_geometry(objs, emitters=()):
    """Per corner, in object order: world vertex position, world face normal, the point where
    Cycles evaluates the corner (`sample`, see cycles_sample_points), global vertex id, emitter
    flag, object index."""
    pos, nrm, smp, vid, emit, obj = [], [], [], [], [], []
    base = 0
    for k, o in enumerate(objs):
        me = o.data
        m = np.array(o.matrix_world)
        nm = np.linalg.inv(m[:3, :3]).T
        co = np.empty(len(me.vertices) * 3)
        me.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
        li = np.empty(len(me.loops), np.int64)
        me.loops.foreach_get("vertex_index", li)
        tot = np.empty(len(me.polygons), np.int64)
        me.polygons.foreach_get("loop_total", tot)
        fn = np.empty(len(me.polygons) * 3)
        me.polygons.foreach_get("normal", fn)
        fn = fn.reshape(-1, 3) @ nm.T
        fn /= np.linalg.norm(fn, axis=1, keepdims=True)
        pos.append(co[li])
        nrm.append(np.repeat(fn, tot, axis=0))
        smp.append(cycles_sample_points(me, co, li))
        vid.append(li + base)
        base += len(me.vertices)
        emit.append(np.full(len(li), o.name in emitters))
        obj.append(np.full(len(li), k))
    return {"pos": np.concatenate(pos), "normal": np.concatenate(nrm), "sample": np.concatenate(smp),
            "vertex": np.concatenate(vid),
            "emitter": np.concatenate(emit), "object": np.concatenate(obj)}


def _run():
    case = rt.arg("--case")
    preset = rt.arg("--preset", "HIGH")
    out_path = rt.arg("--out")
    if case == "factory":
        objs, info = build(case)          # reads factory settings: install the add-on after
        rt.install_addon()
    else:
        rt.setup()
        objs, info = build(case)
    bpy.context.scene.radiosity.preset = preset
    ok, err, reports = rt.bake()
    res = {"ok": ok, "err": err, "reports": reports, "stats": rt.last_stats(),
           "fake": rt.native_is_fake(), "case": case, "preset": preset, "tag": version_tag(),
           "blender": bpy.app.version_string, "info": info}
    if ok:
        geo = corner_geometry(objs, EMITTERS.get(case, ()))
        ours = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs]).astype(np.float64)
        np.savez(out_path, ours=ours, **geo)
    rt.result(**res)


if __name__ == "__main__":
    _run()
