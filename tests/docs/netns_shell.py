# SPDX-License-Identifier: BSD-3-Clause
"""Run under `unshare -rn`: brings the new namespace's loopback up, then
becomes the documents' shell (bash reading commands on stdin)."""
import fcntl
import os
import socket
import struct

SIOCGIFFLAGS = 0x8913
SIOCSIFFLAGS = 0x8914
IFF_UP = 0x1

with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
    request = struct.pack("16sH14x", b"lo", 0)
    flags = struct.unpack("16sH14x", fcntl.ioctl(s, SIOCGIFFLAGS, request))[1]
    fcntl.ioctl(s, SIOCSIFFLAGS, struct.pack("16sH14x", b"lo", flags | IFF_UP))
os.execvp("bash", ["bash", "--norc", "--noprofile", "-m"])
