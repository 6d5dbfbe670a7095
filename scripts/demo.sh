#!/usr/bin/env bash
# The README's demo: install the dependencies, build the add-on, then in Debian's Blender
# (headless) bake example_blends/box_room.blend, render it, move a box as the scene's
# radiosity_move says, re-bake incrementally, render again.
# Writes demo_output/before.png, after.png, stats.json (override with DEMO_OUT=dir,
# the preset with DEMO_PRESET=DRAFT|MEDIUM|HIGH). Skip the install step with DEMO_SKIP_INSTALL=1.
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$(pwd)
OUT=${DEMO_OUT:-$REPO/demo_output}
if [ "${DEMO_SKIP_INSTALL:-0}" != 1 ]; then
  RADIOSITY_SKIP_BPY=1 bash scripts/install_deps.sh
fi
bash scripts/build.sh
mkdir -p "$OUT"
# A private Blender user directory: installing the add-on leaves the user's own config alone.
export BLENDER_USER_CONFIG="$OUT/blender_user/config"
export BLENDER_USER_SCRIPTS="$OUT/blender_user/scripts"
export BLENDER_USER_DATAFILES="$OUT/blender_user/datafiles"
# Debian's Blender uses the system Python; a pyenv/venv python3 first on PATH would hand it the
# wrong standard library, so drop those directories from PATH for the Blender run.
CLEAN_PATH=$(printf '%s' "$PATH" | tr ':' '\n' | grep -v -e '/\.pyenv/' -e "^${VIRTUAL_ENV:-/nonexistent}" | paste -sd: -)
BLENDER=${BLENDER:-$(PATH=$CLEAN_PATH command -v blender)}
env -u PYTHONHOME -u PYTHONPATH PATH="$CLEAN_PATH" "$BLENDER" -b --factory-startup \
  "$REPO/example_blends/box_room.blend" --python-exit-code 1 \
  --python "$REPO/addon/tools/demo.py" -- \
  --zip "$REPO/build/radiosity.zip" --out "$OUT" --preset "${DEMO_PRESET:-MEDIUM}" \
  2>&1 | grep -v -e '^Read blend' -e '^Fra:' -e '^Blender quit'
echo "Pictures: $OUT/before.png $OUT/after.png   stats: $OUT/stats.json"
