#!/usr/bin/env bash
# Runs pytest on tests/python/real/ with the venv of the real libraries
# (scripts/setup-python.sh, python/requirements.txt), the package from the
# build tree (PYTHONPATH). Exit 77 (SKIP, with the reason) when that venv or
# one of the libraries a test file needs is missing.
#   run.sh VENV TEST_FILE [pytest args...]
set -euo pipefail
venv=$1 file=$2
shift 2
py=$venv/bin/python
if [[ ! -x $py ]]; then
  echo "SKIP: no venv of the real libraries at $venv (scripts/setup-python.sh makes it)"
  exit 77
fi
# the modules the file names in its NEEDS line
needs=$(sed -n 's/^NEEDS = (\(.*\))$/\1/p' "$file" | tr -d '",')
for module in $needs; do
  if ! "$py" -c "import $module" 2>/dev/null; then
    echo "SKIP: $module is not importable in $venv (scripts/setup-python.sh installs python/requirements.txt)"
    exit 77
  fi
done
exec "$py" -m pytest -q -p no:cacheprovider -rs "$file" "$@"
