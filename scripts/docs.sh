#!/usr/bin/env bash
# Build the documentation site into docs/_build/html, from the installed polhode (install it
# with its `docs` extra first: pip install '.[docs]'). Any warning is an error (-W). The
# gallery's examples run during the build; the API pages are generated from the docstrings.
set -euo pipefail
cd "$(dirname "$0")/.."
export MPLBACKEND=Agg
python -m sphinx -W --keep-going -q -b html docs docs/_build/html "$@"
echo "docs: docs/_build/html/index.html"
