/* SPDX-License-Identifier: BSD-3-Clause */
#include "vectors.h"

const bin_vector_t bin_vectors[] = {
    {"request 0x01 no payload (manual)", true, "AA AA AA 01 00 00 E8 10"},
    {"request 0x01 payload 12 34 (manual)", true, "AA AA AA 01 02 00 12 34 6D 66"},
    {"request 0x24 ack", true, "AA AA AA 24 03 00 61 63 6B DC B9"},
    {"request 0x07", true, "AA AA AA 07 00 00 35 4C"},
    {"reply 0x21 E_CMD_PENDING (manual)", false, "AA AA AA 21 02 00 1A 00 67 CB"},
    {"reply 0x21 E_SUCCESS (manual)", false, "AA AA AA 21 02 00 00 00 28 04"},
    {"request 0x20 dir=1", true, "AA AA AA 20 01 00 01 AE 93"},
    {"request 0x20 dir=0", true, "AA AA AA 20 01 00 00 8F 83"},
    {"reply 0x20 E_CMD_PENDING", false, "AA AA AA 20 02 00 1A 00 FC 32"},
    {"reply 0x20 E_SUCCESS (manual)", false, "AA AA AA 20 02 00 00 00 B3 FD"},
    {"request 0x21 flags 0, 50 mm, 100 mm/s", true,
     "AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C"},
    {"request 0x43 auto, periodic 20 ms", true, "AA AA AA 43 03 00 01 14 00 36 8D"},
    {"request 0x43 single read", true, "AA AA AA 43 03 00 00 00 00 B8 10"},
    {"reply 0x43 width 110.0", false, "AA AA AA 43 06 00 00 00 00 00 DC 42 5F 18"},
    {"reply 0x40 SF_REFERENCED", false, "AA AA AA 40 06 00 00 00 01 00 00 00 65 BD"},
    {"reply 0x41 HOLDING", false, "AA AA AA 41 03 00 00 00 04 5A 02"},
    {"reply 0x07 E_SUCCESS", false, "AA AA AA 07 02 00 00 00 62 0E"},
    {"reply 0x06 echo abc", false, "AA AA AA 06 05 00 00 00 61 62 63 C6 30"},
    {"request 0xB0 UMI dialect", true, "AA AA AA B0 01 00 00 69 12"},
    {"reply 0xB0 E_CMD_UNKNOWN", false, "AA AA AA B0 02 00 0E 00 A9 58"},
    {"reply 0xB0 UMI", false,
     "AA AA AA B0 13 00 00 00 01 00 00 DC 42 00 00 00 00 00 00 00 00 00 00 00 00 D8 6A"},
    {"request 0xB1 UMI", true,
     "AA AA AA B1 19 00 00 00 00 48 42 00 00 00 00 00 00 70 41 6F 12 83 3A 00 00 A0 42 00 00 A0 "
     "42 0B ED"},
    {"request 0xB0 wsg50-ros-pkg dialect", true,
     "AA AA AA B0 09 00 00 00 00 00 00 00 00 00 00 E5 50"},
    {"reply 0xB0 wsg50-ros-pkg", false,
     "AA AA AA B0 17 00 00 00 01 00 00 DC 42 00 00 00 00 00 00 00 00 00 00 C0 7F 00 00 C0 7F BE "
     "C7"},
    {"reply 0x90 E_CMD_UNKNOWN (manual)", false, "AA AA AA 90 02 00 0E 00 FD 02"},
    {"reply 0x30 150.0 mm/s2 (manual)", false, "AA AA AA 30 06 00 00 00 00 00 16 43 DC CB"},
    {"request 0x40 auto 15880 ms (S10)", true, "AA AA AA 40 03 00 01 08 3E 43 4C"},
};

const size_t bin_vector_count = sizeof(bin_vectors) / sizeof(bin_vectors[0]);
