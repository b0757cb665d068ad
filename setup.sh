#!/bin/sh
# Set up Natura from the repository root:
#
#     ./setup.sh && .venv/bin/natura
#
# On Debian or Ubuntu:
# 1. the system packages: Python's venv module, Mesa's EGL and its software (llvmpipe) driver,
#    Xvfb + xdotool for the window tests, Chromium for the handout's test (natura report's page
#    is opened in headless Chromium) and glslang-tools (the Khronos reference compiler, for
#    `natura shaders check --strict`). As root they are installed with apt-get; as another user
#    the script stops with one line naming what is missing and the command to run.
# 2. a virtual environment in .venv with Natura and its test tools (pip install -e '.[test]'),
#    and Natura's sources compiled to bytecode.
#
# Elsewhere it installs no system package and says so in one line:
# - macOS and Windows (Git Bash, MSYS2, Cygwin): the OS's own OpenGL is used (CGL, WGL), so only
#   step 2 runs; the window and handout tests skip without Xvfb, xdotool and Chromium.
# - another Linux (no apt-get): it names what is missing — Mesa's EGL and DRI drivers (or a
#   display, for GLX) — with the usual package names, and stops only if Python's venv is missing.
#
#     ./setup.sh --check    only say what is missing (exit 1 if anything needed is), install nothing
#
# Exit codes: 0 ready, 1 something is missing or an install failed (one line says what).
set -eu
cd "$(dirname "$0")"

PYTHON=${PYTHON:-python3}
# Needed to run Natura; wanted for its window tests (xvfb, xdotool) and the handout's test
# (chromium: natura report's page opened headless); those tests skip with that reason without.
NEEDED="python3-venv libegl1 libgl1-mesa-dri"
WANTED="xvfb xdotool chromium glslang-tools"
case "$(uname -s 2>/dev/null)" in
    Darwin) SYSTEM=macOS ;;
    MINGW* | MSYS* | CYGWIN*) SYSTEM=Windows ;;
    *) SYSTEM=Linux ;;
esac

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
        chromium) command -v chromium >/dev/null 2>&1 || command -v chromium-browser \
                      >/dev/null 2>&1 ;;
        glslang-tools) command -v glslangValidator >/dev/null 2>&1 ;;
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

if [ "$SYSTEM" != Linux ]; then
    # the OS's own OpenGL (CGL, WGL): only Python's venv is needed from the system
    NEEDED="python3-venv"
    WANTED="xvfb xdotool chromium glslang-tools"
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

if [ "$SYSTEM" != Linux ] || ! command -v apt-get >/dev/null 2>&1; then
    # no apt-get: nothing is installed from the system; what is missing is named
    if ! have_package python3-venv; then
        say "no apt-get here ($SYSTEM): Python's venv module does not work for $PYTHON:" \
            "install Python 3.11+ with it (python.org, Homebrew, the Microsoft Store; Fedora:" \
            "sudo dnf install python3), then ./setup.sh again"
        exit 1
    fi
    if [ "$SYSTEM" != Linux ]; then
        say "$SYSTEM: nothing to install from the system (Natura draws with its own OpenGL);" \
            "the tests that need ${optional:-nothing more} skip; making .venv"
    elif [ -n "$missing$optional" ]; then
        say "no apt-get on this system, nothing installed: headless rendering wants Mesa's" \
            "EGL and DRI drivers (${missing:-present}; Fedora: sudo dnf install mesa-libEGL" \
            "mesa-dri-drivers; Arch: sudo pacman -S mesa; GLX works without them on a display);" \
            "the tests that need ${optional:-nothing more} skip; making .venv"
    fi
elif [ -n "$missing$optional" ]; then
    if [ "$(id -u)" = 0 ]; then
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
bin=.venv/bin
[ -d "$bin" ] || bin=.venv/Scripts  # Windows
"$bin/pip" install -q --disable-pip-version-check -e '.[test]'
# An editable install leaves Natura's own modules uncompiled (pip compiles what it copies, not
# a source tree), and with PYTHONDONTWRITEBYTECODE set Python never caches them: every natura
# command then compiles the whole app package again (0.44 s against 0.20 s for a one-line
# error, two cores). So the sources are compiled once here, as pip would compile an install.
"$PYTHON" -m compileall -q app >/dev/null ||
    say "could not compile app/ to bytecode: natura still runs, compiling it each time"
say "ready: $bin/natura opens the window; $bin/python -m pytest runs the tests"
