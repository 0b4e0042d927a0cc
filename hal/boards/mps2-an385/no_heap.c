/* SPDX-License-Identifier: BSD-3-Clause */
/* No heap on the board: any malloc that sneaks in gets NULL (newlib's malloc
 * grows its arena through _sbrk, which always refuses). size-check.sh also
 * fails the build if malloc is linked at all. */
#include <errno.h>
#include <stddef.h>

void *_sbrk(ptrdiff_t increment);
void *_sbrk(ptrdiff_t increment)
{
    (void)increment;
    errno = ENOMEM;
    return (void *)-1;
}
