#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# The scenario's side of a vcan guest of tests/can/run_vcan.py, the same in
# both kernels: user-mode Linux runs it as init on the host's filesystem
# (hostfs); QEMU's initramfs runs it chrooted into the host's filesystem
# (9p). Loads SocketCAN, creates vcan0, runs the command and leaves its exit
# status where the host reads it. run_vcan.py writes a copy of it with
# @WORKDIR@, @MODULES@ and @COMMAND@ filled in.
export PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
export HOME=/root LANG=C.UTF-8
WORKDIR="@WORKDIR@"
MODULES="@MODULES@"
status=1
{
    mount -t proc proc /proc
    mount -t sysfs sys /sys
    mount -t tmpfs tmpfs /dev/shm 2>/dev/null
    ip link set lo up
    for m in net/can/can net/can/can-raw drivers/net/can/dev/can-dev drivers/net/can/vcan; do
        # .ko, or compressed (.ko.xz, .ko.zst) where the kernel package does
        for ko in "$MODULES/kernel/$m".ko*; do
            insmod "$ko" || echo "guest: insmod $ko failed"
        done
    done
    if ip link add dev vcan0 type vcan && ip link set up vcan0; then
        @COMMAND@
        status=$?
    else
        echo "guest: could not create vcan0"
    fi
} >"$WORKDIR/guest.log" 2>&1
echo "$status" >"$WORKDIR/status"
sync
# As user-mode Linux's init it ends the guest; under QEMU the initramfs's
# init, which started it, powers off.
if [ "$$" = 1 ]; then
    halt -f
fi
