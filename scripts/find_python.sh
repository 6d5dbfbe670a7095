#!/usr/bin/env bash
# bash scripts/find_python.sh 3.13 -> prints the path of a working CPython 3.13, or exits 1.
#
# One place that answers "where is the interpreter for Blender's other Python" for the build
# (native/python/extra_pythons.cmake), scripts/install_deps.sh and the bpy flavours of the
# add-on tests (tests/blender/conftest.py). Debian 12 ships only 3.11, so a 3.13 comes from
# $PYTHON313 (any X.Y: $PYTHON<X><Y>), from PATH, or from pyenv's versions (the project's
# machine image has one there). Each candidate is run: a pyenv shim for a version that is not
# active is on PATH but fails.
set -uo pipefail
want=${1:?usage: find_python.sh X.Y}
override_var="PYTHON${want//./}"
candidates=()
[ -n "${!override_var:-}" ] && candidates+=("${!override_var}")
command -v "python$want" >/dev/null 2>&1 && candidates+=("$(command -v "python$want")")
root=${PYENV_ROOT:-$HOME/.pyenv}
# Newest patch release first (3.13.10 before 3.13.9).
while IFS= read -r dir; do
  candidates+=("$dir/bin/python$want")
done < <(ls -d "$root/versions/$want".* "$root/versions/$want" 2>/dev/null | sort -V -r)
candidates+=("/usr/local/bin/python$want" "/usr/bin/python$want")
for c in "${candidates[@]}"; do
  [ -x "$c" ] || continue
  # Blender embeds the default (GIL) build: a free-threaded 3.13t has another ABI.
  if "$c" -c "import sys, sysconfig; sys.exit(sys.version_info[:2] != tuple(map(int, '$want'.split('.')))
                or bool(sysconfig.get_config_var('Py_GIL_DISABLED')))" >/dev/null 2>&1; then
    echo "$c"
    exit 0
  fi
done
exit 1
