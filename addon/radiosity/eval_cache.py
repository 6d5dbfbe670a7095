"""Keys for what Cycles evaluated (textures.py, world.py), so a live re-bake after a move does
not bake the same textures or render the same world again.

A key is a digest of what the evaluation reads: the node trees (every node's settings and input
values, the links, node groups followed, images by name, file, size and dirty state), and for
textures the evaluated mesh's arrays (positions, topology, material indices, UVs, colour
attributes) and, when a material reads positions in world space, the object's matrix.
Limits: an image whose pixels are painted in this session without being saved changes its key
only through its dirty flag (a second paint stroke bakes nothing new); drivers and animation
are seen through their current values.
"""
import hashlib

import numpy as np

_LIMIT = 64
_cache = {}


def get(key):
    return _cache.get(key)


def put(key, value):
    if key in _cache:
        _cache.pop(key)
    elif len(_cache) >= _LIMIT:
        _cache.pop(next(iter(_cache)))
    _cache[key] = value


def clear():
    _cache.clear()


_SIMPLE = {"BOOLEAN", "INT", "FLOAT", "STRING", "ENUM"}
_SKIP = {"rna_type", "name", "label", "location", "width", "height", "select", "show_options",
         "show_preview", "hide", "show_texture", "color", "use_custom_color", "dimensions",
         "width_hidden", "bl_idname", "bl_label", "bl_description", "bl_icon", "bl_static_type",
         "bl_width_default", "bl_width_min", "bl_width_max", "bl_height_default",
         "bl_height_min", "bl_height_max", "location_absolute", "warning_propagation"}


def _value(v):
    try:
        return tuple(v) if not isinstance(v, str) else v
    except TypeError:
        return v


def _image_key(img):
    if img is None:
        return None
    return (img.name_full, img.filepath, tuple(img.size), bool(img.is_dirty), img.source,
            img.packed_file.size if img.packed_file is not None else 0,
            img.colorspace_settings.name)


def tree_key(tree, h=None, depth=0, seen=None):
    """Digest (hexdigest) of a node tree's content, node groups followed."""
    top = h is None
    h = h or hashlib.blake2b(digest_size=20)
    seen = set() if seen is None else seen
    if tree is None or depth > 16:
        h.update(b"-")
        return h.hexdigest() if top else None
    for node in tree.nodes:
        h.update(f"N|{node.bl_idname}|{node.name}|{getattr(node, 'mute', False)}".encode())
        for prop in node.bl_rna.properties:
            pid = prop.identifier
            if pid in _SKIP:
                continue
            if prop.type in _SIMPLE:
                h.update(f"{pid}={_value(getattr(node, pid, None))!r}".encode())
            elif prop.type == "POINTER" and pid == "image":
                h.update(repr(_image_key(getattr(node, "image", None))).encode())
            elif prop.type == "POINTER" and pid == "object":
                o = getattr(node, "object", None)
                h.update(repr(None if o is None else (o.name_full, tuple(map(tuple, o.matrix_world)))).encode())
        for sock in node.inputs:
            if hasattr(sock, "default_value"):
                h.update(f"I|{sock.identifier}={_value(sock.default_value)!r}".encode())
        if node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
            if node.node_tree.name_full not in seen:
                seen.add(node.node_tree.name_full)
                tree_key(node.node_tree, h, depth + 1, seen)
    for link in tree.links:
        h.update(f"L|{link.from_node.name}|{link.from_socket.identifier}|{link.to_node.name}|"
                 f"{link.to_socket.identifier}|{getattr(link, 'is_muted', False)}".encode())
    return h.hexdigest() if top else None


_WORLD_SPACE_NODES = {"ShaderNodeNewGeometry", "ShaderNodeObjectInfo", "ShaderNodeVectorTransform",
                      "ShaderNodeTexCoord", "ShaderNodeTangent", "ShaderNodeWireframe",
                      "ShaderNodeAmbientOcclusion", "ShaderNodeBevel", "ShaderNodeLightPath",
                      "ShaderNodeLayerWeight", "ShaderNodeFresnel", "ShaderNodeCameraData"}


def reads_placement(tree, depth=0):
    """Whether a material may depend on where its object is (world positions, other objects,
    the view): then a move needs a new evaluation."""
    if tree is None or depth > 16:
        return False
    for node in tree.nodes:
        if node.bl_idname in _WORLD_SPACE_NODES:
            if node.bl_idname == "ShaderNodeTexCoord" and node.object is None and not any(
                    s.is_linked for s in node.outputs
                    if s.identifier in ("Window", "Camera", "Reflection", "Normal")):
                continue    # Generated, UV, Object (own) coordinates move with the object
            return True
        if node.bl_idname == "ShaderNodeGroup" and reads_placement(node.node_tree, depth + 1):
            return True
    return False


def mesh_key(me, h, exclude_prefix=None):
    """The evaluated mesh's arrays a texture can read (attributes whose name starts with
    `exclude_prefix`, our own output, left out)."""
    nv, nf, nc = len(me.vertices), len(me.polygons), len(me.loops)
    for coll, attr, n, width, dtype in ((me.vertices, "co", nv, 3, np.float32),
                                        (me.polygons, "loop_total", nf, 1, np.int32),
                                        (me.polygons, "material_index", nf, 1, np.int32),
                                        (me.loops, "vertex_index", nc, 1, np.int32)):
        a = np.empty(n * width, dtype)
        if n:
            coll.foreach_get(attr, a)
        h.update(a.tobytes())
    for uv in me.uv_layers:
        a = np.empty(nc * 2, np.float32)
        if nc:
            uv.data.foreach_get("uv", a)
        h.update(uv.name.encode())
        h.update(a.tobytes())
    for attr in me.attributes:
        if attr.name.startswith(".") or (exclude_prefix and attr.name.startswith(exclude_prefix)) \
                or attr.data_type not in ("FLOAT_COLOR", "BYTE_COLOR", "FLOAT",
                                                                "FLOAT_VECTOR", "INT"):
            continue
        n = len(attr.data)
        field = {"FLOAT_COLOR": ("color", 4), "BYTE_COLOR": ("color", 4), "FLOAT": ("value", 1),
                 "FLOAT_VECTOR": ("vector", 3), "INT": ("value", 1)}[attr.data_type]
        a = np.empty(n * field[1], np.int32 if attr.data_type == "INT" else np.float32)
        if n:
            attr.data.foreach_get(field[0], a)
        h.update(f"{attr.name}|{attr.domain}".encode())
        h.update(a.tobytes())
