"""Writing corner colours into original meshes."""
import bpy

from .baked_state import TOKEN_KEY
from .gather import WriteTarget

COLOR_TYPE, COLOR_DOMAIN = "FLOAT_COLOR", "CORNER"
BYTE_TYPE = "BYTE_COLOR"       # the optional sRGB copy for game export (core/srgb.py)


def ensure_color_attribute(me, name, data_type=COLOR_TYPE):
    """The `data_type`/CORNER attribute `name`: reused, or (re)created; never duplicated."""
    attr = me.attributes.get(name)
    if attr is not None and (attr.data_type != data_type or attr.domain != COLOR_DOMAIN):
        me.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = me.color_attributes.new(name, data_type, COLOR_DOMAIN)
    return attr


def _make_active(me, name):
    cas = me.color_attributes
    attr = cas.get(name)
    if attr is None:
        return
    # 3.4 .. 5.x all have color_attributes.active_color and render_color_index.
    cas.active_color = attr
    for i, ca in enumerate(cas):
        if ca.name == name:
            if hasattr(cas, "render_color_index"):
                cas.render_color_index = i
            break


def write_mesh(me, name, rgba):
    attr = ensure_color_attribute(me, name)
    attr.data.foreach_set("color", rgba)
    _make_active(me, name)
    me.update()


def read_colours(scene, name):
    """{object name: float32 (C,3) RGB} of every mesh object of `scene` that holds the colour
    attribute `name` (what a bake wrote: scripts, the demo, the benchmarks)."""
    import numpy as np
    out = {}
    for obj in scene.objects:
        if obj.type != "MESH" or name not in obj.data.color_attributes:
            continue
        buf = np.empty(len(obj.data.loops) * 4, dtype=np.float32)
        obj.data.color_attributes[name].data.foreach_get("color", buf)
        out[obj.name] = buf.reshape(-1, 4)[:, :3].copy()
    return out


def resolve(target: WriteTarget):
    """Look the mesh up again by name (the bpy references taken at gather time may be stale
    after a modal job ran for a while)."""
    # Targets are local data (linked library meshes are never written); the (name, None) key
    # asks for the local ID even when a linked one has the same name.
    obj = bpy.data.objects.get((target.object_name, None))
    me = bpy.data.meshes.get((target.mesh_name, None))
    if obj is None or me is None or obj.data != me:
        return None
    return me


def write_byte_copy(me, name, byte_rgba):
    """The sRGB byte copy (uint8 (C,4)); stored exactly (color_srgb takes byte / 255)."""
    from .core.srgb import bytes_to_color_srgb
    attr = ensure_color_attribute(me, name, BYTE_TYPE)
    attr.data.foreach_set("color_srgb", bytes_to_color_srgb(byte_rgba))


def write_all(items, attribute_name, byte_items=None, byte_name=None, token=None):
    """items: [(ObjectInput, rgba)]; byte_items: None or [(ObjectInput, uint8 (C,4))] written
    as `byte_name`; token: the bake's token, stored in each mesh (see baked_state). Resolve
    every mesh first, then write; returns count."""
    resolved = []
    bytes_of = {id(o): b for o, b in (byte_items or [])}
    for obj_input, rgba in items:
        me = resolve(obj_input.target)
        if me is None:
            raise RuntimeError(f"object '{obj_input.name}' was deleted or changed during the bake")
        if len(me.loops) * 4 != len(rgba):
            raise RuntimeError(f"object '{obj_input.name}' changed its topology during the bake")
        b = bytes_of.get(id(obj_input)) if byte_items is not None else None
        if byte_items is not None and (b is None or len(b) != len(me.loops)):
            raise RuntimeError(f"object '{obj_input.name}': no sRGB copy for its corners")
        resolved.append((me, rgba, b))
    for me, rgba, b in resolved:
        if b is not None:
            write_byte_copy(me, byte_name, b)   # first: the float attribute is made active last
        if token is not None:
            # Undo re-reads a mesh with its ID properties: the token stays with its colours.
            me[TOKEN_KEY] = token
        write_mesh(me, attribute_name, rgba)
    return len(resolved)


ADAPTIVE_COLLECTION = "Radiosity Adaptive"


def adaptive_name(object_name):
    return f"{object_name}.radiosity"


def _adaptive_collection(scene):
    coll = bpy.data.collections.get(ADAPTIVE_COLLECTION)
    if coll is None:
        coll = bpy.data.collections.new(ADAPTIVE_COLLECTION)
    if coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    return coll


def write_adaptive(objects, leaf_meshes, attribute_name, scene=None):
    """One new mesh object per baked object from its leaf elements (native leaf_mesh dicts),
    placed like the original (which is not touched), in the 'Radiosity Adaptive' collection,
    colours per corner (each element's value on all its corners). Re-baking replaces it.
    Returns the objects' names."""
    import numpy as np
    from .gather import ADAPTIVE_TAG
    scene = scene or bpy.context.scene
    coll = _adaptive_collection(scene)
    names = []
    for obj_input, lm in zip(objects, leaf_meshes):
        if lm is None or obj_input.target is None:
            continue
        m = np.asarray(obj_input.matrix if obj_input.matrix is not None else np.eye(4), float)
        verts = np.asarray(lm["vertices"], float)
        local = (verts - m[:3, 3]) @ np.linalg.inv(m[:3, :3]).T
        totals = np.asarray(lm["loop_totals"], np.int64)
        cv = np.asarray(lm["corner_verts"], np.int64)
        starts = np.concatenate([[0], np.cumsum(totals)[:-1]]) if len(totals) else totals
        faces = [cv[s:s + t].tolist() for s, t in zip(starts, totals)]
        name = adaptive_name(obj_input.name)
        me = bpy.data.meshes.new(name)
        me.from_pydata(local.tolist(), [], faces)
        me.update()
        vals = np.asarray(lm["values"], np.float32)
        rgba = np.ones((len(cv), 4), np.float32)
        rgba[:, :3] = np.repeat(vals, totals, axis=0)
        write_mesh(me, attribute_name, rgba.ravel())
        # Which input polygon each element subdivides (for scripts and the tests).
        src = me.attributes.new("radiosity_source_face", "INT", "FACE")
        src.data.foreach_set("value", np.asarray(lm["source_face"], np.int32))
        ob = bpy.data.objects.get(name)
        if ob is not None and ADAPTIVE_TAG in ob.keys():
            old = ob.data
            ob.data = me
            if old.users == 0:
                bpy.data.meshes.remove(old)
        else:
            ob = bpy.data.objects.new(name, me)
            coll.objects.link(ob)
        ob[ADAPTIVE_TAG] = obj_input.name
        import mathutils
        ob.matrix_world = mathutils.Matrix([list(map(float, r)) for r in m])
        names.append(ob.name)
    return names
