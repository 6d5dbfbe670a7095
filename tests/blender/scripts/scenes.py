"""Test scenes, built identically in the tests and in the reference generator."""

import bpy

import rt_common as rt

FURNACE_RHO, FURNACE_E = 0.5, 1.0


def build_furnace(n=4):
    """Closed 2x2x2 box of six n x n inward-facing grids, each its own object, in two collections
    (one nested): rho=0.5 and emission 1 everywhere -> B = E/(1-rho) = 2 at every corner.
    Half the faces use Principled (diffuse part + emission), half Add(Diffuse, Emission)."""
    outer = rt.new_collection("Walls")
    inner = rt.new_collection("Caps", outer)
    p = rt.principled_material("Furnace Principled", (FURNACE_RHO,) * 3, (1, 1, 1), FURNACE_E)
    # Blender 4.0+ (Principled v2): the dielectric layer takes its share of the diffuse (0.963
    # by default: addon/radiosity/principled.py) and reflects it specularly, which no closed
    # form covers. Without it (Specular IOR Level 0) the Principled is the pure diffuse the
    # analytic furnace assumes, in Cycles and in the add-on alike.
    bsdf = [n for n in p.node_tree.nodes if n.type == "BSDF_PRINCIPLED"][0]
    if bsdf.inputs.get("Specular IOR Level") is not None:
        bsdf.inputs["Specular IOR Level"].default_value = 0.0
    # Blender 3.x: the Disney diffuse is Lambertian (seen along the normal) only at roughness
    # 0.4; at the default 0.5 it renders 1.006 times brighter (addon/radiosity/principled.py).
    if bpy.app.version < (4, 0, 0):
        bsdf.inputs["Roughness"].default_value = 0.4
    a = rt.add_diffuse_emission_material("Furnace Add", (FURNACE_RHO,) * 3, (1, 1, 1), FURNACE_E)
    s = 2.0
    # (origin, u, v) with u x v pointing out of the box [0,2]^3
    sides = {
        "floor": ((0, 0, 0), (0, s, 0), (s, 0, 0)),
        "ceiling": ((0, 0, s), (s, 0, 0), (0, s, 0)),
        "x0": ((0, 0, 0), (0, 0, s), (0, s, 0)),
        "x1": ((s, 0, 0), (0, s, 0), (0, 0, s)),
        "y0": ((0, 0, 0), (s, 0, 0), (0, 0, s)),
        "y1": ((0, s, 0), (0, 0, s), (s, 0, 0)),
    }
    objs = []
    for i, (name, (o, u, v)) in enumerate(sides.items()):
        verts, faces = rt.grid(o, v, u, n)      # v x u points inward
        coll = inner if name in ("floor", "ceiling") else (outer if i % 2 else None)
        objs.append(rt.mesh_object(name, verts, faces, coll, p if i % 2 else a))
    return objs


def build_diffuse_scene():
    """A 4x4 floor (rho 0.5), a 1x1 light (radiance 10) 2 above it facing down, and a coloured
    subdivided box on the floor. Open to a black world. ~800 corners."""
    rt.black_world()
    floor_mat = rt.diffuse_material("Floor", (0.5, 0.5, 0.5))
    box_mat = rt.diffuse_material("Box", (0.7, 0.35, 0.2))
    light_mat = rt.emission_material("Light", (1.0, 1.0, 1.0), 10.0)
    verts, faces = rt.grid((-2, -2, 0), (4, 0, 0), (0, 4, 0), 10)
    floor = rt.mesh_object("Floor", verts, faces, None, floor_mat)
    lv, lf = rt.grid((-0.5, -0.5, 2.0), (0, 1, 0), (1, 0, 0), 1)     # normal -z
    light = rt.mesh_object("Light", lv, lf, None, light_mat)
    coll = rt.new_collection("Props")
    bv, bf = rt.gridded_box([0.6, 0.3, 0.4], [0.5, 0.5, 0.4], 4)
    box = rt.mesh_object("Box", bv, bf, coll, box_mat)
    return [floor, light, box]
