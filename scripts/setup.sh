#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs the build dependencies (Debian bookworm) and obtains the Unity test framework
# offline, from Debian's ntpsec source package. Idempotent: a second run only checks and
# does not touch the network.
#
# Run it directly, or `source` it (scripts/test.sh, scripts/demo.sh) to also get
# CDPR_UNITY_ROOT exported, which cmake/Unity.cmake picks up. Sourcing also enables
# `set -euo pipefail` in the calling shell.
set -euo pipefail

cdpr_packages=(
    cmake ninja-build build-essential pkg-config
    liblcm-dev liblcm-bin libglib2.0-dev libgsl-dev
    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
    cppcheck clang clang-tidy libclang-rt-14-dev valgrind gcovr
    gnuplot-nox libcyaml-dev libyaml-dev dpkg-dev xz-utils python3-matplotlib iproute2
)

# Pinned: the orig tarball is identical for every Debian revision of ntpsec 1.2.2+dfsg1.
cdpr_ntpsec_tarball=ntpsec_1.2.2+dfsg1.orig.tar.xz
cdpr_ntpsec_sha256=53e527e3d04d551d41af2d359c2715c2de5f5bfa2a695d4ec1a811b3e9137f63

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

cdpr_install_packages
CDPR_CACHE=${CDPR_CACHE:-$HOME/.cache/cdpr}
cdpr_fetch_unity "$CDPR_CACHE"
export CDPR_UNITY_ROOT="$CDPR_CACHE/unity"

if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
    echo "setup: done. For a manual cmake run: export CDPR_UNITY_ROOT=$CDPR_UNITY_ROOT"
fi
