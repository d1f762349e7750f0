#!/usr/bin/env bash
# Installs the built Python package (build/python/groundsim) into a venv,
# creating the venv if it does not exist. The venv sees Debian's packages
# (--system-site-packages), so numpy (and matplotlib, pytest) come from apt.
#   scripts/python-install.sh VENV [BUILD_PYTHON_DIR]   (default: build/python)
# Build the package first: ninja -C build groundsim_python.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
venv=${1:?usage: scripts/python-install.sh VENV [BUILD_PYTHON_DIR]}
src=${2:-$here/build/python}
package=$src/groundsim
if ! ls "$package"/_core.*.so >/dev/null 2>&1; then
  echo "python-install.sh: no built package in $package (ninja -C build groundsim_python)" >&2
  exit 1
fi
if [[ ! -x $venv/bin/python ]]; then
  # the interpreter the module was built for (cmake/GroundsimPython.cmake)
  python=${PYTHON:-/usr/bin/python3}
  "$python" -m venv --system-site-packages --without-pip "$venv"
fi
py=$venv/bin/python
suffix=$("$py" -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
if [[ ! -e $package/_core$suffix ]]; then
  echo "python-install.sh: $py needs _core$suffix; the build has $(basename "$package"/_core.*.so)" \
       "(configure with -DPython_EXECUTABLE=<that venv's base interpreter>)" >&2
  exit 1
fi
site=$("$py" -c 'import sysconfig; print(sysconfig.get_paths()["platlib"])')
version=$("$py" - "$package/__init__.py" <<'PY'
import re, sys
print(re.search(r'__version__ = "([^"]+)"', open(sys.argv[1]).read()).group(1))
PY
)
rm -rf "$site/groundsim" "$site"/groundsim-*.dist-info
cp -r "$package" "$site/groundsim"
find "$site/groundsim" -name __pycache__ -prune -exec rm -rf {} +
# a dist-info, so that pip lists (and can uninstall) the package
info=$site/groundsim-$version.dist-info
mkdir -p "$info"
printf 'Metadata-Version: 2.1\nName: groundsim\nVersion: %s\nSummary: vehicles on implicit ground as vectorised RL environments\nRequires-Dist: numpy\n' \
  "$version" > "$info/METADATA"
echo "groundsim python-install.sh" > "$info/INSTALLER"
(cd "$site" && find groundsim "$(basename "$info")" -type f | sed 's/$/,,/') > "$info/RECORD"
echo "groundsim $version installed into $site"
