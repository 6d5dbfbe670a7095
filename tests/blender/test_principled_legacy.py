"""Blender 3.x Principled BSDF: its Disney diffuse lobe is brighter than a Lambertian one.

Cycles 3.x gives the Principled BSDF Disney's diffuse, whose retro-reflection grows with
Roughness; seen along the normal (as Cycles bakes a corner) under diffuse light a matte
Principled reflects 0.976 + 0.0595 x roughness of its Base Color, and in a closed room the
interreflection makes more of it. addon/radiosity/principled.py measures that factor with a small
Cycles bake per parameter set. This file is both the test and the script it runs in Blender:

    blender -b --factory-startup --python tests/blender/test_principled_legacy.py -- \
        --zip build/radiosity.zip [--spec 0.5] [--spp 512] [--alt '{"name": {"1.0": k, ...}}']
    blender -b --factory-startup --python tests/blender/test_principled_legacy.py -- --study

(tests/blender/scripts on PYTHONPATH; --alt also bakes the room with other constant factors per
roughness, --study prints the measurements behind the choice of factor: quads under a white
world and spheres of the material lit from inside, bench/results/principled_legacy.md.)

In Blender 3.x the test checks (1) the add-on's factors against the lobe's closed form along the
normal under uniform light (roughness 0, 0.5, 1), (2) that Cycles' diffuse is Base Color x that
factor for a coloured base, (3) a closed room (floor, ceiling and walls of matte Principled
materials at roughness 1 and 0.5, a Diffuse BSDF wall, a box, an area light): each surface's mean over
its corners within ROOM_TOL of a Cycles COMBINED bake (glossy off, Specular 0), and (4) that the
old Lambertian reading of the same room misses by more than that. In Blender 4.0+ (Principled v2,
a Lambertian diffuse) it runs the room with Specular IOR Level 0 (a diffuse factor of about 1,
measured by principled.py as before): the same room, the same tolerance, against that version's
Cycles.
"""
import json
import os
import time

HERE = os.path.abspath(__file__)
ROOM_TOL = 0.03        # |ours / Cycles - 1| of each surface's corner mean
FACTOR_TOL = 0.003     # measured factor against the closed form (bake noise about 0.1 %)
# Disney's diffuse seen along the normal under uniform light: 1 - 1/42 + roughness * 5/84.
CLOSED_FORM = (1.0 - 1.0 / 42.0, 5.0 / 84.0)


def closed_form(roughness):
    return CLOSED_FORM[0] + CLOSED_FORM[1] * roughness


# --- pytest side -------------------------------------------------------------------------------

def test_principled_room_matches_cycles(run_blender):
    import pytest

    r = run_blender(HERE)
    assert r["ok"], r["_log"]
    if r["fake"]:
        pytest.skip("stand-in native module: no accuracy to check")
    legacy = (f"; closed form { {k: round(closed_form(float(k)), 4) for k in r['factors']} }; "
              f"coloured base / base {r['coloured']}") if r["legacy"] else ""
    print(f"\n[{r['_flavour']} {r['version']}] factors by roughness {r['factors']}{legacy}; room "
          f"ours/Cycles {r['room']}; Lambertian reading {r.get('lambert')}; Cycles "
          f"{r['cycles_seconds']} s, ours {r['seconds']:.1f} s")
    if r["legacy"]:
        for rough, f in r["factors"].items():
            assert abs(f - closed_form(float(rough))) <= FACTOR_TOL, (rough, f)
        # Cycles' diffuse scales with Base Color: one factor per parameter set, measured white.
        for got in r["coloured"]:
            assert abs(got - r["factors"]["1.0"]) <= FACTOR_TOL, r["coloured"]
    for name, ratio in r["room"].items():
        assert abs(ratio - 1.0) <= ROOM_TOL, (name, r["room"])
    if r["legacy"]:
        # The room tells the readings apart: read as Lambertian, the rough surfaces miss.
        worst = max(abs(r["lambert"][n] - 1.0) for n in r["rough_surfaces"])
        assert worst > ROOM_TOL, r["lambert"]


# --- Blender side ------------------------------------------------------------------------------

def _principled_node(mat):
    return next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")


def _matte(rt, name, base, roughness, spec, **inputs):
    """Principled BSDF of `base` and `roughness`, its specular level `spec` (3.x Specular,
    4.0+ Specular IOR Level; both 0.5 by default) and other `inputs` by name."""
    mat = rt.principled_material(name, base)
    p = _principled_node(mat)
    p.inputs["Roughness"].default_value = roughness
    (p.inputs.get("Specular IOR Level") or p.inputs["Specular"]).default_value = spec
    for key, value in inputs.items():
        p.inputs[key].default_value = value
    return mat


def _cycles(bpy, spp):
    c = bpy.context.scene.cycles
    bpy.context.scene.render.engine = "CYCLES"
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 1
    for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces"):
        setattr(c, attr, 64)
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0         # Filter Glossy blurs glossy seen after a diffuse bounce: a bias
    bpy.context.scene.render.bake.target = "VERTEX_COLORS"


def _cycles_bake(bpy, np, objs, glossy=False):
    """COMBINED bake (glossy pass off unless asked) of `objs`: per object its corners (C, 3)."""
    for o in bpy.context.scene.objects:
        o.select_set(False)
    for o in objs:
        attr = o.data.color_attributes.new("CyclesRef", "FLOAT_COLOR", "CORNER")
        o.data.color_attributes.active_color = attr
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]
    passes = {"EMIT", "DIRECT", "INDIRECT", "DIFFUSE", "TRANSMISSION"} | ({"GLOSSY"} if glossy else set())
    bpy.ops.object.bake(type="COMBINED", pass_filter=passes)
    out = {}
    for o in objs:
        attr = o.data.color_attributes["CyclesRef"]
        buf = np.empty(len(o.data.loops) * 4, np.float32)
        attr.data.foreach_get("color", buf)
        out[o.name] = buf.reshape(-1, 4)[:, :3].astype(np.float64)
        o.data.color_attributes.remove(attr)
    return out


def _white_world(bpy, rt, value):
    world = rt.node_world("Uniform")
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (value, value, value, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = world


def _sheet(rt, name, mat, n=8):
    verts, faces = rt.grid((-0.5, -0.5, 0.0), (1, 0, 0), (0, 1, 0), n)
    return rt.mesh_object(name, verts, faces, material=mat)


def _rect(rt, name, origin, u, v, nu, nv, mat):
    """nu x nv quads over origin + [0,1]u + [0,1]v, normal u x v."""
    import numpy as np
    o, u, v = (np.asarray(x, float) for x in (origin, u, v))
    verts = [o + (i / nu) * u + (j / nv) * v for j in range(nv + 1) for i in range(nu + 1)]
    faces = [(j * (nu + 1) + i, j * (nu + 1) + i + 1, (j + 1) * (nu + 1) + i + 1,
              (j + 1) * (nu + 1) + i) for j in range(nv) for i in range(nu)]
    return rt.mesh_object(name, verts, faces, material=mat)


# Room 4 x 3 x 2.5 m, normals inward: (name, origin, u, v, quads along u and v, base, roughness);
# roughness None is a Diffuse BSDF (the control: its light is only what the room sends it).
W, D, H = 4.0, 3.0, 2.5
ROOM = (
    ("Floor", (-W / 2, -D / 2, 0), (W, 0, 0), (0, D, 0), 8, 6, (0.6, 0.5, 0.4), 1.0),
    ("Ceiling", (-W / 2, D / 2, H), (W, 0, 0), (0, -D, 0), 8, 6, (0.8, 0.8, 0.8), 0.5),
    ("WallXm", (-W / 2, -D / 2, 0), (0, D, 0), (0, 0, H), 6, 5, (0.8, 0.8, 0.75), 1.0),
    ("WallXp", (W / 2, D / 2, 0), (0, -D, 0), (0, 0, H), 6, 5, (0.7, 0.3, 0.2), 1.0),
    ("WallYm", (-W / 2, -D / 2, 0), (0, 0, H), (W, 0, 0), 8, 5, (0.5, 0.6, 0.7), 0.5),
    ("WallYp", (W / 2, D / 2, 0), (0, 0, H), (-W, 0, 0), 8, 5, (0.7, 0.7, 0.7), None),
)
BOX = ((0.8, 0.4, 0.4 + 1e-3), (0.4, 0.4, 0.4), (0.3, 0.6, 0.3), 1.0)   # lifted a hair
# A 1 x 1 m area light facing down 10 cm under the ceiling: one-sided, so the ceiling has no
# hot spot that Cycles' indirect paths would find by chance (noise).
LAMP = ((0.0, 0.3, H - 0.1), 1.0, 300.0)


def _build_room(bpy, rt, spec):
    rt.black_world()
    objs, rough = [], []
    for name, origin, u, v, nu, nv, base, roughness in ROOM:
        mat = (rt.diffuse_material(name, base) if roughness is None
               else _matte(rt, name, base, roughness, spec))
        objs.append(_rect(rt, name, origin, u, v, nu, nv, mat))
        if roughness == 1.0:
            rough.append(name)
    centre, half, base, roughness = BOX
    bv, bf = rt.gridded_box(centre, half, 2)
    objs.append(rt.mesh_object("Box", bv, bf, material=_matte(rt, "Box", base, roughness, spec)))
    rough.append("Box")
    location, size, power = LAMP
    light = bpy.data.lights.new("Lamp", "AREA")
    light.shape, light.size, light.energy = "SQUARE", size, power
    rt.link(bpy.data.objects.new("Lamp", light)).location = location
    return objs, rough


def _bake_ratios(rt, objs, ref):
    ok, err, reports = rt.bake(full=True)
    if not ok:
        raise RuntimeError(f"bake failed: {err} {reports}")
    return {o.name: round(float(rt.corner_colors(o)[:, :3].mean() / ref[o.name].mean()), 4)
            for o in objs}, rt.last_stats()


def _study(bpy, np, rt):
    """The measurements bench/results/principled_legacy.md quotes (Blender 3.x, no add-on)."""
    import bmesh
    rt.reset()
    _cycles(bpy, 256)
    _white_world(bpy, rt, 1.0)
    sheet = _sheet(rt, "Sheet", None)
    rows = {}
    for label, mat, glossy in (
            [("diffuse", rt.diffuse_material("d", (1, 1, 1)), False)]
            + [(f"principled r{x}", _matte(rt, f"p{x}", (1, 1, 1), x, 0.5), False)
               for x in (0.0, 0.25, 0.5, 0.75, 1.0)]
            + [("principled r1 specular 0", _matte(rt, "s0", (1, 1, 1), 1.0, 0.0), False),
               ("principled r1 base (0.8,0.5,0.2), / base", _matte(rt, "c", (0.8, 0.5, 0.2), 1.0, 0.5), False),
               ("principled r1 sheen 1", _matte(rt, "sh", (1, 1, 1), 1.0, 0.5, Sheen=1.0), False),
               ("principled r1 sheen 1 base (0.8,0.5,0.2), / base",
                _matte(rt, "shc", (0.8, 0.5, 0.2), 1.0, 0.5, Sheen=1.0), False),
               ("principled r1 clearcoat 1", _matte(rt, "cc", (1, 1, 1), 1.0, 0.5, Clearcoat=1.0), False),
               ("principled r1 metallic 0.5", _matte(rt, "me", (1, 1, 1), 1.0, 0.5, Metallic=0.5), False),
               ("principled r1 subsurface 0.5", _matte(rt, "ss", (1, 1, 1), 1.0, 0.5, Subsurface=0.5), False),
               ("principled r1 glossy pass on", _matte(rt, "g1", (1, 1, 1), 1.0, 0.5), True),
               ("principled r0.5 glossy pass on", _matte(rt, "g5", (1, 1, 1), 0.5, 0.5), True)]):
        sheet.data.materials.clear()
        sheet.data.materials.append(mat)
        v = _cycles_bake(bpy, np, [sheet], glossy)["Sheet"].mean(axis=0)
        if "/ base" in label:
            v = v / np.array([0.8, 0.5, 0.2])
        rows[f"sheet under a white world: {label}"] = [round(float(x), 4) for x in v]
        print(label, rows[f"sheet under a white world: {label}"], flush=True)
    bpy.data.objects.remove(sheet, do_unlink=True)
    # Furnace: an icosphere (642 vertices) of the material, normals inward, emitting 1 (a
    # Lambertian rho gives 1 / (1 - rho)). Fitting B = 1 + rho k_out / (1 - rho k_tr) to two
    # rhos separates the output's factor k_out from the transport's k_tr.
    _white_world(bpy, rt, 0.0)
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=3, radius=1.0)
    bmesh.ops.reverse_faces(bm, faces=bm.faces[:])
    me = bpy.data.meshes.new("Sphere")
    bm.to_mesh(me)
    bm.free()
    sphere = rt.link(bpy.data.objects.new("Sphere", me))
    for rho in (0.5, 0.8):
        for x in (None, 0.0, 0.5, 1.0):
            if x is None:
                mat = rt.add_diffuse_emission_material(f"d{rho}", (rho,) * 3, (1, 1, 1), 1.0)
            else:
                mat = _matte(rt, f"f{rho}{x}", (rho,) * 3, x, 0.0)
                p = _principled_node(mat)
                p.inputs["Emission"].default_value = (1, 1, 1, 1)
                p.inputs["Emission Strength"].default_value = 1.0
            me.materials.clear()
            me.materials.append(mat)
            b = float(_cycles_bake(bpy, np, [sphere])["Sphere"].mean())
            label = f"furnace rho {rho} " + ("diffuse" if x is None else f"principled r{x}")
            rows[label] = round(b, 4)
            print(label, rows[label], flush=True)
    # The specular lobe's share of the transport (not modelled): Add(Diffuse 0.8 + Emission 1,
    # Principled with a black base): the bake (glossy off) is 1 + 0.8 / (1 - 0.8 - g), g the
    # albedo of the specular lobe (Specular 0.5) under this light; with Filter Glossy off and at
    # its default 1 (which blurs the lobe after a diffuse bounce).
    for x, blur in ((1.0, 0.0), (0.5, 0.0), (1.0, 1.0), (0.5, 1.0)):
        bpy.context.scene.cycles.blur_glossy = blur
        mat = rt.add_diffuse_emission_material(f"g{x}", (0.8,) * 3, (1, 1, 1), 1.0)
        nt = mat.node_tree
        first = next(n for n in nt.nodes if n.type == "ADD_SHADER")
        out = next(n for n in nt.nodes if n.type == "OUTPUT_MATERIAL")
        p = nt.nodes.new("ShaderNodeBsdfPrincipled")
        p.inputs["Base Color"].default_value = (0, 0, 0, 1)
        p.inputs["Roughness"].default_value = x
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(first.outputs[0], add.inputs[0])
        nt.links.new(p.outputs[0], add.inputs[1])
        nt.links.new(add.outputs[0], out.inputs["Surface"])
        me.materials.clear()
        me.materials.append(mat)
        b = float(_cycles_bake(bpy, np, [sphere])["Sphere"].mean())
        label = f"furnace diffuse 0.8 + black principled r{x}, filter glossy {blur}: specular albedo g"
        rows[label] = round(1.0 - 0.8 - 0.8 / (b - 1.0), 4)
        print(label, rows[label], flush=True)
    rt.result(ok=True, study=rows)


def _main():
    import bpy
    import numpy as np
    import rt_common as rt

    if "--study" in rt.script_args():
        _study(bpy, np, rt)
        return
    spec = float(rt.arg("--spec", "0"))
    spp = int(rt.arg("--spp", "512"))
    alt = json.loads(rt.arg("--alt", "{}"))
    rt.setup()
    from radiosity import principled
    legacy = bpy.app.version < (4, 0, 0)
    out = {"ok": False, "fake": rt.native_is_fake(), "version": bpy.app.version_string,
           "legacy": legacy, "spec": spec, "spp": spp}
    _cycles(bpy, spp)
    out["factors"] = {}
    for x in (0.0, 0.5, 1.0):
        mat = _matte(rt, f"factor {x}", (0.3, 0.5, 0.7), x, spec)
        out["factors"][str(x)] = round(float(principled.diffuse_factor(_principled_node(mat))[0]), 5)
    if legacy:
        # A coloured base under a uniform white world, Cycles' own bake: radiance / base.
        _white_world(bpy, rt, 1.0)
        base = np.array([0.8, 0.5, 0.2])
        sheet = _sheet(rt, "Sheet", _matte(rt, "coloured", tuple(base), 1.0, 0.5))
        got = _cycles_bake(bpy, np, [sheet])["Sheet"].mean(axis=0) / base
        out["coloured"] = [round(float(g), 4) for g in got]
        bpy.data.objects.remove(sheet, do_unlink=True)
    objs, rough = _build_room(bpy, rt, spec)
    t0 = time.perf_counter()
    ref = _cycles_bake(bpy, np, objs)
    out["cycles_seconds"] = round(time.perf_counter() - t0, 2)
    bpy.context.scene.radiosity.preset = "HIGH"
    out["room"], stats = _bake_ratios(rt, objs, ref)
    out["seconds"] = stats["seconds"]
    out["rough_surfaces"] = rough
    out["cycles_means"] = {k: round(float(v.mean()), 4) for k, v in ref.items()}
    measured = principled.diffuse_factor
    try:
        if legacy:
            principled.diffuse_factor = lambda node: np.ones(3)      # the Lambertian reading
            out["lambert"] = _bake_ratios(rt, objs, ref)[0]
        for label, table in alt.items():
            principled.diffuse_factor = (lambda node, t=table: np.full(
                3, float(t[str(round(float(node.inputs["Roughness"].default_value), 3))])))
            out[f"alt {label}"] = _bake_ratios(rt, objs, ref)[0]
    finally:
        principled.diffuse_factor = measured
    out["ok"] = True
    rt.result(**out)


if __name__ == "__main__":
    _main()
