#!/bin/busybox sh
# SPDX-License-Identifier: BSD-3-Clause
# shellcheck shell=dash
# /init of the initramfs that tests/can/run_vcan.py boots Debian's kernel
# with in QEMU: busybox and the modules of virtio's 9p transport. Mounts the
# host's filesystem (9p tag hostroot, read-only) as the root the scenario
# sees, with tmpfs on /tmp and /run, the checkout (9p tag checkout,
# read-only: a checkout under /tmp would be hidden by the tmpfs) and the
# work dir (9p tag work, writable) at their host paths, runs guest_init.sh
# there and powers off. run_vcan.py writes a copy of it with @WORKDIR@ and
# @CHECKOUT@ filled in.
/bin/busybox --install -s /bin
export PATH=/bin
WORKDIR="@WORKDIR@"
CHECKOUT="@CHECKOUT@"
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
while read -r module; do
    insmod "/modules/$module" || echo "qemu-init: insmod $module failed"
done </modules/order
opts=trans=virtio,version=9p2000.L,msize=262144
if mount -t 9p -o "$opts,ro" hostroot /newroot; then
    mount -t devtmpfs dev /newroot/dev
    mount -t tmpfs tmpfs /newroot/tmp
    mount -t tmpfs tmpfs /newroot/run
    mkdir -p "/newroot$CHECKOUT" "/newroot$WORKDIR"
    if ! mount -t 9p -o "$opts,ro" checkout "/newroot$CHECKOUT"; then
        echo "qemu-init: could not mount the checkout"
    elif mount -t 9p -o "$opts" work "/newroot$WORKDIR"; then
        chroot /newroot /bin/sh "$WORKDIR/init.sh"
    else
        echo "qemu-init: could not mount the work dir"
    fi
else
    echo "qemu-init: could not mount the host's filesystem"
fi
sync
poweroff -f
