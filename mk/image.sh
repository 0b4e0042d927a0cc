#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# An OCI image of the wsgsim Debian package, made with Debian's own tools:
# mmdebstrap installs the .deb and its dependencies from this machine's apt
# sources into a minimal root filesystem (the suite this machine runs, the
# one the .deb was built for), umoci makes it an OCI image with wsgsim as
# its entry point, and the image layout is tarred into an OCI archive.
# usage: mk/image.sh WSGSIM.DEB OUT_DIR VERSION    writes OUT_DIR/wsgsim-oci.tar
set -eu
deb=$(realpath "$1")
out=$2
version=$3
if [ "$(id -u)" != 0 ]; then
    echo "image: mmdebstrap and umoci write files of every owner: run make image as root" >&2
    exit 1
fi
# shellcheck disable=SC1091 # the running system's own file
suite=$(. /etc/os-release && echo "$VERSION_CODENAME")
sources=/etc/apt/sources.list.d/debian.sources
[ -f "$sources" ] || sources=/etc/apt/sources.list
rm -rf "$out" && mkdir -p "$out"
echo "image: the root filesystem: $deb and its dependencies from the $suite archive (mmdebstrap)"

# --variant=apt: Debian's essential packages and apt (so that an image
# built FROM this one can add packages), no documentation but the
# copyright files and wsgsim's own. The automount hook lets dpkg in the new
# root read the .deb given by its path. The hook's "$1" (the new root) is
# mmdebstrap's to expand.
# shellcheck disable=SC2016
mmdebstrap --variant=apt --include="$deb" \
    --hook-dir=/usr/share/mmdebstrap/hooks/file-mirror-automount \
    --dpkgopt='path-exclude=/usr/share/man/*' \
    --dpkgopt='path-exclude=/usr/share/locale/*' \
    --dpkgopt='path-include=/usr/share/locale/locale.alias' \
    --dpkgopt='path-exclude=/usr/share/doc/*' \
    --dpkgopt='path-include=/usr/share/doc/*/copyright' \
    --dpkgopt='path-include=/usr/share/doc/wsgsim/*' \
    --customize-hook='mkdir -p "$1/var/lib/wsgsim"' \
    "$suite" "$out/rootfs.tar" "$sources"

# One layer holding the whole root filesystem; wsgsim on the device's
# ports (GCL 1000 TCP and UDP, binary UDP 1500, web 8080), Save into the
# volume /var/lib/wsgsim. Arguments given to the container follow these.
echo "image: the OCI image (umoci)"
layout="$out/oci"
umoci init --layout "$layout"
umoci new --image "$layout:$version"
umoci unpack --image "$layout:$version" "$out/bundle" > /dev/null
tar -xpf "$out/rootfs.tar" -C "$out/bundle/rootfs" --numeric-owner
umoci repack --image "$layout:$version" "$out/bundle"
umoci config --image "$layout:$version" \
    --config.entrypoint /usr/bin/wsgsim \
    --config.entrypoint --save-file --config.entrypoint /var/lib/wsgsim/saved.ini \
    --config.env PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    --config.exposedports 1000/tcp --config.exposedports 1000/udp \
    --config.exposedports 1500/udp --config.exposedports 8080/tcp \
    --config.volume /var/lib/wsgsim --config.workingdir / \
    --config.label org.opencontainers.image.title=wsgsim \
    --config.label org.opencontainers.image.version="$version" \
    --config.label org.opencontainers.image.licenses=BSD-3-Clause \
    --config.label org.opencontainers.image.description="virtual Weiss Robotics WSG gripper"
umoci gc --layout "$layout"
tar -cf "$out/wsgsim-oci.tar.tmp" -C "$layout" .
mv "$out/wsgsim-oci.tar.tmp" "$out/wsgsim-oci.tar"
rm -rf "$out/bundle" "$out/rootfs.tar" "$layout"
echo "image: $out/wsgsim-oci.tar (wsgsim:$version)"
