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
echo "setup: done"
