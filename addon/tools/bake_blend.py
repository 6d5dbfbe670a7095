"""Bake a .blend from the command line.

    blender -b FILE.blend --python addon/tools/bake_blend.py -- [--preset HIGH]
            [--error-threshold 0.02] [--attribute NAME] [--full] [--out OUT.blend]

Uses the `radiosity` add-on if it is already enabled (installed from the zip); otherwise it puts
the directory with the add-on package (--addon-dir, else build/addon/stage, else addon/) on
sys.path and registers it for this session only. Saves to --out (default: FILE
itself) and prints the last_stats JSON on a line starting with "RADIOSITY_STATS ".
Exit code 1 when the bake fails (with `--python-exit-code 1`, or via SystemExit here).
"""
import argparse
import os
import sys

import bpy


def parse(argv):
    argv = argv[argv.index("--") + 1:] if "--" in argv else []
    p = argparse.ArgumentParser(prog="bake_blend.py")
    p.add_argument("--preset", choices=("DRAFT", "MEDIUM", "HIGH", "CUSTOM"))
    p.add_argument("--error-threshold", type=float)
    p.add_argument("--attribute")
    p.add_argument("--full", action="store_true")
    p.add_argument("--out")
    p.add_argument("--file", help="open this .blend first (for the bpy module, which has no "
                                  "file argument)")
    p.add_argument("--addon-dir", help="directory that holds the radiosity/ package")
    return p.parse_args(argv)


def addon_dirs(explicit):
    """Where to look for radiosity/: --addon-dir, the build's staging dir (has the native
    module), the source tree (no native module unless copied there)."""
    if explicit:
        return [explicit]
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    return [os.path.join(repo, "build", "addon", "stage"), os.path.dirname(here)]


def ensure_addon(explicit_dir):
    """The enabled add-on if there is one, else the source tree's package."""
    if hasattr(bpy.types.Scene, "radiosity") and hasattr(bpy.ops, "radiosity"):
        return
    import addon_utils
    if any(m.__name__ == "radiosity" for m in addon_utils.modules()):
        if addon_utils.enable("radiosity", default_set=False) is not None:
            return
    dirs = [d for d in addon_dirs(explicit_dir)
            if os.path.isfile(os.path.join(d, "radiosity", "__init__.py"))]
    if not dirs:
        raise SystemExit(f"radiosity add-on not enabled and not found in {addon_dirs(explicit_dir)}")
    sys.path.insert(0, os.path.abspath(dirs[0]))
    import radiosity
    radiosity.register()


def main():
    args = parse(sys.argv)
    if args.file:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.file))
    ensure_addon(args.addon_dir)
    props = bpy.context.scene.radiosity
    if args.preset:
        props.preset = args.preset
    if args.error_threshold is not None:
        props.error_threshold = args.error_threshold
    if args.attribute is not None:
        props.attribute_name = args.attribute
    try:
        result = bpy.ops.radiosity.bake(full=args.full)
    except RuntimeError as exc:         # ERROR report
        print(f"RADIOSITY_ERROR {exc}", file=sys.stderr)
        raise SystemExit(1)
    if "FINISHED" not in result:
        raise SystemExit(1)
    out = args.out or bpy.data.filepath
    if not out:
        print("RADIOSITY_ERROR no --out given and the file was never saved", file=sys.stderr)
        raise SystemExit(1)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(out), copy=bool(args.out))
    print("RADIOSITY_STATS " + props.last_stats, flush=True)


main()
