"""Build a furnished flat of living rooms for the interior benchmark and save it as a .blend.

    blender -b --factory-startup --python bench/interior/make_interior.py -- \
        --triangles 250000 --out interior_250k.blend [--materials principled|diffuse] [--quick]
    python3 bench/interior/make_interior.py --triangles 250000 --out F.blend   (PyPI bpy)

Meshes come only from Blender's primitive operators, edit-mode operators (cutting window and door
openings, joining), modifiers (Bevel, Subdivision Surface, Array) and collection instances,
never from vertex lists, so the scene is what an artist's file would be. Each room is 5 x 4 x
2.7 m (metres, Z up): gridded walls, floor and ceiling; a window in the south wall, a Sun and a
sky-blue world; a pendant point light over a dining table with six chairs instanced from one
collection; a table lamp with an emitting bulb; a sofa and an armchair of bevelled, subdivided
boxes; shelves of Array-modified books; a subdivided Suzanne; a rug 4 mm above the floor; a
plant of spheres; a floor whose colour is a Wave Texture. Materials are Principled BSDF, or
with --materials diffuse Diffuse BSDF of the same colours (emission stays Emission).

Size: --triangles N sets the evaluated triangle count (instances included). Larger sizes get
more rooms side by side (a flat, doors between neighbours, wall gaps closed by door reveals) as
well as finer modifier levels and wall grids; --quick is one room of about 17k triangles. The
build is deterministic. Conventions of example_blends/: the shells (walls, floor, ceiling) are
in the scene collection (the static environment), each piece of furniture is a collection of
its own with one parentless object, and scene["radiosity_move"] names the move the benchmark
makes: room 1's armchair (collection and object "Armchair") 0.5 m along +x, turned 0.6 rad.
"""
import argparse
import json
import math
import os
import random
import sys
import time

import bpy
from mathutils import Vector

ROOM_X, ROOM_Y, ROOM_Z = 5.0, 4.0, 2.7
GAP = 0.15                              # wall thickness between neighbouring rooms
DOOR_Y, DOOR_TOP = (2.95, 3.85), 2.05   # door openings in the rooms' east and west walls
WINDOW_X, WINDOW_Z = (1.7, 3.3), (0.85, 2.2)
LIFT = 0.001                            # resting objects float a hair above the floor
MOVE = {"dx": 0.5, "turn": 0.6}


def parse(argv):
    p = argparse.ArgumentParser(prog="make_interior.py")
    p.add_argument("--triangles", type=int, default=250000)
    p.add_argument("--quick", action="store_true", help="one room, about 17k triangles")
    p.add_argument("--materials", choices=("principled", "diffuse"), default="principled")
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


# --- materials ---------------------------------------------------------------------------------

class Materials:
    """Named materials, made once: Principled BSDF or (diffuse) Diffuse BSDF of one colour."""

    def __init__(self, kind):
        self.kind, self.made = kind, {}

    def _new(self, name):
        m = bpy.data.materials.new(name)
        if bpy.app.version < (5, 0, 0):     # always on (and deprecated) from 5.0
            m.use_nodes = True
        nt = m.node_tree
        for n in list(nt.nodes):
            nt.nodes.remove(n)
        return m, nt, nt.nodes.new("ShaderNodeOutputMaterial")

    def _bsdf(self, nt):
        if self.kind == "diffuse":
            b = nt.nodes.new("ShaderNodeBsdfDiffuse")
            b.inputs["Roughness"].default_value = 0.0
            return b, b.inputs["Color"]
        b = nt.nodes.new("ShaderNodeBsdfPrincipled")
        b.inputs["Roughness"].default_value = 0.6
        return b, b.inputs["Base Color"]

    def get(self, name, rgb):
        if name not in self.made:
            m, nt, out = self._new(name)
            b, colour = self._bsdf(nt)
            colour.default_value = (*rgb, 1.0)
            nt.links.new(b.outputs[0], out.inputs["Surface"])
            m.diffuse_color = (*rgb, 1.0)
            self.made[name] = m
        return self.made[name]

    def wave_floor(self):
        """Wood-like boards: a Wave Texture through a two-colour ramp into the base colour."""
        if "FloorWave" not in self.made:
            m, nt, out = self._new("FloorWave")
            b, colour = self._bsdf(nt)
            wave = nt.nodes.new("ShaderNodeTexWave")
            wave.inputs["Scale"].default_value = 6.0
            wave.inputs["Distortion"].default_value = 3.0
            ramp = nt.nodes.new("ShaderNodeValToRGB")
            ramp.color_ramp.elements[0].color = (0.36, 0.22, 0.12, 1.0)
            ramp.color_ramp.elements[1].color = (0.62, 0.43, 0.25, 1.0)
            nt.links.new(wave.outputs["Fac"], ramp.inputs["Fac"])
            nt.links.new(ramp.outputs["Color"], colour)
            nt.links.new(b.outputs[0], out.inputs["Surface"])
            m.diffuse_color = (0.5, 0.33, 0.18, 1.0)
            self.made["FloorWave"] = m
        return self.made["FloorWave"]

    def emission(self, name, rgb, strength):
        if name not in self.made:
            m, nt, out = self._new(name)
            e = nt.nodes.new("ShaderNodeEmission")
            e.inputs["Color"].default_value = (*rgb, 1.0)
            e.inputs["Strength"].default_value = strength
            nt.links.new(e.outputs[0], out.inputs["Surface"])
            m.diffuse_color = (*rgb, 1.0)
            self.made[name] = m
        return self.made[name]


# --- objects -----------------------------------------------------------------------------------

def collection(name, parent=None):
    c = bpy.data.collections.new(name)
    (parent or bpy.context.scene.collection).children.link(c)
    return c


def select_only(objs, active):
    for o in bpy.context.selected_objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = active


def prim(kind, name, coll, mat, loc, scale=(1, 1, 1), rot=(0, 0, 0), **kw):
    """bpy.ops.mesh.primitive_<kind>_add, then its rotation and scale applied to the mesh (so
    Bevel widths are metres), moved into `coll`, with material `mat`."""
    getattr(bpy.ops.mesh, f"primitive_{kind}_add")(location=loc, rotation=rot, **kw)
    ob = bpy.context.view_layer.objects.active
    ob.name = ob.data.name = name
    ob.scale = scale        # (the operators' own scale argument is ignored by some primitives)
    select_only([ob], ob)
    bpy.ops.object.transform_apply(location=False, rotation=True, scale=True)
    for c in list(ob.users_collection):
        c.objects.unlink(ob)
    coll.objects.link(ob)
    ob.data.materials.append(mat)
    return ob


def box(name, coll, mat, lo, hi):
    """An axis-aligned box from corner lo to corner hi (a 1 m cube scaled)."""
    lo, hi = Vector(lo), Vector(hi)
    return prim("cube", name, coll, mat, (lo + hi) / 2, scale=hi - lo, size=1)


def soft(ob, d, width=0.03):
    """Upholstery: Bevel (rounded edges that keep the box's shape) then Subdivision Surface."""
    bev = ob.modifiers.new("Bevel", "BEVEL")
    bev.width, bev.segments = width, d["soft_bevel"]
    sub = ob.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = sub.render_levels = d["soft"]
    return ob


def bevel(ob, width, segments):
    m = ob.modifiers.new("Bevel", "BEVEL")
    m.width, m.segments = width, segments
    return ob


def array(ob, count, offset, relative=False):
    m = ob.modifiers.new("Array", "ARRAY")
    m.count = count
    m.use_relative_offset, m.use_constant_offset = relative, not relative
    (m.relative_offset_displace if relative else m.constant_offset_displace)[:] = offset
    return ob


def group(root, parts):
    """Parents parts to root, keeping where they are: the piece moves as one."""
    for p in parts:
        p.parent = root
        p.matrix_parent_inverse = root.matrix_world.inverted()
    return root


def grid(name, coll, mat, centre, su, sv, rot, cell):
    """A gridded plane su x sv metres, cells about `cell`, rotated so its normal points inward."""
    nu, nv = max(1, round(su / cell)), max(1, round(sv / cell))
    return prim("grid", name, coll, mat, centre, scale=(su, sv, 1), rot=rot,
                x_subdivisions=nu, y_subdivisions=nv, size=1)


def cut(ob, lo, hi):
    """Deletes the faces whose centres lie in the box lo..hi (world), in edit mode; returns the
    opening's bounds (lo, hi) as the grid cut it."""
    me = ob.data
    o = ob.matrix_world.translation
    inside = [all(lo[k] <= (p.center + o)[k] <= hi[k] for k in range(3)) for p in me.polygons]
    pts = [me.vertices[v].co + o for p, s in zip(me.polygons, inside) if s for v in p.vertices]
    me.polygons.foreach_set("select", inside)
    select_only([ob], ob)
    bpy.context.scene.tool_settings.mesh_select_mode = (False, False, True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.delete(type="FACE")
    bpy.ops.object.mode_set(mode="OBJECT")
    return (Vector([min(p[k] for p in pts) for k in range(3)]),
            Vector([max(p[k] for p in pts) for k in range(3)]))


def join(objs, name):
    select_only(objs, objs[0])
    bpy.ops.object.join()
    ob = bpy.context.view_layer.objects.active
    ob.name = ob.data.name = name
    return ob


# --- the rooms ---------------------------------------------------------------------------------

def shell(i, ox, n_rooms, d, mats):
    """Room i's floor, ceiling and walls (one object, with the reveals of the door to room i-1),
    in the scene collection."""
    env = bpy.context.scene.collection
    cx, cy, cell = ox + ROOM_X / 2, ROOM_Y / 2, d["cell"]
    grid(f"Floor.R{i}", env, mats.wave_floor(), (cx, cy, 0), ROOM_X, ROOM_Y, (0, 0, 0), cell)
    grid(f"Ceiling.R{i}", env, mats.get("Ceiling", (0.85, 0.85, 0.83)), (cx, cy, ROOM_Z),
         ROOM_X, ROOM_Y, (math.pi, 0, 0), cell)
    paint = mats.get(f"Paint{i % 3}", [(0.78, 0.74, 0.66), (0.66, 0.72, 0.70),
                                      (0.80, 0.70, 0.62)][i % 3])
    h, q = ROOM_Z / 2, math.pi / 2
    south = grid("wall_s", env, paint, (cx, 0, h), ROOM_X, ROOM_Z, (-q, 0, 0), cell)
    north = grid("wall_n", env, paint, (cx, ROOM_Y, h), ROOM_X, ROOM_Z, (q, 0, 0), cell)
    west = grid("wall_w", env, paint, (ox, cy, h), ROOM_Z, ROOM_Y, (0, q, 0), cell)
    east = grid("wall_e", env, paint, (ox + ROOM_X, cy, h), ROOM_Z, ROOM_Y, (0, -q, 0), cell)
    cut(south, (ox + WINDOW_X[0], -1, WINDOW_Z[0]), (ox + WINDOW_X[1], 1, WINDOW_Z[1]))
    walls = [south, north, west, east]
    if i > 0:
        lo, hi = cut(west, (ox - 1, DOOR_Y[0], -1), (ox + 1, DOOR_Y[1], DOOR_TOP))
        # Close the gap between the two walls around the door: jambs, lintel, threshold.
        xm, ym, w, zt = ox - GAP / 2, (lo.y + hi.y) / 2, hi.y - lo.y, hi.z
        walls += [grid("jamb_a", env, paint, (xm, lo.y, zt / 2), GAP, zt, (-q, 0, 0), cell),
                  grid("jamb_b", env, paint, (xm, hi.y, zt / 2), GAP, zt, (q, 0, 0), cell),
                  grid("lintel", env, paint, (xm, ym, zt), GAP, w, (math.pi, 0, 0), cell),
                  grid("sill", env, mats.wave_floor(), (xm, ym, 0), GAP, w, (0, 0, 0), cell)]
    if i < n_rooms - 1:
        cut(east, (ox + ROOM_X - 1, DOOR_Y[0], -1), (ox + ROOM_X + 1, DOOR_Y[1], DOOR_TOP))
    join(walls, f"Walls.R{i}")


def sofa_like(name, coll, mats, fab, d, c, width, depth, n_cushions, facing):
    """A sofa or armchair of fabric `fab` facing +y (facing=1) or -y (-1): base on feet, seat
    cushions, back, arms, all soft boxes parented to the base, whose origin is the piece's
    centre."""
    x, y = c
    hx, hy = width / 2, depth / 2
    base = box(name, coll, fab, (x - hx, y - hy, 0.08), (x + hx, y + hy, 0.32))
    soft(base, d)
    feet = box(f"{name} feet", coll, mats.get("Wood", (0.35, 0.22, 0.12)),
               (x - hx + 0.04, y - hy + 0.04, LIFT), (x - hx + 0.1, y - hy + 0.1, 0.081))
    array(array(feet, 2, (width - 0.14, 0, 0)), 2, (0, depth - 0.14, 0))
    arm, back = 0.18, 0.2
    yb = y - facing * (hy - back / 2)            # the back's centre line
    parts = [feet, soft(box(f"{name} back", coll, fab, (x - hx + arm, yb - back / 2, 0.32),
                            (x + hx - arm, yb + back / 2, 0.82)), d)]
    for s in (-1, 1):
        xa = x + s * (hx - arm / 2)
        parts.append(soft(box(f"{name} arm{'LR'[s > 0]}", coll, fab,
                              (xa - arm / 2, y - hy, 0.32), (xa + arm / 2, y + hy, 0.62)), d))
    inner = width - 2 * arm
    w = inner / n_cushions
    y0, y1 = sorted((yb + facing * back / 2, y + facing * (hy - 0.02)))
    for k in range(n_cushions):
        xa = x - inner / 2 + (k + 0.5) * w
        parts.append(soft(box(f"{name} cushion{k}", coll, fab,
                              (xa - w / 2 + 0.01, y0, 0.32), (xa + w / 2 - 0.01, y1, 0.46)), d,
                          width=0.04))
    return group(base, parts)


def dining_chair(mats, d):
    """The chair every dining place instances: built once, in a collection outside the scene
    (the instances' source), facing +y, origin at the centre of its footprint on the floor."""
    src = collection("DiningChair")
    wood = mats.get("ChairWood", (0.48, 0.32, 0.18))
    seat = bevel(box("DiningChair seat", src, wood, (-0.225, -0.225, 0.43), (0.225, 0.225, 0.47)),
                 0.01, d["bevel"])
    legs = box("DiningChair legs", src, wood, (-0.21, -0.21, LIFT), (-0.17, -0.17, 0.43))
    array(array(legs, 2, (0.38, 0, 0)), 2, (0, 0.38, 0))
    back = bevel(box("DiningChair back", src, wood, (-0.225, -0.225, 0.47), (0.225, -0.19, 0.92)),
                 0.01, d["bevel"])
    for part in (legs, back):
        part.parent = seat
    bpy.context.scene.collection.children.unlink(src)
    return src


def furnish(i, ox, d, mats, chair_src):
    """Room i's furniture: one collection per piece (the solver's objects)."""
    tag = "" if i == 0 else f".R{i}"
    rng = random.Random(1000 + i)                  # the plant's leaves, fixed per room
    wood = mats.get("Wood", (0.35, 0.22, 0.12))
    # Living corner: sofa against the north wall, rug in front, side table with the lamp.
    sofa_rgb = [(0.22, 0.30, 0.45), (0.35, 0.38, 0.25), (0.45, 0.25, 0.30)][i % 3]
    sofa_like(f"Sofa{tag}", collection(f"Sofa{tag}"), mats,
              mats.get(f"SofaFabric{i % 3}", sofa_rgb), d, (ox + 2.1, 3.55), 2.0, 0.8, 2, -1)
    arm_c = collection(f"Armchair{tag}")
    sofa_like(f"Armchair{tag}", arm_c, mats, mats.get("ArmchairFabric", (0.58, 0.27, 0.17)), d,
              (ox + 1.2, 1.0), 0.85, 0.8, 1, 1)
    grid(f"Rug{tag}", collection(f"Rug{tag}"), mats.get("Rug", (0.62, 0.22, 0.20)),
         (ox + 2.1, 2.425, 0.004), 2.0, 1.05, (0, 0, 0), d["rug_cell"])
    side_c = collection(f"SideTable{tag}")
    bevel(box(f"SideTable{tag}", side_c, wood, (ox + 3.225, 3.375, LIFT), (ox + 3.675, 3.825, 0.5)),
          0.01, d["bevel"])
    lamp_c = collection(f"TableLamp{tag}")
    lx, ly, v = ox + 3.45, 3.6, d["round"]
    metal = mats.get("Metal", (0.30, 0.30, 0.30))
    lamp = prim("cylinder", f"TableLamp{tag}", lamp_c, metal, (lx, ly, 0.516),
                vertices=v, radius=0.08, depth=0.03)
    parts = [prim("cylinder", f"TableLamp stem{tag}", lamp_c, metal, (lx, ly, 0.65),
                  vertices=v // 2, radius=0.012, depth=0.24),
             prim("cone", f"TableLamp shade{tag}", lamp_c, mats.get("Shade", (0.90, 0.85, 0.70)),
                  (lx, ly, 0.81), vertices=v, radius1=0.17, radius2=0.10, depth=0.22,
                  end_fill_type="NOTHING"),
             prim("uv_sphere", f"TableLamp bulb{tag}", lamp_c,
                  mats.emission("Bulb", (1.0, 0.85, 0.6), 150.0), (lx, ly, 0.805),
                  segments=v, ring_count=v // 2, radius=0.035)]
    group(lamp, parts)
    # Dining: table, six instanced chairs, the pendant light above, Suzanne on the table.
    tx, ty = ox + 3.75, 1.6
    table_c = collection(f"DiningTable{tag}")
    table = bevel(box(f"DiningTable{tag}", table_c, wood, (tx - 0.7, ty - 0.4, 0.71),
                      (tx + 0.7, ty + 0.4, 0.75)), 0.01, d["bevel"])
    legs = box(f"DiningTable legs{tag}", table_c, wood, (tx - 0.645, ty - 0.345, LIFT),
               (tx - 0.595, ty - 0.295, 0.71))
    group(table, [array(array(legs, 2, (1.24, 0, 0)), 2, (0, 0.64, 0))])
    for k, (x, y, a) in enumerate([(3.4, 1.0, 0), (4.1, 1.0, 0), (3.4, 2.2, math.pi),
                                   (4.1, 2.2, math.pi), (2.8, 1.6, -math.pi / 2),
                                   (4.7, 1.6, math.pi / 2)]):
        chairs = collection(f"Chair{k}{tag}")
        bpy.ops.object.collection_instance_add(collection=chair_src.name, location=(ox + x, y, 0),
                                               rotation=(0, 0, a))
        inst = bpy.context.view_layer.objects.active
        inst.name = f"Chair{k}{tag}"
        for c in list(inst.users_collection):
            c.objects.unlink(inst)
        chairs.objects.link(inst)
    pend_c = collection(f"Pendant{tag}")
    shade = prim("cone", f"Pendant{tag}", pend_c, mats.get("Shade", (0.90, 0.85, 0.70)),
                 (tx, ty, 2.11), vertices=v, radius1=0.25, radius2=0.06, depth=0.22,
                 end_fill_type="NOTHING")
    cord = prim("cylinder", f"Pendant cord{tag}", pend_c, metal, (tx, ty, 2.4595),
                vertices=8, radius=0.006, depth=0.479)
    lamp = bpy.data.objects.new(f"PendantLight{tag}", bpy.data.lights.new(f"PendantLight{tag}",
                                                                         "POINT"))
    lamp.data.energy, lamp.data.shadow_soft_size = 80.0, 0.04
    lamp.data.color = (1.0, 0.88, 0.72)
    lamp.location = (tx, ty, 2.06)
    pend_c.objects.link(lamp)
    group(shade, [cord, lamp])
    suz_c = collection(f"Suzanne{tag}")
    bpy.ops.mesh.primitive_monkey_add(size=0.3, location=(tx, ty, 0))
    suz = bpy.context.view_layer.objects.active
    suz.name = suz.data.name = f"Suzanne{tag}"
    for c in list(suz.users_collection):
        c.objects.unlink(suz)
    suz_c.objects.link(suz)
    suz.data.materials.append(mats.get("Suzanne", (0.80, 0.58, 0.20)))
    suz.location.z = 0.752 - min(vtx.co.z for vtx in suz.data.vertices)
    sub = suz.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = sub.render_levels = d["monkey"]
    # Shelves of books against the west wall.
    shelf_c = collection(f"Shelves{tag}")
    sides = box(f"Shelves{tag}", shelf_c, wood, (ox + 0.03, 1.6, LIFT), (ox + 0.35, 1.62, 1.9))
    array(sides, 2, (0, 1.18, 0))
    boards = array(box(f"Shelves boards{tag}", shelf_c, wood, (ox + 0.04, 1.62, 0.09),
                       (ox + 0.34, 2.78, 0.11)), 5, (0, 0, 0.42))
    parts = [boards, box(f"Shelves back{tag}", shelf_c, wood, (ox + 0.02, 1.6, LIFT),
                         (ox + 0.03, 2.8, 1.9))]
    for k, (y0, thick, h, n, rel, rgb) in enumerate([
            (1.64, 0.030, 0.24, 12, 1.25, (0.60, 0.15, 0.10)),
            (2.12, 0.025, 0.28, 10, 1.30, (0.15, 0.30, 0.50)),
            (2.47, 0.040, 0.20, 6, 1.15, (0.75, 0.65, 0.35))]):
        book = box(f"Books{k}{tag}", shelf_c, mats.get(f"Book{k}", rgb),
                   (ox + 0.08, y0, 0.111), (ox + 0.30, y0 + thick, 0.111 + h))
        bevel(book, 0.004, d["bevel"])
        parts.append(array(array(book, n, (0, rel, 0), relative=True), 4, (0, 0, 0.42)))
    group(sides, parts)
    # A plant in the south-east corner: a pot, a stem, leaves of spheres (one mesh).
    plant_c = collection(f"Plant{tag}")
    px, py = ox + 4.6, 0.4
    pot = prim("cone", f"Plant{tag}", plant_c, mats.get("Pot", (0.62, 0.36, 0.24)),
               (px, py, 0.161), vertices=v, radius1=0.13, radius2=0.17, depth=0.32)
    stem = prim("cylinder", f"Plant stem{tag}", plant_c, mats.get("Stem", (0.25, 0.35, 0.12)),
                (px, py, 0.63), vertices=8, radius=0.015, depth=0.62)
    leaf = mats.get("Leaf", (0.15, 0.40, 0.12))
    leaves = []
    for k in range(14):
        a, r, z = rng.uniform(0, 2 * math.pi), rng.uniform(0.05, 0.2), rng.uniform(0.65, 1.2)
        leaves.append(prim("ico_sphere", f"leaf{k}", plant_c, leaf,
                           (px + r * math.cos(a), py + r * math.sin(a), z),
                           subdivisions=d["sphere"], radius=rng.uniform(0.07, 0.13)))
    group(pot, [stem, join(leaves, f"Plant leaves{tag}")])
    return arm_c


def lights_and_world(n_rooms):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("Sky")
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.45, 0.62, 0.90, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    world.color = (0.45, 0.62, 0.90)
    scene.world = world
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy, sun.data.angle = 3.0, math.radians(1.0)
    sun.data.color = (1.0, 0.95, 0.86)
    travel = Vector((0.3, 0.75, -0.55)).normalized()     # in through the south windows
    sun.rotation_euler = (-travel).to_track_quat("Z", "Y").to_euler()
    sun.location = (n_rooms * (ROOM_X + GAP) / 2, -3, 4)
    scene.collection.objects.link(sun)
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    cam.location = (4.6, 3.7, 1.6)
    look = Vector((1.6, 1.2, 0.8)) - cam.location
    cam.rotation_euler = look.to_track_quat("-Z", "Y").to_euler()
    cam.data.lens = 18
    scene.collection.objects.link(cam)
    scene.camera = cam


# --- size --------------------------------------------------------------------------------------

# Per level: Subdivision Surface levels of the upholstery (soft) and of Suzanne, Bevel segments
# of the upholstery and of the wooden pieces, the leaves' icosphere subdivisions, vertices round
# cylinders and cones, the rug's grid cell (m); and one room's furniture triangles at that level
# (measured; only used to pick the level, the walls' grid then takes the rest of the budget).
LEVELS = {
    1: dict(soft=1, soft_bevel=1, monkey=1, bevel=1, sphere=2, round=16, rug_cell=0.1,
            furniture=14132),
    2: dict(soft=2, soft_bevel=2, monkey=2, bevel=2, sphere=3, round=32, rug_cell=0.05,
            furniture=56500),
    3: dict(soft=3, soft_bevel=2, monkey=2, bevel=2, sphere=3, round=48, rug_cell=0.03,
            furniture=118006),
}


def plan(triangles):
    """(rooms, level): one room up to about 100k triangles, then more rooms (2 at 250k, 4 at 1M,
    6 at 2M), each at the finest level whose furniture takes at most 55 % of its share."""
    rooms = max(1, round(math.sqrt(triangles / 62500)))
    share = triangles / rooms
    level = max([1] + [k for k, v in LEVELS.items() if v["furniture"] <= 0.55 * share])
    return rooms, level


def detail(level, cell):
    return dict(LEVELS[level], level=level, cell=cell)


def count(depsgraph=None):
    """(triangles, mesh objects, instances) of the evaluated scene: each polygon of n corners is
    n - 2 triangles, every instance counted."""
    dg = depsgraph or bpy.context.evaluated_depsgraph_get()
    tris = meshes = instances = 0
    for inst in dg.object_instances:
        ob = inst.object
        if ob.type != "MESH":
            continue
        me = ob.data
        tris += len(me.loops) - 2 * len(me.polygons)
        if inst.is_instance:
            instances += 1
        else:
            meshes += 1
    return tris, meshes, instances


def shell_area(rooms):
    """A room's mean shell area without its window and doors (m^2), for the grid's cell size."""
    window = (WINDOW_X[1] - WINDOW_X[0]) * (WINDOW_Z[1] - WINDOW_Z[0])
    doors = (DOOR_Y[1] - DOOR_Y[0]) * DOOR_TOP * 2 * (rooms - 1) / rooms
    return 2 * ROOM_X * ROOM_Y + 2 * (ROOM_X + ROOM_Y) * ROOM_Z - window - doors


def build(triangles, materials):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    rooms, level = plan(triangles)
    mats = Materials(materials)
    d = detail(level, 0.25)
    chair = dining_chair(mats, d)
    # Furnish room 1 first: what its furniture costs sets the shells' grid, which takes the
    # rest of each room's share.
    movable = furnish(0, 0.0, d, mats, chair)
    furniture = count()[0]
    rest = max(triangles / rooms - furniture, 2000)
    d["cell"] = min(0.5, max(0.015, math.sqrt(2 * shell_area(rooms) / rest)))
    for i in range(1, rooms):
        furnish(i, i * (ROOM_X + GAP), d, mats, chair)
    for i in range(rooms):
        shell(i, i * (ROOM_X + GAP), rooms, d, mats)
    lights_and_world(rooms)
    arm = bpy.data.objects["Armchair"]
    scene["radiosity_move"] = {"object": movable.name,
                               "location": tuple(arm.location + Vector((MOVE["dx"], 0, 0))),
                               "rotation_z_deg": math.degrees(MOVE["turn"])}
    scene["interior"] = {"rooms": rooms, "level": level, "cell": round(d["cell"], 4),
                         "materials": materials, "target_triangles": triangles}
    scene.render.engine = "CYCLES"
    scene.render.bake.target = "VERTEX_COLORS"
    scene.view_settings.view_transform = "Standard"
    return rooms, d


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    a = parse(argv)
    target = 17000 if a.quick else a.triangles
    t = time.perf_counter()
    rooms, d = build(target, a.materials)
    tris, meshes, instances = count()
    seconds = time.perf_counter() - t
    out = os.path.abspath(a.out)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    bpy.context.preferences.filepaths.save_version = 0      # no .blend1 beside it
    bpy.ops.wm.save_as_mainfile(filepath=out)
    info = {"out": out, "triangles": tris, "target": target, "rooms": rooms,
            "mesh_objects": meshes, "instances": instances,
            "lights": sum(o.type == "LIGHT" for o in bpy.context.scene.objects),
            "level": d["level"], "cell": round(d["cell"], 4), "materials": a.materials,
            "seconds": round(seconds, 2), "blender": bpy.app.version_string}
    print("INTERIOR " + json.dumps(info), flush=True)


if __name__ == "__main__":
    main()
