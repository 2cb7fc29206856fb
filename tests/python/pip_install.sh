#!/usr/bin/env bash
# `pip install .` from the repository root into a fresh virtual environment,
# then `import gdof` and the pytest suite against that install (not the
# build tree): pip_install.sh WORK_DIR [PYTHON]. The build is lean: the
# libraries and the module only (pyproject.toml), both cores, through ccache
# when GDOF_LAUNCHER says so (GDOF_CXX: the compiler). Prints how long each
# step took.
set -euo pipefail
unset PYTHONPATH  # the installed module, never the build tree's
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
work="$1"
python="${2:-python3}"
rm -rf "$work"
mkdir -p "$work"
t0=$SECONDS
# The venv's base interpreter: the one the build's venv came from.
base="$("$python" -c 'import sys; print(getattr(sys, "_base_executable", sys.executable))')"
"$base" -m venv "$work/venv"
venv_python="$work/venv/bin/python"
"$venv_python" -m pip install -q --disable-pip-version-check --upgrade pip >/dev/null
# The compiler and launcher of the build under test: the libraries' files
# then compile with the same command lines, and ccache serves them.
args=()
if [[ -n "${GDOF_LAUNCHER:-}" ]]; then
  args+=("--config-settings=cmake.define.CMAKE_CXX_COMPILER_LAUNCHER=$GDOF_LAUNCHER")
fi
if [[ -n "${GDOF_CXX:-}" ]]; then
  args+=("--config-settings=cmake.define.CMAKE_CXX_COMPILER=$GDOF_CXX")
fi
t1=$SECONDS
CMAKE_BUILD_PARALLEL_LEVEL=2 "$venv_python" -m pip install -q --disable-pip-version-check \
  --config-settings=build-dir="$work/build" "${args[@]}" "$root"
t2=$SECONDS
"$venv_python" -m pip install -q --disable-pip-version-check -r "$root/tests/python/requirements.txt"
cd "$work"
"$venv_python" -c "import gdof, sys; print('gdof', gdof.__version__, 'from', gdof.__file__); sys.exit(0 if '$work/venv' in gdof.__file__ else 1)"
test -x "$work/venv/bin/gdof-submit"
# The OpenImageIO module ships in the wheel beside _gdof, and a PNG loads
# that one (not the build folder's).
pkg="$("$venv_python" -c 'import gdof, os; print(os.path.dirname(gdof.__file__))')"
test -f "$pkg/gdof_oiio.so"
LD_DEBUG=files "$venv_python" -c "
import gdof, numpy
gdof.write_image('$work/grey.png', gdof.Image.from_array(numpy.full((3, 4, 8), 0.5, numpy.float32), ['R', 'G', 'B']))
assert len(gdof.read_image('$work/grey.png')) == 1
" 2> "$work/ld_debug.txt"
grep -q "file=$pkg/gdof_oiio.so" "$work/ld_debug.txt"
t3=$SECONDS
"$venv_python" -m pytest -q -p no:cacheprovider --rootdir="$root/tests/python" "$root/tests/python"
t4=$SECONDS
echo "pip_install: venv $((t1 - t0)) s, pip install . $((t2 - t1)) s, test packages $((t3 - t2)) s, pytest $((t4 - t3)) s"
