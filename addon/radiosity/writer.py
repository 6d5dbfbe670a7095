"""Writing corner colours into original meshes."""
import bpy

from .gather import WriteTarget

COLOR_TYPE, COLOR_DOMAIN = "FLOAT_COLOR", "CORNER"


def ensure_color_attribute(me, name):
    """The FLOAT_COLOR/CORNER attribute `name`: reused, or (re)created; never duplicated."""
    attr = me.attributes.get(name)
    if attr is not None and (attr.data_type != COLOR_TYPE or attr.domain != COLOR_DOMAIN):
        me.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = me.color_attributes.new(name, COLOR_TYPE, COLOR_DOMAIN)
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


def resolve(target: WriteTarget):
    """Look the mesh up again by name (the bpy references taken at gather time may be stale
    after a modal job ran for a while)."""
    obj = bpy.data.objects.get(target.object_name)
    me = bpy.data.meshes.get(target.mesh_name)
    if obj is None or me is None or obj.data != me:
        return None
    return me


def write_all(items, attribute_name):
    """items: [(ObjectInput, rgba)]. Resolve every mesh first, then write; returns count."""
    resolved = []
    for obj_input, rgba in items:
        me = resolve(obj_input.target)
        if me is None:
            raise RuntimeError(f"object '{obj_input.name}' was deleted or changed during the bake")
        if len(me.loops) * 4 != len(rgba):
            raise RuntimeError(f"object '{obj_input.name}' changed its topology during the bake")
        resolved.append((me, rgba))
    for me, rgba in resolved:
        write_mesh(me, attribute_name, rgba)
    return len(resolved)
