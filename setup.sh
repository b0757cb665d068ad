#!/bin/sh
# Set up Natura on a fresh Debian (or Ubuntu) machine, from the repository root:
#
#     ./setup.sh && .venv/bin/natura
#
# 1. the system packages: Python's venv module, Mesa's EGL and its software (llvmpipe) driver,
#    Xvfb + xdotool for the window tests, and Chromium for the handout's test (natura report's
#    page is opened in headless Chromium). As root they are installed with apt-get; as
#    another user the script stops with one line naming what is missing and the command to run.
# 2. a virtual environment in .venv with Natura and its test tools (pip install -e '.[test]').
#
#     ./setup.sh --check    only say what is missing (exit 1 if anything is), install nothing
#
# Exit codes: 0 ready, 1 something is missing or an install failed (one line says what).
set -eu
cd "$(dirname "$0")"

PYTHON=${PYTHON:-python3}
# Needed to run Natura; wanted for its window tests (xvfb, xdotool) and the handout's test
# (chromium: natura report's page opened headless); those tests skip with that reason without.
NEEDED="python3-venv libegl1 libgl1-mesa-dri"
WANTED="xvfb xdotool chromium"

say() { echo "setup: $*" >&2; }

# A package is present when dpkg says it is installed; without dpkg (not Debian), by what it
# provides.
have_package() {
    if command -v dpkg-query >/dev/null 2>&1; then
        dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"
        return
    fi
    case "$1" in
        python3-venv) "$PYTHON" -c "import ensurepip, venv" >/dev/null 2>&1 ;;
        libegl1) ldconfig -p 2>/dev/null | grep -q "libEGL.so.1" ;;
        libgl1-mesa-dri) ls /usr/lib/*/dri/swrast_dri.so /usr/lib*/dri/swrast_dri.so \
                             >/dev/null 2>&1 ;;
        xvfb) command -v Xvfb >/dev/null 2>&1 ;;
        xdotool) command -v xdotool >/dev/null 2>&1 ;;
        chromium) command -v chromium >/dev/null 2>&1 ;;
        *) return 1 ;;
    esac
}

missing_of() {
    out=""
    for p in $1; do have_package "$p" || out="$out $p"; done
    echo "${out# }"
}

if ! command -v "$PYTHON" >/dev/null 2>&1; then
    say "no $PYTHON on PATH: allowed Python 3.11 or newer (Debian: apt-get install python3)"
    exit 1
fi
if ! "$PYTHON" -c "import sys; sys.exit(sys.version_info < (3, 11))"; then
    say "$("$PYTHON" -V 2>&1) is too old: allowed Python 3.11 or newer (set PYTHON=python3.11)"
    exit 1
fi

missing=$(missing_of "$NEEDED")
optional=$(missing_of "$WANTED")
if [ "${1:-}" = "--check" ]; then
    [ -z "$missing" ] && [ -z "$optional" ] && { say "nothing missing"; exit 0; }
    say "missing: ${missing:-none}; for the window and handout tests: ${optional:-none}"
    [ -z "$missing" ]
    exit
fi
if [ -n "${1:-}" ]; then
    say "unknown option '$1': allowed --check or nothing"
    exit 1
fi

if [ -n "$missing$optional" ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        say "installing $missing $optional with apt-get"
        export DEBIAN_FRONTEND=noninteractive
        # shellcheck disable=SC2086 # the lists are words
        if ! { apt-get update -qq && apt-get install -y -qq $missing $optional >/dev/null; }; then
            # the window tests' packages are optional: try the needed ones alone
            [ -z "$missing" ] || apt-get install -y -qq $missing >/dev/null || {
                say "apt-get could not install $missing: install them, then run ./setup.sh again"
                exit 1
            }
            [ -z "$optional" ] || say "could not install $optional: the tests that need" \
                "them will skip"
        fi
    elif [ -n "$missing" ]; then
        say "missing Debian packages $missing: run 'sudo apt-get install $missing $optional'" \
            "then ./setup.sh again"
        exit 1
    else
        say "the window and handout tests will skip without $optional" \
            "('sudo apt-get install $optional')"
    fi
fi

"$PYTHON" -m venv .venv
.venv/bin/pip install -q --disable-pip-version-check -e '.[test]'
say "ready: .venv/bin/natura opens the window; .venv/bin/python -m pytest runs the tests"
