#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs the build dependencies (Debian bookworm), obtains the Unity test framework
# offline, from Debian's ntpsec source package, and builds LCM's Python module (`lcm`) from
# Debian's lcm source package with patches/lcm-python-1.3.1-py311.patch for /usr/bin/python3
# (Debian ships no Python LCM module). Idempotent: a second run only checks and does not
# touch the network.
#
# Run it directly, or `source` it (scripts/test.sh, scripts/demo.sh) to also get
# CDPR_UNITY_ROOT exported, which cmake/Unity.cmake picks up, and CDPR_LCM_PYTHON (the folder
# holding the lcm module: put it on PYTHONPATH, docs/realtime.md "Python"). Sourcing also enables
# `set -euo pipefail` in the calling shell.
set -euo pipefail

cdpr_packages=(
    cmake ninja-build build-essential pkg-config
    liblcm-dev liblcm-bin libglib2.0-dev libgsl-dev
    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
    cppcheck clang clang-tidy libclang-rt-14-dev valgrind gcovr
    gnuplot-nox libcyaml-dev libyaml-dev dpkg-dev xz-utils python3-matplotlib iproute2
    python3-dev python3-setuptools python3-distutils patch
    python3-numpy python3-scipy python3-ruamel.yaml
    slurm-wlm munge
    liblcm-java libjchart2d-java default-jdk-headless
    liblapack-dev
    # OpenBLAS (serial: no threads of its own next to ctest's) takes over liblapack.so.3 and
    # libblas.so.3 through Debian's alternatives: the design check's 21 cases run 5x faster
    # (1.2 s instead of 6.7 s each at 703 states; docs/validation.md §8).
    libopenblas0-serial
)

# Pinned: the orig tarball is identical for every Debian revision of ntpsec 1.2.2+dfsg1.
cdpr_ntpsec_tarball=ntpsec_1.2.2+dfsg1.orig.tar.xz
cdpr_ntpsec_sha256=53e527e3d04d551d41af2d359c2715c2de5f5bfa2a695d4ec1a811b3e9137f63

# Pinned: the orig tarball of lcm 1.3.1+repack1 (every Debian revision of it shares it).
cdpr_lcm_tarball=lcm_1.3.1+repack1.orig.tar.gz
cdpr_lcm_sha256=abf293e54aff3d073cb4f9d4d5a261eab0e5ffea02e13fd601715c11612b85e8
cdpr_lcm_patch=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/patches/lcm-python-1.3.1-py311.patch

cdpr_sudo=()
if [[ $(id -u) -ne 0 ]]; then
    cdpr_sudo=(sudo)
fi

cdpr_install_packages() {
    local missing=() p
    for p in "${cdpr_packages[@]}"; do
        # "ii" = wanted and installed; anything else (absent, half-configured) is missing.
        if [[ $(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null) != ii* ]]; then
            missing+=("$p")
        fi
    done
    if [[ ${#missing[@]} -eq 0 ]]; then
        return 0
    fi
    echo "setup: installing ${missing[*]}"
    "${cdpr_sudo[@]}" apt-get update
    "${cdpr_sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "${cdpr_packages[@]}"
}

# `apt-get source` needs a deb-src entry; Debian images ship only `deb` ones. Add the same
# archive(s) as source entries, in deb822 format.
cdpr_ensure_deb_src() {
    local list=/etc/apt/sources.list.d/cdpr-deb-src.sources
    # $(CREATED_BY) is apt's format field, not shell. grep without -q reads all input, so
    # apt-get never sees SIGPIPE (which pipefail would report as a failure).
    # shellcheck disable=SC2016
    if apt-get indextargets --format '$(CREATED_BY)' | grep -x Sources >/dev/null; then
        return 0
    fi
    echo "setup: adding deb-src entries in $list"
    if [[ -f /etc/apt/sources.list.d/debian.sources ]]; then
        sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources |
            "${cdpr_sudo[@]}" tee "$list" >/dev/null
    else
        "${cdpr_sudo[@]}" tee "$list" >/dev/null <<'SOURCES'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
    fi
}

cdpr_fetch_unity() {
    local cache=$1
    local unity="$cache/unity" tarball="$cache/src/$cdpr_ntpsec_tarball"
    if [[ -f $unity/unity.c ]]; then
        return 0
    fi
    mkdir -p "$cache/src"
    if [[ ! -f $tarball ]]; then
        cdpr_ensure_deb_src
        "${cdpr_sudo[@]}" apt-get update
        # As root apt warns that the download is unsandboxed; harmless here.
        (cd "$cache/src" && apt-get source --download-only ntpsec)
    fi
    echo "$cdpr_ntpsec_sha256  $tarball" | sha256sum --check --quiet -
    # Unity (MIT) lives in ntpsec-<version>/tests/unity/: extract only that, flattened.
    # Unpack next to the final folder and rename, so an interrupted run leaves no half copy.
    rm -rf "$unity.tmp"
    mkdir -p "$unity.tmp"
    tar -xJf "$tarball" -C "$unity.tmp" --no-same-owner --strip-components=3 --wildcards '*/tests/unity/*'
    rm -rf "$unity"
    mv "$unity.tmp" "$unity"
    echo "setup: Unity extracted to $unity"
}

# LCM's Python module into $cache/lcm-python/lcm/ (upstream's lcm/__init__.py and the
# extension _lcm, linked against Debian's liblcm). Rebuilt only when the patch changed (its
# hash is the stamp) or the module does not import.
cdpr_build_lcm_python() {
    local cache=$1
    local dest="$cache/lcm-python" tarball="$cache/src/$cdpr_lcm_tarball" stamp
    stamp=$(sha256sum "$cdpr_lcm_patch" | cut -d' ' -f1)
    if [[ -f $dest/.stamp && $(cat "$dest/.stamp") == "$stamp" ]] &&
        PYTHONPATH="$dest" /usr/bin/python3 -c 'import lcm' 2>/dev/null; then
        return 0
    fi
    mkdir -p "$cache/src"
    if [[ ! -f $tarball ]]; then
        cdpr_ensure_deb_src
        "${cdpr_sudo[@]}" apt-get update
        # Only the orig tarball is used (the pinned hash below decides): a failure to fetch the
        # Debian diff alone does not matter.
        (cd "$cache/src" && apt-get source --download-only lcm) ||
            echo "setup: apt-get source lcm reported an error; checking the orig tarball"
    fi
    echo "$cdpr_lcm_sha256  $tarball" | sha256sum --check --quiet -
    local work
    work=$(mktemp -d)
    tar -xzf "$tarball" -C "$work" --no-same-owner
    (cd "$work/lcm-1.3.1" && patch -p1 --forward --quiet < "$cdpr_lcm_patch")
    rm -rf "$dest.tmp"
    (cd "$work/lcm-1.3.1/lcm-python" &&
        /usr/bin/python3 setup.py --quiet build_ext --build-temp "$work/build" \
            --build-lib "$dest.tmp")
    cp "$work/lcm-1.3.1/lcm-python/lcm/__init__.py" "$dest.tmp/lcm/"
    cp "$work/lcm-1.3.1/lcm-python/COPYING" "$dest.tmp/lcm/COPYING"
    echo "$stamp" > "$dest.tmp/.stamp"
    rm -rf "$work" "$dest"
    mv "$dest.tmp" "$dest"
    PYTHONPATH="$dest" /usr/bin/python3 -c 'import lcm'
    echo "setup: LCM's Python module built in $dest (PYTHONPATH=$dest)"
}

cdpr_install_packages
CDPR_CACHE=${CDPR_CACHE:-$HOME/.cache/cdpr}
cdpr_fetch_unity "$CDPR_CACHE"
export CDPR_UNITY_ROOT="$CDPR_CACHE/unity"
cdpr_build_lcm_python "$CDPR_CACHE"
export CDPR_LCM_PYTHON="$CDPR_CACHE/lcm-python"

if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
    echo "setup: done. For a manual cmake run: export CDPR_UNITY_ROOT=$CDPR_UNITY_ROOT"
    echo "setup: Python: export PYTHONPATH=$CDPR_LCM_PYTHON:<build>/lcmtypes/python"
fi
