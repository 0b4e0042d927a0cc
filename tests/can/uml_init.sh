#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Init of the user-mode Linux guest of tests/can/run_vcan.py: the host's
# filesystem is the root (hostfs). Loads SocketCAN, creates vcan0, runs the
# scenario and leaves its exit status where the host reads it.
# run_vcan.py writes a copy of it with @WORKDIR@, @MODULES@ and @COMMAND@
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
    for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko \
             drivers/net/can/vcan.ko; do
        insmod "$MODULES/kernel/$m" || echo "uml: insmod $m failed"
    done
    if ip link add dev vcan0 type vcan && ip link set up vcan0; then
        @COMMAND@
        status=$?
    else
        echo "uml: could not create vcan0"
    fi
} >"$WORKDIR/guest.log" 2>&1
echo "$status" >"$WORKDIR/status"
sync
halt -f
