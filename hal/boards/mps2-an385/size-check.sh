#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Reports an image's flash and static RAM use against its budget and fails
# when it is over, or when a heap allocator is linked in.
# usage: size-check.sh ELF FLASH_BUDGET_BYTES RAM_BUDGET_BYTES
#   flash = .text + .data (initial values live in flash)
#   RAM   = .data + .bss, the main stack included (see mps2-an385.ld)
set -eu
elf=$1 flash_max=$2 ram_max=$3
SIZE=${SIZE:-arm-none-eabi-size}
NM=${NM:-arm-none-eabi-nm}
# shellcheck disable=SC2046
set -- $($SIZE -B "$elf" | awk 'NR == 2 { print $1, $2, $3 }')
text=$1 data=$2 bss=$3
flash=$((text + data))
ram=$((data + bss))
status=0
verdict() { # used budget
    if [ "$1" -gt "$2" ]; then echo "OVER BUDGET"; else echo "ok"; fi
}
kib() { awk -v b="$1" 'BEGIN { printf "%.1f KiB", b / 1024 }'; }
printf '%-22s flash %7d B (%s) of %s: %s\n' "$(basename "$elf")" "$flash" "$(kib "$flash")" \
    "$(kib "$flash_max")" "$(verdict "$flash" "$flash_max")"
printf '%-22s RAM   %7d B (%s) of %s: %s  [.data %d, .bss+stack %d]\n' "" "$ram" \
    "$(kib "$ram")" "$(kib "$ram_max")" "$(verdict "$ram" "$ram_max")" "$data" "$bss"
[ "$flash" -le "$flash_max" ] || status=1
[ "$ram" -le "$ram_max" ] || status=1
heap=$($NM "$elf" | awk '$3 ~ /^(_?malloc|_malloc_r|calloc|_calloc_r|realloc|_realloc_r|_sbrk|_sbrk_r)$/ { print $3 }' | tr '\n' ' ')
if [ -n "$heap" ]; then
    echo "$(basename "$elf"): a heap allocator is linked in: $heap" >&2
    status=1
fi
exit $status
