#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fetches Debian's source package "lwip" into DEST (lwIP is a build
# dependency of the Ethernet image, not part of this repository).
# usage: fetch-lwip.sh DEST
# Adds a deb-src entry for the running Debian suite when apt has none (root
# only; otherwise it prints what to do and fails), then runs apt-get source.
set -eu
dest=$1
if [ -f "$dest/.fetched" ]; then
    exit 0
fi
# shellcheck disable=SC1091
. /etc/os-release
suite=${VERSION_CODENAME:?cannot tell the Debian suite from /etc/os-release}
srcfile=/etc/apt/sources.list.d/wsgsim-deb-src.sources

has_deb_src() {
    grep -rqsE '^(deb-src|Types:.*deb-src)' /etc/apt/sources.list /etc/apt/sources.list.d/
}

if ! has_deb_src; then
    if [ "$(id -u)" != "0" ]; then
        echo "fetch-lwip: apt has no deb-src entry; as root, write $srcfile:" >&2
        printf '  Types: deb-src\n  URIs: http://deb.debian.org/debian\n  Suites: %s\n  Components: main\n  Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
            "$suite" >&2
        echo "and run 'apt-get update', then build again" >&2
        exit 1
    fi
    echo "fetch-lwip: adding $srcfile" >&2
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: %s\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
        "$suite" > "$srcfile"
    apt-get update -qq >&2
fi
command -v dpkg-source >/dev/null || "$(dirname "$0")/../../../mk/deps.sh" dpkg-dev

tmp="$dest.tmp"
rm -rf "$tmp"
mkdir -p "$tmp"
if ! (cd "$tmp" && apt-get source -qq lwip >&2); then
    echo "fetch-lwip: 'apt-get source lwip' failed; try 'apt-get update' first" >&2
    exit 1
fi
srcdir=$(find "$tmp" -mindepth 1 -maxdepth 1 -type d -name 'lwip-*' | head -n 1)
if [ -z "$srcdir" ] || [ ! -d "$srcdir/src/core" ]; then
    echo "fetch-lwip: unexpected source layout in $tmp" >&2
    exit 1
fi
rm -rf "$dest"
mv "$srcdir" "$dest"
rm -rf "$tmp"
touch "$dest/.fetched"
echo "fetch-lwip: lwIP source in $dest" >&2
