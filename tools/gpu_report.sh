#!/bin/sh
# One prepared GPU run: from a fresh clone, install Natura, print `natura doctor` (the context,
# the paths the scenes take on it, the shader compilers' verdict), then measure every scene's
# frame at 1920x1080 with GPU timer queries per pass, the maritime and village frames against
# the 16.7 ms budget, and the theses' tables (planet methods, clouds Table 6.1, grass methods
# at 10k-1M blades, FFT sizes): app/bench/gpu_report.py. Writes DIR/gpu-report.md (one
# Markdown page) and DIR/gpu-report.json.
#
#     tools/gpu_report.sh [--small] [--out DIR] [--wheels DIR]
#
#   --small        llvmpipe sizes (80x45 frames in two rounds, one size per table): CI runs it
#   --out DIR      where the report goes (default gpu-report/)
#   --wheels DIR   install from these wheels only (a GPU machine without a network: pip
#                  download them beside the clone first, setuptools and wheel included);
#                  also $NATURA_WHEELS
#
# An existing .venv with Natura in it is used as it is. Exit codes: 0 done, 1 the install or
# the run failed, 2 a bad option (one line says which).
set -eu
cd "$(dirname "$0")/.."

small=""
out="gpu-report"
wheels="${NATURA_WHEELS:-}"
while [ $# -gt 0 ]; do
    case "$1" in
        --small) small="--small" ;;
        --out) [ $# -ge 2 ] || { echo "gpu_report: --out needs a folder" >&2; exit 2; }
               out="$2"; shift ;;
        --wheels) [ $# -ge 2 ] || { echo "gpu_report: --wheels needs a folder" >&2; exit 2; }
                  wheels="$2"; shift ;;
        *) echo "gpu_report: unknown option '$1': allowed --small, --out DIR, --wheels DIR" >&2
           exit 2 ;;
    esac
    shift
done

PYTHON=${PYTHON:-python3}
if ! .venv/bin/python -c "import app.bench.gpu_report, moderngl" >/dev/null 2>&1; then
    echo "gpu_report: installing Natura into .venv" >&2
    "$PYTHON" -m venv .venv
    if [ -n "$wheels" ]; then
        .venv/bin/pip install -q --disable-pip-version-check --no-index --find-links "$wheels" \
            -e . || { echo "gpu_report: pip could not install from $wheels" >&2; exit 1; }
    else
        .venv/bin/pip install -q --disable-pip-version-check -e . \
            || { echo "gpu_report: pip install -e . failed" >&2; exit 1; }
    fi
fi

export PYTHONUNBUFFERED=1
# the driver report first (a failing shader is reported there and measured around)
.venv/bin/natura doctor || echo "gpu_report: natura doctor exited $? (see above)" >&2
exec .venv/bin/python -m app.bench.gpu_report $small --out "$out"
