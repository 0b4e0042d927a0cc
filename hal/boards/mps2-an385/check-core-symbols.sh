#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Keeps host-only habits out of the portable core: the cross-compiled objects
# of firmware/ and hal/sim/ may reference only each other, the HAL, a few
# string and math functions and the compiler's runtime helpers. A heap, stdio
# (printf of floats), time or any OS call fails the check.
# usage: check-core-symbols.sh OBJECT...
set -eu
NM=${NM:-arm-none-eabi-nm}
allowed='^(hal_[a-z_]+|mem(set|cpy|move|cmp)|str(len|cmp|ncmp|ncpy|chr)|expf|__aeabi_[a-z0-9_]+|__gnu_[a-z0-9_]+)$'
defined=$($NM --defined-only "$@" | awk 'NF == 3 { print $3 }' | sort -u)
undefined=$($NM -u "$@" | awk 'NF == 2 { print $2 }' | sort -u)
bad=""
for sym in $undefined; do
    if ! printf '%s\n' "$defined" | grep -qx "$sym" && ! printf '%s\n' "$sym" | grep -Eq "$allowed"; then
        bad="$bad $sym"
    fi
done
if [ -n "$bad" ]; then
    echo "check-core-symbols: the core uses what a microcontroller port cannot offer:$bad" >&2
    exit 1
fi
echo "check-core-symbols: $# core objects use only the HAL, string/math and compiler helpers"
