#!/usr/bin/env bash
# Installs the system HDF5 library (headers, libraries, pkg-config file) that `cargo build --features hdf5` links
# against, on a Debian or Ubuntu machine, if it is missing. Idempotent: a machine that has both libhdf5-dev and
# pkg-config installed is left alone. Runs as root, or through sudo when that is available.
#
#   bash ci/install-hdf5.sh
set -euo pipefail

packages=(libhdf5-dev pkg-config)

missing=()
for p in "${packages[@]}"; do
    if dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$'; then
        echo "install-hdf5: $p is installed ($(dpkg-query -W -f='${Version}' "$p"))"
    else
        missing+=("$p")
    fi
done

if ((${#missing[@]} > 0)); then
    if ! command -v apt-get >/dev/null; then
        echo "install-hdf5: apt-get not found; install ${missing[*]} (HDF5 ≥ 1.10 with pkg-config) by hand" >&2
        exit 1
    fi
    sudo=()
    if [[ $(id -u) -ne 0 ]]; then
        if command -v sudo >/dev/null; then
            sudo=(sudo)
        else
            echo "install-hdf5: not root and no sudo; cannot install ${missing[*]}" >&2
            exit 1
        fi
    fi
    echo "install-hdf5: installing ${missing[*]}"
    echo "+ apt-get update"
    "${sudo[@]}" apt-get update
    echo "+ apt-get install -y ${missing[*]}"
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
fi

# What the hdf5-metno-sys build script will find.
if version=$(pkg-config --modversion hdf5 2>/dev/null); then
    echo "install-hdf5: pkg-config finds hdf5 $version"
else
    echo "install-hdf5: pkg-config does not find hdf5 (Debian names it hdf5-serial: $(pkg-config --modversion hdf5-serial 2>/dev/null || echo none))"
fi
