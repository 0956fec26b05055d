#!/usr/bin/env bash
# Sets up a fresh machine for the project: Python packages from PyPI (pinned in
# requirements.txt), this package in editable mode, a Jupyter kernel for the notebooks, and
# TeX Live from Debian's packages for the report. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore -r requirements.txt
python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore --no-deps -e .
python3 -m ipykernel install --user --name python3 >/dev/null

need_tex=0
for cmd in latexmk pdflatex pdftoppm; do command -v "$cmd" >/dev/null || need_tex=1; done
if [ "$need_tex" = 1 ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    latexmk texlive-latex-base texlive-latex-recommended texlive-latex-extra \
    texlive-fonts-recommended poppler-utils >/dev/null
fi
# Siconos's Moreau-Jean time-stepping, a baseline of the work-precision study (issue 6).
# Debian packages its Python module for Debian's own /usr/bin/python3 (~64 MB download,
# ~475 MB installed, ~30 s); the study runs it there in a subprocess. Optional: where apt or
# the package is missing the study says plainly that Siconos was not available.
if command -v apt-get >/dev/null && [ -x /usr/bin/python3 ] && ! /usr/bin/python3 -c "import siconos.kernel" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  if $SUDO apt-get install -y -qq --no-install-recommends python3-siconos >/dev/null 2>&1 \
     || { $SUDO apt-get update -qq && $SUDO apt-get install -y -qq --no-install-recommends python3-siconos >/dev/null 2>&1; }; then
    echo "setup: Siconos installed for /usr/bin/python3"
  else
    echo "setup: python3-siconos not installed (optional; the work-precision study will say so)"
  fi
fi
echo "setup: done"
